#pragma once
// Polynomial response surface fitted by least squares: the seed paper's regression
// equations, with the standard errors and cross-validation needed to trust them.
//
// Inputs are mapped to [-1, 1] from a box (given bounds, or the data range) before the
// design matrix is built: raw powers of values like 2e7 (a modulus) or 0.05 (a friction)
// would make XᵀX singular to working precision long before the design is.

#include "surrogate/cross_validation.hpp"
#include "surrogate/surrogate_model.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace demcal::surrogate {

struct PolynomialOptions {
  int degree = 2;  // total degree, 1..4; ignored when `terms` is given
  // Explicit term set instead of a total degree: one exponent vector (one entry per input,
  // each >= 0) per term; e.g. {{0,0},{1,0},{0,1},{1,1}} is 1 + x0 + x1 + x0*x1.
  std::vector<std::vector<int>> terms;
  std::vector<std::string> input_names;  // empty: "x0", "x1", ...
  // Scaling box, one entry per input; both empty: the range of the data.
  std::vector<double> lower;
  std::vector<double> upper;
};

class PolynomialSurface final : public SurrogateModel {
 public:
  // Everything that defines a fitted surface; what surrogate_io saves.
  struct State {
    std::vector<std::vector<int>> terms;
    std::vector<std::string> input_names;
    Eigen::VectorXd lower, upper;  // scaling box
    Eigen::MatrixXd x;             // training inputs, unscaled
    Eigen::VectorXd y;
    Eigen::VectorXd coefficients;  // on the scaled inputs, aligned with `terms`
    Eigen::MatrixXd xtx_inverse;   // (XᵀX)⁻¹ of the scaled design matrix
    Eigen::VectorXd hat_diagonal;  // h_ii of the training points
    double residual_sigma = 0.0;   // sqrt(SSE / (n - terms))
  };

  // Throws std::invalid_argument naming the problem: sizes that disagree, a non-finite
  // value, degree outside 1..4, a malformed term, fewer points than terms + 1 (the residual
  // variance needs one spare degree of freedom), or a rank-deficient design (names a term
  // the points cannot separate from the others).
  static PolynomialSurface fit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                               const PolynomialOptions& options = {});
  // Rebuilds a saved surface without refitting; checks that the pieces are consistent.
  static PolynomialSurface from_state(State state);
  const State& state() const { return state_; }

  // All exponent vectors of total degree <= degree in p inputs, by degree and then
  // lexicographically descending: 1, x0, x1, x0^2, x0*x1, x1^2, ...
  static std::vector<std::vector<int>> total_degree_terms(int degree, int inputs);

  std::string kind() const override { return "polynomial_surface"; }
  std::string description() const override;
  std::size_t input_dimension() const override;
  const std::vector<std::string>& input_names() const override { return state_.input_names; }

  const std::vector<std::vector<int>>& terms() const { return state_.terms; }
  // "1", "x0", "x0^2*x1", or with input names "mu_r^2*mu_s".
  std::vector<std::string> term_names() const;
  // Highest total degree among the terms.
  int degree() const;

  // On the scaled inputs u = (2x - lower - upper) / (upper - lower), aligned with terms().
  const Eigen::VectorXd& coefficients() const { return state_.coefficients; }
  // sigma² (XᵀX)⁻¹ on the scaled inputs; its diagonal gives standard_errors().
  Eigen::MatrixXd coefficient_covariance() const;
  Eigen::VectorXd standard_errors() const;
  // The same polynomial expanded in the unscaled inputs (coefficients and standard errors
  // aligned with terms()), for regression equations in physical units. Throws
  // std::logic_error when the term set is not closed under lowering an exponent (then the
  // expansion has terms outside the set); total-degree sets always are.
  Eigen::VectorXd unscaled_coefficients() const;
  Eigen::VectorXd unscaled_standard_errors() const;

  std::size_t points() const { return static_cast<std::size_t>(state_.y.size()); }
  int residual_degrees_of_freedom() const;
  double residual_sigma() const { return state_.residual_sigma; }
  double r_squared() const;           // NaN when y is constant
  double adjusted_r_squared() const;  // NaN when y is constant

  Prediction predict(const Eigen::MatrixXd& points) const override;
  Eigen::VectorXd predict_mean(const Eigen::MatrixXd& points) const override;
  // Standard error of the fitted mean, and of a new observation (adds residual sigma²).
  Eigen::VectorXd mean_standard_error(const Eigen::MatrixXd& points) const;
  Eigen::VectorXd observation_standard_error(const Eigen::MatrixXd& points) const;
  Eigen::MatrixXd gradient(const Eigen::MatrixXd& points) const override;

  // Closed form through the hat matrix: residual e_i / (1 - h_ii), and the variance of a
  // new observation from the refit without i, s_(i)² / (1 - h_ii), with s_(i) the deleted
  // residual sigma (NaN when n - terms < 2). A point of leverage 1 gets an infinite
  // residual: no fit without it exists.
  LeaveOneOut leave_one_out() const override;

 private:
  explicit PolynomialSurface(State state) : state_(std::move(state)) {}
  Eigen::MatrixXd scaled_design(const Eigen::MatrixXd& points) const;

  State state_;
};

enum class CrossValidationMethod { leave_one_out, k_fold };

struct DegreeSelectionOptions {
  int min_degree = 1;
  int max_degree = 4;
  CrossValidationMethod method = CrossValidationMethod::leave_one_out;
  int folds = 5;           // k_fold only
  std::uint64_t seed = 1;  // k_fold only: fold assignment
  // Hastie et al.'s one-standard-error rule: take the lowest degree whose mean squared CV
  // error is within one standard error of the best, trading a little fit for a surface
  // that extrapolates more tamely. Off: the lowest CV error wins.
  bool one_standard_error_rule = false;
};

struct DegreeSelection {
  int degree = 0;
  std::vector<int> degrees;         // tried (those with fewer terms than points - 1)
  std::vector<double> cv_rmse;  // aligned with `degrees`; +inf where a fit was singular
  std::vector<double> cv_mse_standard_error;  // of the mean squared CV error (one-SE rule)
  PolynomialSurface surface;                  // refitted on all points at `degree`
};

// Total degree by cross-validation; `base` supplies names and bounds (its degree and terms
// are ignored). Throws std::invalid_argument for bad degree limits or folds, or when no
// degree in the range can be fitted.
DegreeSelection select_polynomial_degree(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                         const PolynomialOptions& base = {},
                                         const DegreeSelectionOptions& options = {});

}  // namespace demcal::surrogate
