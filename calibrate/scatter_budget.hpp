#pragma once
// The DEM scatter term of a target's sigma budget (calibration_problem.hpp):
//
//   sigma_total^2 = sigma_measured^2 + sigma_dem^2 + var_surrogate(theta),
//   sigma_dem     = s(theta_hat) / sqrt(repeats),
//
// s the DEM's single-run scatter, the stand-in for the test-to-test scatter of a
// recording that is the mean of `repeats` tests. Today cli/calibration_targets.cpp takes
// s = the replicate sd pooled over the whole design (ReplicateScatter::sd). That is the
// scatter at the truth only when the scatter is the same everywhere; where it grows with
// the response (discharge times: 2-5 %, AoR: 5-15 % in tests/concealed/truth/runs.csv),
// the pooled value is an average over the box, too large at one end and too small at the
// other, and the chi-square p-value stops being uniform
// (tests/unit/test_detection_calibration.cpp). The corrected rule: the replicate
// variance pooled with weights that fall off with the distance from theta_hat
// (bound-scaled units, Gaussian kernel), i.e. the scatter where the fit lands.

#include "calibrate/calibration_problem.hpp"

#include <Eigen/Core>

#include <vector>

namespace demcal::calibrate {

// The runs at one design point: its inputs (parameter units) and their values.
struct ReplicatePoint {
  Eigen::VectorXd x;
  std::vector<double> values;  // points with fewer than 2 values carry no scatter
};

struct LocalScatterOptions {
  // Gaussian kernel width in bound-scaled units. Large: the pooled sd of today; small:
  // the nearest points alone, with few degrees of freedom (a noisy sd makes the chi-square
  // heavy-tailed, as bad as a biased one). 0.35 is about one spacing of a 4-level grid.
  double bandwidth = 0.35;
};

// Throws std::invalid_argument naming the option out of range (bandwidth <= 0).
void validate(const LocalScatterOptions& options);

// Kernel-weighted pooled replicate sd at theta (parameter units):
//   s^2 = sum_k w_k SS_k / sum_k w_k (n_k - 1),  w_k = exp(-|u_k - u|^2 / (2 h^2)).
// NaN when no point has two values. Throws std::invalid_argument when a point's or
// theta's size differs from the parameter count.
double local_replicate_scatter(const std::vector<ReplicatePoint>& points,
                               const Eigen::VectorXd& theta,
                               const std::vector<ParameterBounds>& bounds,
                               const LocalScatterOptions& options = {});

// sigma_dem of a recording that is the mean of `repeats` (>= 1) tests with single-test
// scatter s; 0 when s is not finite (no replicates: nothing known to add).
double recording_dem_sigma(double single_run_scatter, int repeats);

// The targets with sigma_dem replaced by local_replicate_scatter at theta over sqrt of
// their recordings' repeats: the second pass of a calibration whose first pass used the
// pooled scatter. replicates and repeats have one entry per target; an empty replicate
// set keeps the target's sigma_dem. Throws std::invalid_argument on a size mismatch.
std::vector<Target> with_local_scatter(const std::vector<Target>& targets,
                                       const std::vector<std::vector<ReplicatePoint>>& replicates,
                                       const std::vector<int>& repeats,
                                       const Eigen::VectorXd& theta,
                                       const std::vector<ParameterBounds>& bounds,
                                       const LocalScatterOptions& options = {});

}  // namespace demcal::calibrate
