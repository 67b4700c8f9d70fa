#include "study/simulation_run.hpp"

#include "config/simulation_config.hpp"
#include "config/study_config.hpp"
#include "config/toml_reader.hpp"
#include "dem/output/vtk_writer.hpp"
#include "dem/simulation.hpp"
#include "study/engine_evaluator.hpp"

#include <omp.h>

#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <string_view>
#include <utility>

namespace demcal::study {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNever = std::numeric_limits<double>::infinity();

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The cap that bounds a phase, by the names the apparatus report (apparatus.cpp:
// settling phases run to max_settle_s, flow phases to max_flow_s). A phase not
// listed gets no estimate rather than a wrong one.
double phase_cap_s(std::string_view phase, const dem::RunProtocol& p) {
  if (phase == "fill" || phase == "settle" || phase == "pile") return p.max_settle_s;
  if (phase == "discharge" || phase == "pour") return p.max_flow_s;
  return kNever;
}

void note_end_state(const dem::Simulation& sim, SimulationRunOutcome& outcome) {
  outcome.end_time_s = sim.time_s();
  outcome.steps = sim.step_count();
  outcome.particles = sim.particles().size();
  outcome.particle_steps = sim.particle_steps();
}

// A study whose [engine] names LAMMPS or LIGGGHTS: the deck is written and run in
// <output directory>/engine-run, its dumps measured by demcal's own code, and run.json
// written as for demcal's run, with "engine" and "engine_deck" saying how it was made (as
// the design runner's records of that engine do). No VTK output: the engine's dumps are
// beside the deck.
SimulationRunOutcome run_on_other_engine(const config::StudyConfig& study,
                                         const config::StudyApparatus& chosen,
                                         const std::filesystem::path& dir) {
  std::optional<EngineEvaluator> engine =
      EngineEvaluator::for_run(study, chosen, dir / "engine-run");
  SimulationRunOutcome outcome;
  outcome.name = study.name;
  outcome.apparatus = chosen.name;
  outcome.engine = study.engine->kind;
  outcome.run_record = run_record_path(dir);
  RunResults& res = outcome.results;
  const Clock::time_point start = Clock::now();
  dem::ApparatusResult result;
  try {
    result = engine->run();
  } catch (const std::exception& e) {
    res.stopped_because = "error";
    res.error = e.what();
    res.wall_time_s = seconds_since(start);
    try {
      nlohmann::json record = make_apparatus_run_record(study, chosen, res, nullptr);
      engine->describe(record);
      write_failed_run_record(dir, record);
    } catch (const std::exception&) {
    }
    throw;
  }
  res.stopped_because = "finished";
  res.wall_time_s = seconds_since(start);
  nlohmann::json record = make_apparatus_run_record(study, chosen, res, &result);
  engine->describe(record);
  res.time_step_s = record.value("time_step_s", 0.0);
  write_run_record(dir, record);
  outcome.observables = config::with_stable_observables(result.observables);
  outcome.particles = result.details.value("particles", std::size_t{0});
  return outcome;
}

// The apparatus path: `doc` is the study config as read, no overrides applied yet.
SimulationRunOutcome run_apparatus(const SimulationRunOptions& options,
                                   config::ConfigDocument&& doc, ProgressObserver& observer) {
  for (const auto& o : options.overrides)
    config::apply_override(doc, o, config::study_override_aliases());
  if (options.output_dir)
    config::set_config_value(doc, "output.directory", toml::value<std::string>(*options.output_dir),
                             "--output " + *options.output_dir);
  if (options.threads)
    config::set_config_value(doc, "study.threads", toml::value<std::int64_t>(*options.threads),
                             "--threads " + std::to_string(*options.threads));
  config::StudyConfig study = config::build_study(std::move(doc));
  config::StudyApparatus& chosen = config::select_apparatus(study, options.apparatus);
  const std::filesystem::path dir = config::output_directory(study, chosen.name);
  // [engine] naming another engine: checked (deck writable, launch line starts that engine)
  // before the output directory is touched, then run there instead of demcal's own DEM.
  if (engine_run_key(study, chosen.name)) {
    prepare_output_directory(dir, options.overwrite);
    return run_on_other_engine(study, chosen, dir);
  }
  prepare_output_directory(dir, options.overwrite);

  dem::Apparatus& apparatus = *chosen.apparatus;
  const dem::Simulation& sim = apparatus.simulation();
  // As on the plain path: no parallel region may start more threads than allowed.
  omp_set_num_threads(study.protocol.threads);

  SimulationRunOutcome outcome;
  outcome.name = study.name;
  outcome.apparatus = chosen.name;
  outcome.run_record = run_record_path(dir);
  RunResults& res = outcome.results;
  std::unique_ptr<dem::VtkSeries> vtk = open_vtk_series(dir, study.output.vtk, res);
  const double snap_dt = study.output.snapshot_interval_s;

  // Snapshot times are k * interval, not accumulated, so they do not drift;
  // the first is the first step's state (the apparatus inserts at t = 0).
  std::int64_t snaps_done = 0;
  double next_snap = vtk && snap_dt > 0.0 ? 0.0 : kNever;
  double previous_t = 0.0;
  std::string phase;
  double phase_end_s = kNever;
  const dem::StepObserver observe = [&](const dem::Simulation& s, std::string_view p) {
    const double t = s.time_s();
    const double dt = t - previous_t;
    previous_t = t;
    if (p != phase) {
      phase = p;
      phase_end_s = (t - dt) + phase_cap_s(p, study.protocol);
    }
    if (t + 0.5 * dt >= next_snap) {
      vtk->write(s);
      while (next_snap <= t + 0.5 * dt) next_snap = static_cast<double>(++snaps_done) * snap_dt;
    }
    if ((s.step_count() & 63) == 0) observer.on_simulation_step(s, phase, phase_end_s);
  };

  auto time_step = [&] {
    return sim.step_count() > 0 ? sim.time_s() / static_cast<double>(sim.step_count()) : 0.0;
  };
  const Clock::time_point start = Clock::now();
  dem::ApparatusResult result;
  try {
    result = apparatus.run(observe);
    if (vtk && (vtk->snapshots() == 0 || vtk->last_time_s() < sim.time_s())) vtk->write(sim);
  } catch (const std::exception& e) {
    res.stopped_because = "error";
    res.error = e.what();
    res.phase = phase;
    res.wall_time_s = seconds_since(start);
    res.time_step_s = time_step();
    res.snapshots = vtk ? vtk->snapshots() : 0;
    // The record of a failed run is still evidence; a failure to write it must
    // not hide the original error.
    try {
      write_failed_run_record(dir, make_apparatus_run_record(study, chosen, res, nullptr));
    } catch (const std::exception&) {
    }
    throw;
  }
  // The apparatus decides when its event is over; details.phases says whether
  // each phase came to rest or reached its cap.
  res.stopped_because = "finished";
  res.phase = phase;
  res.wall_time_s = seconds_since(start);
  res.time_step_s = time_step();
  res.snapshots = vtk ? vtk->snapshots() : 0;
  write_run_record(dir, make_apparatus_run_record(study, chosen, res, &result));
  outcome.observables = config::with_stable_observables(result.observables);
  note_end_state(sim, outcome);
  return outcome;
}

}  // namespace

SimulationRunOutcome run_simulation(const SimulationRunOptions& options,
                                    ProgressObserver& observer) {
  config::ConfigDocument doc = config::read_config_file(options.config);
  if (config::is_study_config(doc)) return run_apparatus(options, std::move(doc), observer);
  if (options.apparatus)
    throw config::ConfigError(doc.file + ": --apparatus " + *options.apparatus +
                              ": applies only to study configs (with [apparatus.*] tables); "
                              "this is a simulation config");
  for (const auto& o : options.overrides) config::apply_override(doc, o);
  if (options.output_dir)
    config::set_config_value(doc, "output.directory", toml::value<std::string>(*options.output_dir),
                             "--output " + *options.output_dir);
  if (options.threads)
    config::set_config_value(doc, "simulation.threads", toml::value<std::int64_t>(*options.threads),
                             "--threads " + std::to_string(*options.threads));
  config::SimulationConfig cfg = config::build_simulation(std::move(doc));
  const std::filesystem::path dir = cfg.output.directory;
  prepare_output_directory(dir, options.overwrite);

  dem::Simulation& sim = *cfg.simulation;
  // The configured thread count also becomes OpenMP's default, so a parallel
  // region without its own num_threads cannot start (and spin) more threads
  // than the user allowed.
  omp_set_num_threads(sim.options().threads);
  const config::RunControl& rc = cfg.run;
  const double snap_dt = cfg.output.snapshot_interval_s;

  SimulationRunOutcome outcome;
  outcome.name = cfg.name;
  outcome.run_record = run_record_path(dir);
  RunResults& res = outcome.results;
  std::unique_ptr<dem::VtkSeries> vtk = open_vtk_series(dir, cfg.output.vtk, res);
  const Clock::time_point start = Clock::now();
  try {
    // Resolves the time step and performs the insertions due at t = 0.
    const double dt = sim.time_step_s();
    res.time_step_s = dt;
    const double half = 0.5 * dt;
    // Event times as k * interval, not by accumulation, so they do not drift.
    std::int64_t snaps_done = 0, checks_done = 0;
    double next_snap = kNever;
    if (vtk && snap_dt > 0.0) {
      vtk->write(sim);
      next_snap = static_cast<double>(++snaps_done) * snap_dt;
    }
    double next_check = static_cast<double>(++checks_done) * rc.check_interval_s;
    res.stopped_because = "end_time";
    while (sim.time_s() + half < rc.end_time_s) {
      sim.step();
      const double t = sim.time_s();
      if (t + half >= next_snap) {
        vtk->write(sim);
        while (next_snap <= t + half) next_snap = static_cast<double>(++snaps_done) * snap_dt;
      }
      if (t + half >= next_check) {
        while (next_check <= t + half)
          next_check = static_cast<double>(++checks_done) * rc.check_interval_s;
        if (rc.stop_at_rest && sim.insertion_finished() &&
            sim.rms_speed_m_s() < rc.rest_speed_m_s) {
          res.stopped_because = "at_rest";
          break;
        }
      }
      if ((sim.step_count() & 63) == 0) observer.on_simulation_step(sim, {}, rc.end_time_s);
    }
    if (vtk && (vtk->snapshots() == 0 || vtk->last_time_s() < sim.time_s())) vtk->write(sim);
  } catch (const std::exception& e) {
    res.stopped_because = "error";
    res.error = e.what();
    res.wall_time_s = seconds_since(start);
    res.snapshots = vtk ? vtk->snapshots() : 0;
    // The record of a failed run is still evidence; a failure to write it must
    // not hide the original error.
    try {
      write_failed_run_record(dir, make_run_record(cfg, res));
    } catch (const std::exception&) {
    }
    throw;
  }
  res.wall_time_s = seconds_since(start);
  res.snapshots = vtk ? vtk->snapshots() : 0;
  write_run_record(dir, make_run_record(cfg, res));
  note_end_state(sim, outcome);
  return outcome;
}

}  // namespace demcal::study
