// demcal command line. Thin on purpose: the logic lives in demcal_cli_lib so
// tests and other front ends reach it without a process boundary.

#include "cli/calibrate_command.hpp"
#include "cli/diagnose_command.hpp"
#include "cli/directory_option.hpp"
#include "cli/doe_command.hpp"
#include "cli/export_command.hpp"
#include "cli/fit_command.hpp"
#include "cli/simulate_command.hpp"
#include "config/schema.hpp"
#include "config/simulation_config.hpp"
#include "study/mpi_session.hpp"
#include "study/run_record.hpp"

#include <unistd.h>
#include <CLI/CLI.hpp>

#include <cstddef>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

namespace {

// Runs a subcommand's body: bad input (ConfigError) exits 2, any other error
// 1, each with one "demcal: [who]error: ..." line; otherwise the body's code.
template <typename Body>
int guarded(const std::string& who, Body&& body) {
  try {
    return body();
  } catch (const demcal::config::ConfigError& e) {
    std::cerr << "demcal: " << who << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "demcal: " << who << "error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = demcal::cli;
  namespace study = demcal::study;
  namespace reader = demcal::config::reader;
  CLI::App app{"demcal: discrete element simulations and their calibration"};
  app.set_version_flag("--version", "demcal " + study::engine_version());
  app.require_subcommand(1);

  cli::SimulateOptions sim_opts;
  std::string config;
  std::string output;
  std::string apparatus;
  int threads = 0;
  CLI::App* simulate_cmd = app.add_subcommand(
      "simulate", "Run one simulation, or one apparatus of a study, from a TOML config");
  simulate_cmd
      ->add_option("config", config,
                   "The simulation config, or a study config with [apparatus.*] tables (TOML)")
      ->required();
  simulate_cmd
      ->add_option("--set", sim_opts.overrides,
                   "Override a config value, e.g. --set interaction[0].sliding_friction=0.4; "
                   "in a study, mu_s=0.52 and mu_r=0.3 stand for "
                   "interaction.particle_particle.sliding_friction and .rolling_friction "
                   "(repeatable)")
      ->allow_extra_args(false);
  simulate_cmd->add_option("--apparatus", apparatus,
                           "Study configs: the apparatus to run (needed when the study defines "
                           "several)");
  simulate_cmd->add_option("--output", output, "Output directory (replaces output.directory)")
      ->check(cli::directory_to_write());
  simulate_cmd
      ->add_option("--threads", threads, "Threads (replaces simulation.threads or study.threads)")
      ->check(CLI::Range(1, 4096));
  simulate_cmd->add_flag("--overwrite", sim_opts.overwrite,
                         "Replace the run.json of an earlier run in the output directory");
  simulate_cmd->add_flag("--quiet,-q", sim_opts.quiet,
                         "No progress or summary; only the output paths and errors");

  cli::DoeOptions doe_opts;
  std::string doe_shard;
  std::size_t doe_stop_after = 0;
  CLI::App* doe_cmd = app.add_subcommand(
      "doe",
      "Run a study's design of experiments (its [design] table): every design point x "
      "replicate x apparatus into the run store <output>/<study>/runs/<hash>.json, reusing "
      "runs already there, then write <output>/<study>/doe.csv and doe.json. Under mpirun the "
      "runs are split over the ranks");
  doe_cmd->add_option("study", doe_opts.study, "The study config, with a [design] table (TOML)")
      ->required();
  doe_cmd->add_option("--jobs,-j", doe_opts.jobs, "Runs at a time in this process (worker threads)")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  doe_cmd->add_option("--apparatus", doe_opts.apparatus,
                      "Run only this apparatus of the study (repeatable; default: all)");
  doe_cmd->add_option("--shard", doe_shard,
                      "i/N: run only the runs numbered i modulo N (no table; merge the stores "
                      "and --collect)");
  doe_cmd
      ->add_option("--output", doe_opts.output_dir,
                   "Directory holding <study name>/runs and the tables")
      ->check(cli::directory_to_write())
      ->capture_default_str();
  const char* run_store_help =
      "Keep the run records in DIR instead of <output>/<study>/runs: one store shared by several "
      "studies "
      "of the same apparatus (runs are named by the hash of their inputs, which leaves [study] "
      "out)";
  doe_cmd->add_option("--run-store", doe_opts.run_store, run_store_help)
      ->check(cli::directory_to_write());
  doe_cmd
      ->add_option("--threads-per-run", doe_opts.threads_per_run,
                   "OpenMP threads of each run (part of each run's key)")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  doe_cmd
      ->add_option("--set", doe_opts.overrides,
                   "Override a study value before the design values, as for simulate "
                   "(repeatable)")
      ->allow_extra_args(false);
  doe_cmd->add_flag("--quiet,-q", doe_opts.quiet, "No progress bar or line per run");
  CLI::Option* dry = doe_cmd->add_flag("--dry-run", doe_opts.dry_run,
                                       "List the runs and which are stored; run and write nothing");
  CLI::Option* collect = doe_cmd->add_flag("--collect", doe_opts.collect,
                                           "Run nothing; write the tables from the store as it is");
  collect->excludes(dry);
  doe_cmd->add_flag("--retry-failed", doe_opts.retry_failed, "Run again the runs stored as failed");
  // For testing resumption: stop as if killed after storing N runs.
  doe_cmd->add_option("--stop-after", doe_stop_after)->group("")->check(CLI::Range(1, 1 << 30));

  cli::FitOptions fit_opts;
  std::string fit_doe;
  const auto add_fit_options = [&](CLI::App* cmd) {
    cmd->add_option("study", fit_opts.study,
                    "The study config, with [design] and [surrogate] tables (TOML)")
        ->required();
    cmd->add_option("--output", fit_opts.output_dir, "Directory holding <study name>/ (as for doe)")
        ->check(cli::directory_to_write())
        ->capture_default_str();
    cmd->add_option("--doe", fit_doe,
                    "The design table to fit (default: <output>/<study name>/doe.csv), e.g. a "
                    "checked-in doe.csv");
    cmd->add_option("--set", fit_opts.overrides, "Override a study value (repeatable)")
        ->allow_extra_args(false);
    cmd->add_flag("--quiet,-q", fit_opts.quiet, "Only the paths of what was written, and warnings");
  };
  CLI::App* fit_cmd = app.add_subcommand(
      "fit",
      "Fit the study's surrogates ([surrogate] table) to its design table and save them as "
      "<output>/<study>/surrogates/<apparatus>.<observable>.json");
  add_fit_options(fit_cmd);
  CLI::App* inspect_cmd = app.add_subcommand(
      "inspect",
      "Write the surrogate inspection report <output>/<study>/reports/inspection/index.html "
      "(maps, leave-one-out parity and residuals, coefficients, Sobol indices)");
  add_fit_options(inspect_cmd);
  CLI::App* calibrate_cmd = app.add_subcommand(
      "calibrate",
      "Solve the inverse problem: the parameters that reproduce the study's recordings "
      "([calibration] "
      "table), with confidence regions, on all recordings and on AoR alone; writes "
      "<output>/<study>/reports/calibration/index.html");
  add_fit_options(calibrate_cmd);

  cli::StudyOptions study_opts;
  CLI::App* study_cmd = app.add_subcommand("study",
                                           "The whole pipeline: doe, fit, inspect, calibrate; "
                                           "resumable, each stage skipped when its inputs "
                                           "have not changed");
  study_cmd->add_option("study", study_opts.doe.study, "The study config (TOML)")->required();
  study_cmd->add_option("--jobs,-j", study_opts.doe.jobs, "Runs at a time")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  study_cmd->add_option("--output", study_opts.doe.output_dir, "Directory holding <study name>/")
      ->check(cli::directory_to_write())
      ->capture_default_str();
  study_cmd->add_option("--set", study_opts.doe.overrides, "Override a study value (repeatable)")
      ->allow_extra_args(false);
  study_cmd->add_option("--run-store", study_opts.doe.run_store, run_store_help)
      ->check(cli::directory_to_write());
  study_cmd->add_flag("--quiet,-q", study_opts.doe.quiet, "No line per run");
  study_cmd->add_flag("--force", study_opts.force,
                      "Refit, re-inspect and recalibrate even if nothing changed");

  cli::DiagnoseOptions diag_opts;
  CLI::App* diagnose_cmd =
      app.add_subcommand("diagnose",
                         "When the base model does not reproduce the recordings: locate the "
                         "mismatch, name the physics left "
                         "out ([diagnosis] table), model it and compare; writes "
                         "<output>/<study>/reports/diagnosis/index.html");
  diagnose_cmd
      ->add_option("study", diag_opts.study,
                   "The study config, with [calibration] and [diagnosis] (TOML)")
      ->required();
  diagnose_cmd->add_option("--jobs,-j", diag_opts.jobs, "Runs at a time")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  diagnose_cmd->add_option("--output", diag_opts.output_dir, "Directory holding <study name>/")
      ->check(cli::directory_to_write())
      ->capture_default_str();
  diagnose_cmd->add_option("--set", diag_opts.overrides, "Override a study value (repeatable)")
      ->allow_extra_args(false);
  diagnose_cmd->add_option(
      "--run-store", diag_opts.run_store,
      std::string(run_store_help) + "; the diagnosis' probes and extended designs use it too");
  diagnose_cmd->add_flag("--quiet,-q", diag_opts.quiet, "No line per run");
  cli::ExportOptions export_opts;
  CLI::App* export_cmd = cli::add_export_command(app, export_opts);

  std::string schema_name;
  CLI::App* schema_cmd = app.add_subcommand(
      "schema",
      "Print every registered key (apparatus, walls, regions, inserters, size distributions, "
      "surrogates, contact parts, diagnosis candidates) with its unit, default and range, "
      "and the observables");
  schema_cmd->add_option("name", schema_name,
                         "Only this entry: a model (sandglass, plane, log_normal, liquid_bridge), "
                         "a family (apparatus, wall, size, surrogate, contact.adhesion), "
                         "contact, candidates, observables");

  // A misspelt subcommand ("simulat") is named, with the closest one, rather
  // than reported as a missing subcommand.
  if (argc > 1 && argv[1][0] != '-') {
    const std::string given = argv[1];
    std::string names, closest;
    std::size_t best = std::string::npos;
    for (const CLI::App* sub : app.get_subcommands({})) {
      const std::string name = sub->get_name();
      if (name == given) {
        best = 0;
        break;
      }
      names += (names.empty() ? "" : ", ") + name;
      const std::size_t d = reader::edit_distance(given, name);
      if (d < best) {
        best = d;
        closest = name;
      }
    }
    if (best != 0) {
      std::cerr << "demcal: error: unknown subcommand \"" << given << "\""
                << (best <= 3 ? "; did you mean \"" + closest + "\"?" : "")
                << " (subcommands: " << names << "; see demcal --help)\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "demcal: error: " << e.what() << " (see demcal --help)\n";
    return 2;
  }

  if (*study_cmd)
    return guarded("", [&] {
      study_opts.doe.progress = !study_opts.doe.quiet && isatty(fileno(stderr)) != 0;
      return cli::run_study(study_opts, std::cout, std::cerr).empty() ? 1 : 0;
    });

  if (*export_cmd)
    return guarded("", [&] { return cli::run_export(export_opts, std::cout, std::cerr); });

  if (*diagnose_cmd)
    return guarded("", [&] {
      return cli::diagnose(diag_opts, std::cout, std::cerr).outcome == "incomplete" ? 1 : 0;
    });

  if (*fit_cmd || *inspect_cmd || *calibrate_cmd)
    return guarded("", [&] {
      if (!fit_doe.empty()) fit_opts.doe_csv = fit_doe;
      if (*fit_cmd)
        cli::fit(fit_opts, std::cout, std::cerr);
      else if (*inspect_cmd)
        cli::inspect(fit_opts, std::cout, std::cerr);
      else
        cli::calibrate_study(fit_opts, std::cout, std::cerr);
      return 0;
    });

  if (*doe_cmd) {
    // The MPI session (if any) ends before main returns, whatever happens.
    study::MpiSession mpi;
    const int rank = mpi.group().rank;
    const std::string who = mpi.group().size > 1 ? "rank " + std::to_string(rank) + ": " : "";
    return guarded(who, [&] {
      if (!doe_shard.empty()) doe_opts.shard = cli::parse_shard(doe_shard);
      if (doe_stop_after > 0) doe_opts.stop_after = doe_stop_after;
      doe_opts.group = mpi.group();
      doe_opts.progress = !doe_opts.quiet && mpi.group().size == 1 && isatty(fileno(stderr)) != 0;
      const cli::DoeOutcome r = cli::run_doe(doe_opts, std::cout, std::cerr);
      if (doe_opts.dry_run) return 0;
      if (r.not_run > 0) {
        std::cerr << "demcal doe: " << who << r.not_run
                  << " runs were not run; run the same command again to complete the store\n";
        return 1;
      }
      if (r.missing > 0) {
        std::cerr << "demcal doe: " << r.missing
                  << " rows of the table have no result in the store yet\n";
        return 1;
      }
      // A campaign none of whose runs gave a result did not do what was asked.
      if (!r.table_csv.empty() && r.ok == 0 && r.rows > 0) {
        std::cerr << "demcal doe: every run of the table failed (see the errors in "
                  << r.table_json.string() << "); no result to fit\n";
        return 1;
      }
      return 0;
    });
  }

  return guarded("", [&] {
    if (*schema_cmd) std::cout << demcal::config::schema_text(schema_name);
    if (*simulate_cmd) {
      sim_opts.config = config;
      if (!output.empty()) sim_opts.output_dir = output;
      if (threads > 0) sim_opts.threads = threads;
      if (!apparatus.empty()) sim_opts.apparatus = apparatus;
      sim_opts.progress = !sim_opts.quiet && isatty(fileno(stderr)) != 0;
      cli::simulate(sim_opts, std::cout, std::cerr);
    }
    return 0;
  });
}
