#include "cli/simulate_command.hpp"

#include "dem/simulation.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <string_view>

namespace demcal::cli {

namespace {

std::string format(const char* fmt, double a, double b = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

std::string observable_text(const nlohmann::json& v) {
  if (v.is_null()) return "null (not measured)";
  if (v.is_number()) return format("%.6g", v.get<double>());
  return v.dump();
}

// One status line on a terminal, rewritten in place about twice a second.
class ProgressLine final : public study::ProgressObserver {
 public:
  ProgressLine(std::ostream& os, bool enabled)
      : os_(os), enabled_(enabled), start_(Clock::now()), last_(start_), phase_start_(start_) {}
  ~ProgressLine() override {
    if (shown_) os_ << '\n' << std::flush;
  }

  // `phase` leads the line when not empty (apparatus runs), with the wall time
  // spent so far. The estimate of the time left is shown only when `end_s` is finite.
  void on_simulation_step(const dem::Simulation& sim, std::string_view phase,
                          double end_s) override;

 private:
  using Clock = std::chrono::steady_clock;
  std::ostream& os_;
  bool enabled_;
  Clock::time_point start_;
  Clock::time_point last_;
  double last_particle_steps_ = 0.0;
  // Where the current phase began, for its own rate: the first phase's rate
  // says little about the next one's (a settling fill vs. a discharge).
  std::string phase_;
  double phase_start_s_ = 0.0;
  Clock::time_point phase_start_;
  std::size_t width_ = 0;
  bool shown_ = false;
};

void ProgressLine::on_simulation_step(const dem::Simulation& sim, std::string_view phase,
                                      double end_s) {
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

}  // namespace

SimulateOutcome simulate(const SimulateOptions& options, std::ostream& out,
                         std::ostream& progress_stream) {
  SimulateOutcome r;
  {
    ProgressLine progress(progress_stream, options.progress);  // its line ends here
    r = study::run_simulation(options, progress);
  }
  const study::RunResults& res = r.results;
  if (!options.quiet) {
    const double rate = res.wall_time_s > 0.0 ? r.particle_steps / res.wall_time_s : 0.0;
    out << "demcal: " << r.name << ": ";
    if (r.apparatus.empty())
      out << "stopped " << (res.stopped_because == "at_rest" ? "at rest" : "at the end time")
          << format(" at t = %.4f s after ", r.end_time_s);
    else if (!r.engine.empty())
      out << r.apparatus << ": finished on " << r.engine << "; ";
    else
      out << r.apparatus << format(": finished at t = %.4f s after ", r.end_time_s);
    if (r.engine.empty()) out << r.steps << " steps; ";
    out << r.particles << " particles" << format(", %.1f s wall time", res.wall_time_s);
    if (r.engine.empty()) out << format(", %.3g particle-steps/s", rate);
    out << "\n";
    for (const auto& [name, value] : r.observables.items())
      out << "  " << name << " = " << observable_text(value) << "\n";
  }
  out << "run record: " << r.run_record.string() << "\n";
  if (!res.vtk_series.empty()) out << "vtk series: " << res.vtk_series.string() << "\n";
  return r;
}

}  // namespace demcal::cli
