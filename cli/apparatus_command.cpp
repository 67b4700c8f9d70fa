#include "cli/apparatus_command.hpp"

#include "study/run_record.hpp"
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
#include <string>
#include <string_view>

namespace demcal::cli {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNever = std::numeric_limits<double>::infinity();

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string format(const char* fmt, double a, double b = 0.0) {
  char buf[128];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

// The cap that bounds a phase, by the names the apparatus report (apparatus.cpp:
// settling phases run to max_settle_s, flow phases to max_flow_s). A phase not
// listed gets no estimate rather than a wrong one.
double phase_cap_s(std::string_view phase, const dem::RunProtocol& p) {
  if (phase == "fill" || phase == "settle" || phase == "pile") return p.max_settle_s;
  if (phase == "discharge" || phase == "pour") return p.max_flow_s;
  return kNever;
}

std::string observable_text(const nlohmann::json& v) {
  if (v.is_null()) return "null (not measured)";
  if (v.is_number()) return format("%.6g", v.get<double>());
  return v.dump();
}

}  // namespace

SimulateOutcome simulate_apparatus(const SimulateOptions& options, config::ConfigDocument&& doc,
                                   std::ostream& out, std::ostream& progress_stream) {
  for (const auto& o : options.overrides) config::apply_override(doc, o, config::study_override_aliases());
  if (options.output_dir)
    config::set_config_value(doc, "output.directory", toml::value<std::string>(*options.output_dir),
                     "--output " + *options.output_dir);
  if (options.threads)
    config::set_config_value(doc, "study.threads", toml::value<std::int64_t>(*options.threads),
                     "--threads " + std::to_string(*options.threads));
  config::StudyConfig study = config::build_study(std::move(doc));
  config::StudyApparatus& chosen = config::select_apparatus(study, options.apparatus);
  const std::filesystem::path dir = config::output_directory(study, chosen.name);
  study::prepare_output_directory(dir, options.overwrite);

  dem::Apparatus& apparatus = *chosen.apparatus;
  const dem::Simulation& sim = apparatus.simulation();
  // As on the plain path: no parallel region may start more threads than allowed.
  omp_set_num_threads(study.protocol.threads);

  SimulateOutcome outcome;
  outcome.run_record = study::run_record_path(dir);
  study::RunResults& res = outcome.results;
  std::unique_ptr<dem::VtkSeries> vtk = study::open_vtk_series(dir, study.output.vtk, res);
  const double snap_dt = study.output.snapshot_interval_s;
  ProgressLine progress(progress_stream, options.progress);

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
      while (next_snap <= t + 0.5 * dt)
        next_snap = static_cast<double>(++snaps_done) * snap_dt;
    }
    if ((s.step_count() & 63) == 0) progress.update(s, phase, phase_end_s);
  };

  auto time_step = [&] {
    return sim.step_count() > 0 ? sim.time_s() / static_cast<double>(sim.step_count()) : 0.0;
  };
  const Clock::time_point start = Clock::now();
  dem::ApparatusResult result;
  try {
    result = apparatus.run(observe);
    progress.finish();
    if (vtk && (vtk->snapshots() == 0 || vtk->last_time_s() < sim.time_s())) vtk->write(sim);
  } catch (const std::exception& e) {
    progress.finish();
    res.stopped_because = "error";
    res.error = e.what();
    res.phase = phase;
    res.wall_time_s = seconds_since(start);
    res.time_step_s = time_step();
    res.snapshots = vtk ? vtk->snapshots() : 0;
    // The record of a failed run is still evidence; a failure to write it must
    // not hide the original error.
    try {
      study::write_failed_run_record(dir, study::make_apparatus_run_record(study, chosen, res, nullptr));
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
  study::write_run_record(dir, study::make_apparatus_run_record(study, chosen, res, &result));
  outcome.observables = config::with_stable_observables(result.observables);

  if (!options.quiet) {
    const double rate = res.wall_time_s > 0.0 ? sim.particle_steps() / res.wall_time_s : 0.0;
    out << "demcal: " << study.name << ": " << chosen.name
        << format(": finished at t = %.4f s after ", sim.time_s()) << sim.step_count()
        << " steps; " << sim.particles().size() << " particles"
        << format(", %.1f s wall time, %.3g particle-steps/s", res.wall_time_s, rate) << "\n";
    for (const auto& [name, value] : outcome.observables.items())
      out << "  " << name << " = " << observable_text(value) << "\n";
  }
  out << "run record: " << outcome.run_record.string() << "\n";
  if (vtk) out << "vtk series: " << res.vtk_series.string() << "\n";
  return outcome;
}

}  // namespace demcal::cli
