#include "calibrate/scatter_budget.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace demcal::calibrate {

void validate(const LocalScatterOptions& options) {
  if (!(options.bandwidth > 0.0) || !std::isfinite(options.bandwidth))
    throw std::invalid_argument("LocalScatterOptions: bandwidth must be finite and > 0");
}

double local_replicate_scatter(const std::vector<ReplicatePoint>& points,
                               const Eigen::VectorXd& theta,
                               const std::vector<ParameterBounds>& bounds,
                               const LocalScatterOptions& options) {
  validate(options);
  const auto p = static_cast<Eigen::Index>(bounds.size());
  if (theta.size() != p)
    throw std::invalid_argument("local_replicate_scatter: theta has " +
                                std::to_string(theta.size()) + " values for " + std::to_string(p) +
                                " parameters");
  double ss_w = 0.0, dof_w = 0.0;
  const double h2 = options.bandwidth * options.bandwidth;
  for (const auto& pt : points) {
    if (pt.x.size() != p)
      throw std::invalid_argument("local_replicate_scatter: a design point has " +
                                  std::to_string(pt.x.size()) + " inputs for " + std::to_string(p) +
                                  " parameters");
    if (pt.values.size() < 2) continue;
    double d2 = 0.0;
    for (Eigen::Index j = 0; j < p; ++j) {
      const auto& b = bounds[static_cast<std::size_t>(j)];
      const double du = (pt.x(j) - theta(j)) / (b.upper - b.lower);
      d2 += du * du;
    }
    const double w = std::exp(-0.5 * d2 / h2);
    double mean = 0.0;
    for (double v : pt.values) mean += v;
    mean /= static_cast<double>(pt.values.size());
    double ss = 0.0;
    for (double v : pt.values) ss += (v - mean) * (v - mean);
    ss_w += w * ss;
    dof_w += w * static_cast<double>(pt.values.size() - 1);
  }
  // Far from every point the weights underflow: then the pooled value is the best guess.
  if (!(dof_w > 1e-12)) {
    if (options.bandwidth > 1e3) return std::numeric_limits<double>::quiet_NaN();
    LocalScatterOptions wide = options;
    wide.bandwidth = 1e6;
    return local_replicate_scatter(points, theta, bounds, wide);
  }
  return std::sqrt(ss_w / dof_w);
}

double recording_dem_sigma(double single_run_scatter, int repeats) {
  if (repeats < 1)
    throw std::invalid_argument("recording_dem_sigma: repeats must be >= 1, got " +
                                std::to_string(repeats));
  if (!std::isfinite(single_run_scatter)) return 0.0;
  return single_run_scatter / std::sqrt(static_cast<double>(repeats));
}

std::vector<Target> with_local_scatter(const std::vector<Target>& targets,
                                       const std::vector<std::vector<ReplicatePoint>>& replicates,
                                       const std::vector<int>& repeats,
                                       const Eigen::VectorXd& theta,
                                       const std::vector<ParameterBounds>& bounds,
                                       const LocalScatterOptions& options) {
  if (replicates.size() != targets.size() || repeats.size() != targets.size())
    throw std::invalid_argument(
        "with_local_scatter: need one replicate set and one repeats per target (" +
        std::to_string(targets.size()) + " targets)");
  std::vector<Target> out = targets;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (replicates[i].empty()) continue;
    const double s = local_replicate_scatter(replicates[i], theta, bounds, options);
    if (std::isfinite(s)) out[i].sigma_dem = recording_dem_sigma(s, repeats[i]);
  }
  return out;
}

}  // namespace demcal::calibrate
