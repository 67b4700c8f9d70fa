#include "cli/simulate_command.hpp"

#include "cli/apparatus_command.hpp"
#include "config/study_config.hpp"

#include "dem/output/vtk_writer.hpp"
#include "dem/simulation.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>

namespace demcal::cli {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

}  // namespace

ProgressLine::ProgressLine(std::ostream& os, bool enabled)
    : os_(os), enabled_(enabled), start_(Clock::now()), last_(start_), phase_start_(start_) {}

void ProgressLine::update(const dem::Simulation& sim, std::string_view phase, double end_s) {
  if (!enabled_) return;
  const Clock::time_point now = Clock::now();
  if (phase != phase_) {
    phase_ = phase;
    phase_start_s_ = sim.time_s();
    phase_start_ = now;
  }
  const double since_last = std::chrono::duration<double>(now - last_).count();
  if (since_last < 0.5) return;
  // The recent rate, not the average: the particle count grows during a pour.
  const double rate = (sim.particle_steps() - last_particle_steps_) / since_last;
  last_ = now;
  last_particle_steps_ = sim.particle_steps();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double t = sim.time_s();
  std::string line;
  if (phase_.empty()) {
    line = format("t = %.4f / %.4f s | ", t, end_s);
  } else {
    line = phase_ + format(" | t = %.4f s | ", t);
  }
  line += std::to_string(sim.particles().size()) + " particles | " +
          format("%.3g particle-steps/s", rate);
  if (!phase_.empty()) line += format(" | %.0f s elapsed", elapsed);
  // Before the event is over only a cap bounds it, so the estimate is an upper bound.
  const double phase_elapsed = std::chrono::duration<double>(now - phase_start_).count();
  if (std::isfinite(end_s) && t > phase_start_s_)
    line += format(" | <= %.0f s left", phase_elapsed * (end_s - t) / (t - phase_start_s_)) +
            (phase_.empty() ? "" : " (to the " + phase_ + " cap)");
  // Pad so a shorter line fully covers the previous one.
  if (line.size() < width_) line.append(width_ - line.size(), ' ');
  width_ = line.size();
  os_ << '\r' << line << std::flush;
  shown_ = true;
}

void ProgressLine::finish() {
  if (shown_) os_ << '\n' << std::flush;
  shown_ = false;
}

SimulateOutcome simulate(const SimulateOptions& options, std::ostream& out,
                         std::ostream& progress_stream) {
  config::ConfigDocument doc = config::read_config_file(options.config);
  if (config::is_study_config(doc)) return simulate_apparatus(options, std::move(doc), out, progress_stream);
  if (options.apparatus)
    throw config::ConfigError(doc.file + ": --apparatus " + *options.apparatus +
                      ": applies only to study configs (with [apparatus.*] tables); this is a "
                      "simulation config");
  for (const auto& o : options.overrides) config::apply_override(doc, o);
  if (options.output_dir)
    config::set_config_value(doc, "output.directory", toml::value<std::string>(*options.output_dir),
                     "--output " + *options.output_dir);
  if (options.threads)
    config::set_config_value(doc, "simulation.threads", toml::value<std::int64_t>(*options.threads),
                     "--threads " + std::to_string(*options.threads));
  config::SimulationConfig cfg = config::build_simulation(std::move(doc));
  const std::filesystem::path dir = cfg.output.directory;
  study::prepare_output_directory(dir, options.overwrite);

  dem::Simulation& sim = *cfg.simulation;
  // The configured thread count also becomes OpenMP's default, so a parallel
  // region without its own num_threads cannot start (and spin) more threads
  // than the user allowed.
  omp_set_num_threads(sim.options().threads);
  const config::RunControl& rc = cfg.run;
  const double snap_dt = cfg.output.snapshot_interval_s;
  constexpr double kNever = std::numeric_limits<double>::infinity();

  SimulateOutcome outcome;
  outcome.run_record = study::run_record_path(dir);
  study::RunResults& res = outcome.results;
  std::unique_ptr<dem::VtkSeries> vtk = study::open_vtk_series(dir, cfg.output.vtk, res);
  const Clock::time_point start = Clock::now();
  ProgressLine progress(progress_stream, options.progress);
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
      if ((sim.step_count() & 63) == 0) progress.update(sim, {}, rc.end_time_s);
    }
    progress.finish();
    if (vtk && (vtk->snapshots() == 0 || vtk->last_time_s() < sim.time_s())) vtk->write(sim);
  } catch (const std::exception& e) {
    progress.finish();
    res.stopped_because = "error";
    res.error = e.what();
    res.wall_time_s = seconds_since(start);
    res.snapshots = vtk ? vtk->snapshots() : 0;
    // The record of a failed run is still evidence; a failure to write it must
    // not hide the original error.
    try {
      study::write_failed_run_record(dir, study::make_run_record(cfg, res));
    } catch (const std::exception&) {
    }
    throw;
  }
  res.wall_time_s = seconds_since(start);
  res.snapshots = vtk ? vtk->snapshots() : 0;
  study::write_run_record(dir, study::make_run_record(cfg, res));

  if (!options.quiet) {
    const double rate = res.wall_time_s > 0.0 ? sim.particle_steps() / res.wall_time_s : 0.0;
    out << "demcal: " << cfg.name << ": stopped "
        << (res.stopped_because == "at_rest" ? "at rest" : "at the end time")
        << format(" at t = %.4f s after ", sim.time_s()) << sim.step_count() << " steps; "
        << sim.particles().size() << " particles"
        << format(", %.1f s wall time, %.3g particle-steps/s", res.wall_time_s, rate) << "\n";
  }
  out << "run record: " << outcome.run_record.string() << "\n";
  if (vtk) out << "vtk series: " << res.vtk_series.string() << "\n";
  return outcome;
}

}  // namespace demcal::cli
