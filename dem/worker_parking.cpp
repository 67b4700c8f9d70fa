#include "dem/worker_parking.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace demcal::dem {

const char* worker_parking_name(WorkerParking parking) {
  switch (parking) {
    case WorkerParking::kNever:
      return "never";
    case WorkerParking::kAlways:
      return "always";
    case WorkerParking::kAdaptive:
      break;
  }
  return "adaptive";
}

const std::vector<std::string>& worker_parking_names() {
  static const std::vector<std::string> names = {"adaptive", "never", "always"};
  return names;
}

WorkerParking parse_worker_parking(const std::string& name) {
  if (name == "adaptive") return WorkerParking::kAdaptive;
  if (name == "never") return WorkerParking::kNever;
  if (name == "always") return WorkerParking::kAlways;
  throw std::invalid_argument("unknown worker parking '" + name +
                              "'; expected \"adaptive\", \"never\" or \"always\"");
}

WorkerParkingPolicy::WorkerParkingPolicy(WorkerParking parking, WorkerParkingOptions options)
    : parking_(parking), options_(options) {
  if (!(options_.window_s > 0.0) || !std::isfinite(options_.window_s))
    throw std::invalid_argument("worker parking: window_s must be finite and > 0");
  if (!(options_.switch_margin >= 0.0 && options_.switch_margin < 1.0))
    throw std::invalid_argument("worker parking: switch_margin must lie in [0, 1)");
  if (options_.first_probe_interval_windows < 1 ||
      options_.max_probe_interval_windows < options_.first_probe_interval_windows)
    throw std::invalid_argument(
        "worker parking: the probe intervals must satisfy 1 <= first <= max");
  settled_parked_ = parking_ == WorkerParking::kAlways;
  probe_interval_ = options_.first_probe_interval_windows;
  windows_until_probe_ = probe_interval_;
}

void WorkerParkingPolicy::record(double run_s) {
  if (parking_ != WorkerParking::kAdaptive) return;
  // A clock that went backwards or a nonsense time must not steer the rule:
  // the run is left out of the window altogether.
  if (!(run_s >= 0.0) || !std::isfinite(run_s)) return;
  window_s_ += run_s;
  ++window_runs_;
  if (window_s_ >= options_.window_s && window_runs_ >= options_.min_runs_per_window)
    close_window();
}

void WorkerParkingPolicy::close_window() {
  const double mean_s = window_s_ / static_cast<double>(window_runs_);
  window_s_ = 0.0;
  window_runs_ = 0;
  if (probing_) {
    probing_ = false;
    ++probes_;
    // The settled window just before the probe is the comparison: the load of
    // the machine and the work of a step change little over two windows.
    if (last_settled_mean_s_ > 0.0 &&
        mean_s < (1.0 - options_.switch_margin) * last_settled_mean_s_) {
      settled_parked_ = !settled_parked_;
      ++switches_;
      last_settled_mean_s_ = mean_s;
      probe_interval_ = options_.first_probe_interval_windows;
    } else {
      probe_interval_ = std::min(2 * probe_interval_, options_.max_probe_interval_windows);
    }
    windows_until_probe_ = probe_interval_;
    return;
  }
  last_settled_mean_s_ = mean_s;
  if (--windows_until_probe_ == 0) probing_ = true;
}

}  // namespace demcal::dem
