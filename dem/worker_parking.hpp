#pragma once
// Whether a thread team's workers take part in its runs, or sleep while the
// caller runs every chunk alone ("parked"), decided from the team's own
// measured wall time.
//
// Why: on a machine where another CPU-bound process holds a core, a team of
// two threads shares the cores with it, and a step waits at every run for
// whichever member the kernel descheduled while it held a chunk (a chunk
// cannot be taken over half done: it updates contact histories in place).
// Measured (BENCHMARKS.md, 2026-12-03): such a 2-thread run took 1.1-1.35x the
// wall time of a 1-thread run, whatever the chunking or the pinning. A parked
// team runs the same chunks, in the same order of chunks, writing the same
// buffers, so its results are bit-identical to the team's; only who runs them
// changes. Parking is therefore a pure scheduling decision and can be taken
// and revised during a run without touching determinism.
//
// The rule (an explore-exploit rule on wall time): the team runs in its
// settled mode and measures the mean wall time of a run over windows of at
// least `window_s` seconds. Every `probe_interval` windows it runs one window
// in the other mode (a probe). If the probe's mean run time is below
// (1 - switch_margin) x that of the settled window just before it, the other
// mode becomes the settled one. The probe interval starts at
// `first_probe_interval_windows`, doubles after every probe that did not
// switch (up to `max_probe_interval_windows`) and returns to its start after a
// switch. With 0.2 s windows, a quiet machine pays one slow window in 128 once
// the run is long (about 0.4 % of the 2-thread rate; 1-2 % over the first
// minute), a load that comes is noticed within 2 s and one that goes within
// 26 s.

#include <cstdint>
#include <string>
#include <vector>

namespace demcal::dem {

enum class WorkerParking {
  kAdaptive,  // park or not, by the rule above (the default)
  kNever,     // every member works in every run (the behaviour up to 2026-12-03)
  kAlways,    // the caller runs every chunk; the workers sleep (tests, benchmarks)
};

// "adaptive" | "never" | "always".
const char* worker_parking_name(WorkerParking parking);
const std::vector<std::string>& worker_parking_names();
// Throws std::invalid_argument naming the known names when `name` is none of them.
WorkerParking parse_worker_parking(const std::string& name);

struct WorkerParkingOptions {
  // A window closes at the first run that brings it to at least this wall time
  // and at least min_runs_per_window runs: long enough to average over many
  // scheduler time slices (a few ms each) and over the mix of runs in a step.
  double window_s = 0.2;
  std::uint32_t min_runs_per_window = 32;
  // The other mode must be at least this much faster to be adopted.
  double switch_margin = 0.05;
  std::uint32_t first_probe_interval_windows = 8;
  std::uint32_t max_probe_interval_windows = 128;
};

// The rule as plain arithmetic on measured times, with no clock and no thread,
// so it is tested with made-up times.
class WorkerParkingPolicy {
 public:
  explicit WorkerParkingPolicy(WorkerParking parking = WorkerParking::kAdaptive,
                               WorkerParkingOptions options = {});

  // Whether the next run is to be run by the caller alone.
  bool park() const { return probing_ ? !settled_parked_ : settled_parked_; }
  // The wall time of the run just done, in the mode park() gave for it.
  void record(double run_s);

  // What happened so far, for logs and tests.
  bool settled_parked() const { return settled_parked_; }
  std::uint64_t probes() const { return probes_; }
  std::uint64_t switches() const { return switches_; }

 private:
  void close_window();

  WorkerParking parking_;
  WorkerParkingOptions options_;
  bool settled_parked_ = false;
  bool probing_ = false;
  double window_s_ = 0.0;
  std::uint32_t window_runs_ = 0;
  double last_settled_mean_s_ = 0.0;  // mean run time of the last settled window
  std::uint32_t probe_interval_ = 0;
  std::uint32_t windows_until_probe_ = 0;
  std::uint64_t probes_ = 0;
  std::uint64_t switches_ = 0;
};

}  // namespace demcal::dem
