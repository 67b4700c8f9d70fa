#pragma once
// How sure the calibration is: the local (Gauss-Newton) covariance at a minimum, where the
// Jacobian has full rank, and the likelihood-ratio region on a grid over the bounds,
// always. The region is what shows that AoR alone admits a whole curve of (mu_r, mu_s)
// while AoR with the discharge time closes it; the covariance only says so near one point.

#include "calibrate/calibration_problem.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace demcal::calibrate {

struct GaussNewtonUncertainty {
  Eigen::MatrixXd covariance;  // parameter units; NaN-filled when not available
  bool covariance_available = false;
  std::vector<double> standard_errors;  // NaN when not available
  bool rank_deficient = false;
  Eigen::VectorXd singular_values;    // bound-scaled Jacobian, descending, zero-padded to p
  Eigen::VectorXd weakest_direction;  // unit, parameter units, first non-zero entry > 0
};

// At theta: J = d r / d u from Ceres (Problem::Evaluate) with u the bound-scaled
// parameters; rank deficient when s_min / s_max < options.rank_condition_threshold (fewer
// targets than parameters always is); otherwise the covariance from ceres::Covariance
// (DENSE_SVD, same threshold), mapped to parameter units. Bounds are ignored: at a bound
// the covariance describes the unconstrained curvature.
GaussNewtonUncertainty gauss_newton_uncertainty(const CalibrationProblem& problem,
                                                const Eigen::VectorXd& theta,
                                                const CalibrationOptions& options);

// The region along one parameter.
struct ParameterExtent {
  std::string name;
  double lower = 0.0, upper = 0.0;  // of the grid nodes inside; NaN when none is
  bool touches_lower_bound = false, touches_upper_bound = false;
  // The region stays off both bounds along this parameter: the data, not the prior box,
  // limit it.
  bool identified() const { return !touches_lower_bound && !touches_upper_bound; }
};

// {theta : chi^2(theta) <= threshold} on a regular grid over the bounds.
//
// Layout of every per-node vector: node (i0, i1, i2) at (axes[0][i0], axes[1][i1],
// axes[2][i2]) is element i0 + n0 * (i1 + n1 * i2): the FIRST parameter varies fastest,
// as in the report's GridField (values[iy * nx + ix] with x = parameter 0).
struct LikelihoodRegion {
  bool available = false;  // false above 3 parameters
  double confidence = 0.95;
  std::vector<std::vector<double>> axes;  // per parameter, lower..upper inclusive
  std::vector<double> chi_squared;        // per node
  std::vector<double> log_posterior;      // per node, as CalibrationProblem::log_posterior
  // Per target, the surrogate mean at each node: its iso-line at the measured value is
  // where that target alone is matched exactly.
  std::vector<std::vector<double>> predicted_mean;
  // threshold = chi_squared_min + chi2 quantile(confidence, p), with chi_squared_min the
  // lower of the grid minimum and the optimum passed in.
  double chi_squared_min = 0.0;
  double threshold = 0.0;
  Eigen::VectorXd grid_minimum;  // node of least chi^2
  std::vector<bool> inside;      // per node: chi^2 <= threshold
  std::size_t nodes_inside = 0;
  // In parameter units (a length for 1 parameter, a volume for 3): each node stands for
  // the cell around it (half cells at the bounds, so all nodes add up to the box).
  double area = 0.0;
  std::vector<ParameterExtent> extent;
  // Major axis of the inside nodes' spread (unit, parameter units, first non-zero entry
  // > 0): the direction the region runs along.
  Eigen::VectorXd principal_axis;
  // At least 5 distinct node positions along every axis inside: otherwise the region is
  // about a grid cell wide and area and extent are coarse (the covariance is better).
  bool resolved = false;
};

// Evaluates chi^2 on the grid in batches. `chi_squared_at_optimum`: the best minimum's
// chi^2 (its optimum may lie between nodes), or +infinity.
LikelihoodRegion likelihood_region(const CalibrationProblem& problem,
                                   double chi_squared_at_optimum,
                                   const CalibrationOptions& options);

// The same statement without the grid: chi^2(theta) <= region.threshold.
bool region_contains(const CalibrationProblem& problem, const LikelihoodRegion& region,
                     const Eigen::VectorXd& theta);

// Node weights (cell measures, see `area`) in the region's layout; they sum to the box.
std::vector<double> grid_cell_measures(const std::vector<std::vector<double>>& axes);

}  // namespace demcal::calibrate
