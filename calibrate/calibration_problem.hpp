#pragma once
// The inverse problem: bounded parameters (mu_r, mu_s, ...), measured targets, and the
// standardized residuals that tie them through surrogate models,
//
//   r_i(theta) = (measured_i - mean_i(theta)) / sigma_total_i(theta),
//   sigma_total_i^2 = sigma_measured_i^2 + sigma_dem_i^2 + var_i(theta),
//
// chi^2 = sum_i r_i^2. Ceres minimizes chi^2 from many starts inside the bounds; the
// converged points are merged into distinct minima, each with its Gauss-Newton
// uncertainty (confidence_region.hpp).
//
// Internally the solver works in bound-scaled ("unit") coordinates u = (theta - lower) /
// (upper - lower), each in [0, 1], so that tolerances and condition numbers do not depend
// on the parameters' units; everything returned is in parameter units unless it says so.

#include "surrogate/surrogate_model.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ceres {
class CostFunction;
}

namespace demcal::calibrate {

struct ParameterBounds {
  std::string name;  // e.g. "mu_r"; unique, not empty
  double lower = 0.0;
  double upper = 1.0;  // finite, > lower
};

// One measured quantity and the surrogate that predicts it.
struct Target {
  std::string setup;       // e.g. "sandglass"
  std::string observable;  // e.g. "angle_of_repose_deg"
  double measured = 0.0;
  double sigma_measured = 0.0;  // > 0: the measurement's standard uncertainty
  double sigma_dem = 0.0;       // >= 0: the DEM's run-to-run scatter (replicate sd)
  // Inputs in the parameters' order; input_dimension() must equal the parameter count.
  std::shared_ptr<const surrogate::SurrogateModel> model;
  // Adds the surrogate's own predictive variance to sigma_total^2: where the surrogate
  // is unsure, the target constrains theta less.
  bool include_surrogate_variance = true;
};

// Defaults suit 2-3 parameters and GP-sized surrogates (about 1 s for calibrate()).
struct CalibrationOptions {
  // Local solves start from the box centre and this many Sobol points (>= 0).
  int multistart_points = 16;
  // Seeds the MCMC random numbers (GSL MT19937); the starts are a fixed Sobol sequence.
  std::uint64_t seed = 1;
  // Of the likelihood-ratio region, the credible region and the marginal intervals; (0, 1).
  double confidence = 0.95;
  // Likelihood-ratio grid nodes per axis, both bounds included (>= 3): for 1 and 2
  // parameters, and (smaller, since the cost grows as n^3) for 3. No grid above 3.
  int grid_points_per_axis = 121;
  int grid_points_per_axis_3d = 41;
  // Kept posterior samples, summed over chains and rounded up to a multiple of
  // mcmc_chains (0: no sampling); burn-in is per chain.
  int mcmc_samples = 20000;
  int mcmc_burn_in = 4000;
  // Chain k starts at minimum k mod (number of minima); two or more give R-hat.
  int mcmc_chains = 2;
  int histogram_bins = 40;  // per marginal posterior histogram (>= 1)
  // Two converged points are one minimum when closer than this (Euclidean, bound-scaled
  // units) ...
  double distinct_minimum_tolerance = 0.02;
  // ... or when chi^2 along the straight segment between them never rises more than this
  // above the higher end: a valley of equally good points (AoR alone) is one minimum, not
  // one per start. Minima separated by less could not be told apart by the data anyway.
  double distinct_minimum_barrier = 1.0;
  // The Jacobian of the residuals w.r.t. the bound-scaled parameters is rank deficient
  // when its smallest singular value is below this fraction of its largest; (0, 1).
  double rank_condition_threshold = 1e-3;
  int max_solver_iterations = 200;  // per local solve (>= 1)
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const CalibrationOptions& options);

// Batched evaluation: one row per point, one column per target.
struct TargetPredictions {
  Eigen::MatrixXd mean;
  Eigen::MatrixXd sigma_total;
  Eigen::MatrixXd residual;  // standardized: (measured - mean) / sigma_total
  Eigen::VectorXd chi_squared;
  Eigen::VectorXd log_variance_sum;  // sum_i log sigma_total_i^2, for the likelihood
};

class CalibrationProblem {
 public:
  // Throws std::invalid_argument naming the offending parameter or target: no parameters
  // or targets, an empty or repeated name, lower >= upper or not finite, a missing model,
  // sigma_measured <= 0, sigma_dem < 0, a non-finite value, a model whose input count
  // differs from the parameter count, or whose input names are the parameters' in
  // another order.
  CalibrationProblem(std::vector<ParameterBounds> parameters, std::vector<Target> targets);

  const std::vector<ParameterBounds>& parameters() const { return parameters_; }
  const std::vector<Target>& targets() const { return targets_; }
  Eigen::Index parameter_count() const { return static_cast<Eigen::Index>(parameters_.size()); }
  Eigen::Index target_count() const { return static_cast<Eigen::Index>(targets_.size()); }
  // "target 1 (sandglass discharge_time_s)", as used in messages.
  std::string target_label(std::size_t i) const;

  Eigen::VectorXd lower() const;
  Eigen::VectorXd upper() const;
  Eigen::VectorXd range() const;  // upper - lower
  Eigen::VectorXd to_unit(const Eigen::VectorXd& theta) const;
  Eigen::VectorXd from_unit(const Eigen::VectorXd& u) const;
  bool inside_bounds(const Eigen::VectorXd& theta) const;

  // Points are rows in parameter units (anywhere; the models extrapolate). One predict()
  // per target for the whole batch, so callers pass grids in large chunks.
  TargetPredictions evaluate(const Eigen::MatrixXd& points) const;
  double chi_squared(const Eigen::VectorXd& theta) const;
  // Unnormalized: -chi^2/2 - sum_i log(sigma_total_i^2)/2 inside the bounds (uniform
  // prior), -infinity outside. The second term matters where the surrogate variance
  // varies; chi^2 alone would favour regions where the surrogate is unsure.
  double log_posterior(const Eigen::VectorXd& theta) const;

  // Standardized residuals and, when asked, d r / d theta (targets x parameters, per
  // parameter unit): the mean's derivative from the model's gradient(), the variance's by
  // central differences (the interface has no variance gradient).
  Eigen::VectorXd residuals(const Eigen::VectorXd& theta, Eigen::MatrixXd* jacobian = nullptr) const;

  // The residual block Ceres works on: one parameter block of parameter_count() unit-scaled
  // values, target_count() residuals. It refers to this problem, which must outlive it.
  std::unique_ptr<ceres::CostFunction> make_cost_function() const;

 private:
  std::vector<ParameterBounds> parameters_;
  std::vector<Target> targets_;
};

// A distinct minimum of chi^2 inside the bounds.
struct Minimum {
  Eigen::VectorXd theta;  // parameter units
  double chi_squared = 0.0;
  std::vector<double> residuals;    // standardized, per target
  std::vector<double> predicted;    // surrogate mean, per target
  std::vector<double> sigma_total;  // per target
  bool at_bound = false;            // some parameter within 1e-6 (bound-scaled) of a bound
  int starts = 0;                   // local solves that ended in this minimum

  // Gauss-Newton uncertainty (confidence_region.hpp): covariance = (J^T J)^-1 with J the
  // Jacobian of the standardized residuals, so sigma is taken as stated (not rescaled by
  // chi^2/dof). Not available (NaN-filled) when J is rank deficient.
  Eigen::MatrixXd covariance;
  bool covariance_available = false;
  std::vector<double> standard_errors;  // sqrt(diag(covariance)); NaN when not available
  bool rank_deficient = false;
  // Of J w.r.t. the bound-scaled parameters, descending, padded with zeros to the
  // parameter count (a 1 x 2 Jacobian has singular values (s, 0)).
  Eigen::VectorXd singular_values;
  // Unit vector in parameter units along which chi^2 changes least (the right singular
  // vector of the smallest singular value, mapped back to parameter units); with AoR
  // alone, the tangent of the AoR iso-line. Sign: first non-zero component positive.
  Eigen::VectorXd weakest_direction;

  std::string solver_report;  // Ceres BriefReport of the best solve that ended here
};

// Local solves (Levenberg-Marquardt, DENSE_QR, bounds enforced) from the box centre and
// options.multistart_points Sobol points; converged points merged into distinct minima
// (see the options), sorted by chi^2, each with its Gauss-Newton uncertainty.
std::vector<Minimum> find_minima(const CalibrationProblem& problem,
                                 const CalibrationOptions& options);

// One local solve from `start` (parameter units, inside the bounds), without merging.
Minimum minimize_from(const CalibrationProblem& problem, const Eigen::VectorXd& start,
                      const CalibrationOptions& options);

}  // namespace demcal::calibrate
