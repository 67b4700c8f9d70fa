// demcal command line. Thin on purpose: the logic lives in demcal_cli_lib so
// tests and other front ends reach it without a process boundary.

#include "cli/run_record.hpp"
#include "cli/simulate_command.hpp"
#include "cli/simulation_config.hpp"

#include <unistd.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <iostream>

int main(int argc, char** argv) {
  using namespace demcal::cli;
  CLI::App app{"demcal: discrete element simulations and their calibration"};
  app.set_version_flag("--version", "demcal " + engine_version());
  app.require_subcommand(1);

  SimulateOptions sim_opts;
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
  simulate_cmd->add_option("--output", output, "Output directory (replaces output.directory)");
  simulate_cmd
      ->add_option("--threads", threads, "Threads (replaces simulation.threads or study.threads)")
      ->check(CLI::Range(1, 4096));
  simulate_cmd->add_flag("--overwrite", sim_opts.overwrite,
                         "Replace the run.json of an earlier run in the output directory");
  simulate_cmd->add_flag("--quiet,-q", sim_opts.quiet,
                         "No progress or summary; only the output paths and errors");

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

  try {
    if (*simulate_cmd) {
      sim_opts.config = config;
      if (!output.empty()) sim_opts.output_dir = output;
      if (threads > 0) sim_opts.threads = threads;
      if (!apparatus.empty()) sim_opts.apparatus = apparatus;
      sim_opts.progress = !sim_opts.quiet && isatty(fileno(stderr)) != 0;
      simulate(sim_opts, std::cout, std::cerr);
    }
  } catch (const ConfigError& e) {
    std::cerr << "demcal: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "demcal: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
