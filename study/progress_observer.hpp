#pragma once
// How the study library reports while it works: a design's runs as they
// finish, the progress of the whole, one simulation's steps, warnings and
// notes. The library prints nothing itself; the command line implements this
// by printing (one line per run, or a bar on a terminal), a test by counting,
// a service by logging.
// Every callback comes from the thread that called into the library, one at
// a time, so an observer need not be thread-safe.

#include <cstddef>
#include <string>
#include <string_view>

namespace demcal::dem {
class Simulation;
}

namespace demcal::study {

struct PlannedRun;

// Where a design stands: this process's share of its runs.
struct DesignProgress {
  std::size_t total = 0;     // runs of the share
  std::size_t reused = 0;    // already in the store when the design started
  std::size_t executed = 0;  // run and stored since
  std::size_t failed = 0;    // of the executed: stored as failed
  double run_seconds = 0.0;  // the executed runs' wall times, summed
  double elapsed_s = 0.0;    // since the runs started
  std::size_t done() const { return reused + executed; }
};

// One run that has just been stored.
struct FinishedRun {
  const PlannedRun* run = nullptr;
  bool ok = false;
  std::string error;  // when not ok
  double wall_time_s = 0.0;
};

class ProgressObserver {
 public:
  virtual ~ProgressObserver() = default;
  // A note worth a line (what a setting means for this study, ...).
  virtual void on_message(const std::string& /*text*/) {}
  // Something is off but the work goes on (a store file that is not a whole
  // record and will be redone, ...).
  virtual void on_warning(const std::string& /*text*/) {}
  // A worker has started a run (reported when the reporting thread next wakes).
  virtual void on_run_started(const PlannedRun& /*run*/) {}
  // A run has been stored; `progress` counts it.
  virtual void on_run_finished(const FinishedRun& /*run*/, const DesignProgress& /*progress*/) {}
  // While runs execute: after every stored run and at least every half second.
  virtual void on_progress(const DesignProgress& /*progress*/) {}
  // While one simulation steps (study/simulation_run.hpp), every 64 steps:
  // `phase` is the apparatus' phase (empty for a plain simulation) and `end_s`
  // the simulated time the run, or the phase, ends at the latest (infinite
  // when nothing bounds it).
  virtual void on_simulation_step(const dem::Simulation& /*simulation*/, std::string_view /*phase*/,
                                  double /*end_s*/) {}
};

// Says nothing.
class SilentObserver final : public ProgressObserver {};

}  // namespace demcal::study
