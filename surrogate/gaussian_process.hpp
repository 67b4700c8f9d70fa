#pragma once
// Gaussian-process surrogate (universal kriging): a constant or linear mean estimated by
// generalized least squares, a Matérn 5/2 or squared-exponential covariance with one
// length scale per input, and a nugget for the DEM's run-to-run noise. Hyperparameters
// come from maximizing the log marginal likelihood (NLopt L-BFGS, analytic gradient,
// bounded in log space, several deterministic starts), or are given.
//
// Internally inputs are mapped to the unit box and the output standardized (zero mean,
// unit sample variance), so that the default hyperparameter bounds mean the same thing for
// a friction coefficient and for a discharge time in seconds.

#include "surrogate/covariance_kernel.hpp"
#include "surrogate/cross_validation.hpp"
#include "surrogate/surrogate_model.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace demcal::surrogate {

enum class MeanFunction { constant, linear };
enum class NuggetMode {
  none,       // interpolate the data exactly (deterministic simulator)
  estimated,  // one noise variance for all points, by maximum likelihood
  fixed,      // one given variance per point, e.g. replicate variance / replicates
};
// "constant"/"linear" and "none"/"estimated"/"fixed"; the parsers throw
// std::invalid_argument naming the unknown value.
std::string to_string(MeanFunction mean);
std::string to_string(NuggetMode mode);
MeanFunction mean_function_from_string(const std::string& name);
NuggetMode nugget_mode_from_string(const std::string& name);

// In the caller's units.
struct GaussianProcessHyperparameters {
  std::vector<double> length_scales;  // input units, one per input
  double signal_variance = 1.0;       // output units²
  double nugget_variance = 0.0;       // output units²; used only with NuggetMode::estimated
};

// Search box of the likelihood maximization, in the internal units: length scales as
// fractions of each input's range, variances as multiples of the sample variance of y.
struct HyperparameterBounds {
  // Below 1 % of the range the GP is a set of spikes between design points; above 20 ranges
  // the input is effectively irrelevant.
  double min_length_scale = 0.01;
  double max_length_scale = 20.0;
  // A linear mean can explain nearly all variance, leaving a tiny residual process.
  double min_signal_variance = 1e-6;
  double max_signal_variance = 1e3;
  // The lower bound keeps K invertible; the upper one stops the nugget from explaining all
  // the data as noise.
  double min_nugget_variance = 1e-10;
  double max_nugget_variance = 1.0;
};

struct GaussianProcessOptions {
  CovarianceKernel kernel = CovarianceKernel::matern52;
  MeanFunction mean = MeanFunction::constant;
  NuggetMode nugget = NuggetMode::estimated;
  std::vector<double> nugget_variances;  // NuggetMode::fixed: one per point, output units²
  std::vector<std::string> input_names;  // empty: "x0", "x1", ...
  // Scaling box, one entry per input; both empty: the range of the data.
  std::vector<double> lower;
  std::vector<double> upper;
  // Given: used as they are, no optimization.
  std::optional<GaussianProcessHyperparameters> hyperparameters;
  HyperparameterBounds bounds;
  int starts = 8;             // first start at a fixed central guess, the rest drawn from seed
  std::uint64_t seed = 1;
  int max_evaluations = 400;  // per start
};

// What the likelihood maximization did; empty for given hyperparameters or a loaded model.
struct MaximumLikelihoodReport {
  std::vector<double> start_log_likelihoods;  // best found from each start (-inf: failed)
  int best_start = -1;
  int evaluations = 0;  // over all starts
  // e.g. "length_scale[mu_r] at upper bound": the likelihood wants to leave the box.
  std::vector<std::string> at_bounds;
};

class GaussianProcess final : public SurrogateModel {
 public:
  // Everything that defines a fitted process, in the internal units; what surrogate_io
  // saves. Derived quantities (Cholesky factor, weights) are recomputed from it.
  struct State {
    CovarianceKernel kernel = CovarianceKernel::matern52;
    MeanFunction mean = MeanFunction::constant;
    NuggetMode nugget_mode = NuggetMode::estimated;
    std::vector<std::string> input_names;
    Eigen::VectorXd lower, upper;  // scaling box
    Eigen::MatrixXd x;             // training inputs, unscaled
    Eigen::VectorXd y;             // training outputs, unscaled
    double output_mean = 0.0;      // y is standardized as (y - output_mean) / output_scale
    double output_scale = 1.0;
    Eigen::VectorXd length_scales;           // fractions of (upper - lower)
    double signal_variance = 1.0;            // in output_scale² units
    double nugget_variance = 0.0;            // NuggetMode::estimated, output_scale² units
    Eigen::VectorXd point_nugget_variances;  // NuggetMode::fixed, output_scale² units
    Eigen::VectorXd mean_coefficients;       // GLS estimate on the unit box, standardized y
    double jitter = 0.0;                     // added to the diagonal of K, output_scale² units
    double log_marginal_likelihood = 0.0;    // see log_marginal_likelihood()
  };

  // Throws std::invalid_argument naming the problem: sizes that disagree, a non-finite
  // value, too few points for the mean function, a negative per-point nugget, bad bounds or
  // hyperparameters. Throws std::runtime_error when the covariance matrix is not positive
  // definite even after the largest jitter (duplicate points with no nugget).
  static GaussianProcess fit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                             const GaussianProcessOptions& options = {});
  // Rebuilds a saved process with its stored jitter, without optimizing.
  static GaussianProcess from_state(State state);
  const State& state() const { return state_; }

  std::string kind() const override { return "gaussian_process"; }
  std::string description() const override;
  std::size_t input_dimension() const override;
  const std::vector<std::string>& input_names() const override { return state_.input_names; }

  GaussianProcessHyperparameters hyperparameters() const;  // caller's units
  // Noise variance of each training point in output units²: the estimated nugget, the
  // given per-point values, or zeros.
  Eigen::VectorXd point_nugget_variances() const;
  // Mean function in the caller's units: {intercept} or {intercept at x = 0, slopes...}.
  Eigen::VectorXd mean_coefficients() const;
  // Log marginal likelihood of y (original units) at the hyperparameters, mean
  // coefficients profiled out by GLS (not the restricted likelihood).
  double log_marginal_likelihood() const { return state_.log_marginal_likelihood; }
  // Jitter that had to be added to K, relative to the signal variance (0 when none).
  double relative_jitter() const;
  const MaximumLikelihoodReport& report() const { return report_; }

  // Variance is that of the latent function (the surrogate's uncertainty), including the
  // uncertainty of the GLS mean coefficients; add the nugget for a new observation.
  Prediction predict(const Eigen::MatrixXd& points) const override;
  Eigen::VectorXd predict_mean(const Eigen::MatrixXd& points) const override;
  Eigen::MatrixXd gradient(const Eigen::MatrixXd& points) const override;

  // Dubrule's closed form (R&W eq. 5.12 extended to universal kriging): with
  // Q = K⁻¹ - K⁻¹H (HᵀK⁻¹H)⁻¹ HᵀK⁻¹, mu_i = y_i - [Q y]_i / Q_ii and var_i = 1 / Q_ii.
  // This equals refitting without point i with the hyperparameters (and any jitter) held
  // fixed and the mean coefficients re-estimated by GLS; var_i is for a new observation
  // (includes the nugget). Costs one n x n inverse.
  LeaveOneOut leave_one_out() const override;

 private:
  explicit GaussianProcess(State state);
  Eigen::MatrixXd unit_box(const Eigen::MatrixXd& points) const;
  Eigen::MatrixXd mean_basis(const Eigen::MatrixXd& u) const;
  Eigen::MatrixXd cross_covariance(const Eigen::MatrixXd& u) const;

  State state_;
  MaximumLikelihoodReport report_;
  // Derived from state_.
  Eigen::MatrixXd u_;             // training inputs on the unit box
  Eigen::LLT<Eigen::MatrixXd> k_llt_;
  Eigen::VectorXd alpha_;         // K⁻¹ (y_std - H beta)
  Eigen::MatrixXd kinv_h_;        // K⁻¹ H
  Eigen::LLT<Eigen::MatrixXd> hkh_llt_;  // of Hᵀ K⁻¹ H
};

}  // namespace demcal::surrogate
