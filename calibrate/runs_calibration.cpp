#include "calibrate/runs_calibration.hpp"

#include "calibrate/scatter_budget.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace demcal::calibrate {

std::vector<RunResult> runs_in_design_order(std::vector<RunResult> runs) {
  std::stable_sort(runs.begin(), runs.end(), [](const RunResult& a, const RunResult& b) {
    if (a.request.batch != b.request.batch) return a.request.batch < b.request.batch;
    return a.request.slot < b.request.slot;
  });
  return runs;
}

RunsCalibration calibrate_runs(const std::vector<ParameterBounds>& parameters,
                               const std::vector<Recording>& recordings,
                               const std::vector<RunResult>& unordered_runs,
                               const surrogate::SurrogateSpec& surrogate_spec,
                               const CalibrationOptions& calibration_options) {
  const std::vector<RunResult> runs = runs_in_design_order(unordered_runs);
  const std::size_t p = parameters.size();
  std::vector<std::string> names;
  std::vector<double> lower, upper;
  for (const auto& b : parameters) {
    names.push_back(b.name);
    lower.push_back(b.lower);
    upper.push_back(b.upper);
  }
  // Replicates are exact copies of an earlier theta (the design repeats a point, it does not
  // round it), so grouping by exact equality is right.
  std::map<std::vector<double>, int> group_of;
  std::vector<int> group;
  Eigen::MatrixXd x(static_cast<Eigen::Index>(runs.size()), static_cast<Eigen::Index>(p));
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const auto& run = runs[r];
    if (run.request.theta.size() != p)
      throw std::invalid_argument(
          "calibrate_runs: run (batch " + std::to_string(run.request.batch) + ", slot " +
          std::to_string(run.request.slot) + ") has " + std::to_string(run.request.theta.size()) +
          " parameter values, expected " + std::to_string(p));
    if (run.observables.size() != recordings.size())
      throw std::invalid_argument(
          "calibrate_runs: run (batch " + std::to_string(run.request.batch) + ", slot " +
          std::to_string(run.request.slot) + ") has " + std::to_string(run.observables.size()) +
          " observables, expected " + std::to_string(recordings.size()) + " (one per recording)");
    const auto [it, inserted] =
        group_of.emplace(run.request.theta, static_cast<int>(group_of.size()));
    (void)inserted;
    group.push_back(it->second);
    for (std::size_t j = 0; j < p; ++j)
      x(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(j)) = run.request.theta[j];
  }

  RunsCalibration out;
  for (std::size_t i = 0; i < recordings.size(); ++i) {
    const Recording& rec = recordings[i];
    surrogate::ReplicatedData data;
    data.input_names = names;
    data.lower = lower;
    data.upper = upper;
    data.x = x;
    data.y.resize(static_cast<Eigen::Index>(runs.size()));
    for (std::size_t r = 0; r < runs.size(); ++r)
      data.y(static_cast<Eigen::Index>(r)) = runs[r].observables[i];
    data.group = group;
    data.output_name = rec.setup + " " + rec.observable;
    out.surrogates.push_back(surrogate::fit_surrogate(data, surrogate_spec));
    const auto& fit = out.surrogates.back();
    Target t;
    t.setup = rec.setup;
    t.observable = rec.observable;
    t.measured = rec.value;
    t.sigma_measured = rec.sigma;
    // The one rule (as study/calibration_targets.cpp): a mean of `repeats` tests.
    t.sigma_dem = recording_dem_sigma(fit.scatter.sd, std::max(1, rec.repeats));
    t.model = fit.model;
    out.targets.push_back(t);
  }
  out.result = calibrate(parameters, out.targets, calibration_options);
  return out;
}

}  // namespace demcal::calibrate
