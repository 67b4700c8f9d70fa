#include "surrogate/polynomial_surface.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

namespace demcal::surrogate {
namespace {

const std::string kWho = "polynomial surface";
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

double ipow(double base, int exponent) {
  double r = 1.0;
  for (int k = 0; k < exponent; ++k) r *= base;
  return r;
}

std::string term_name(const std::vector<int>& exponents, const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t j = 0; j < exponents.size(); ++j) {
    if (exponents[j] == 0) continue;
    if (!out.empty()) out += "*";
    out += names[j];
    if (exponents[j] > 1) {
      out += '^';
      out += std::to_string(exponents[j]);
    }
  }
  return out.empty() ? "1" : out;
}

int total_degree(const std::vector<int>& exponents) {
  int d = 0;
  for (int e : exponents) d += e;
  return d;
}

Eigen::MatrixXd design_matrix(const Eigen::MatrixXd& scaled, const std::vector<std::vector<int>>& terms) {
  Eigen::MatrixXd X(scaled.rows(), static_cast<Eigen::Index>(terms.size()));
  for (Eigen::Index i = 0; i < scaled.rows(); ++i)
    for (std::size_t t = 0; t < terms.size(); ++t) {
      double v = 1.0;
      for (std::size_t j = 0; j < terms[t].size(); ++j)
        v *= ipow(scaled(i, static_cast<Eigen::Index>(j)), terms[t][j]);
      X(i, static_cast<Eigen::Index>(t)) = v;
    }
  return X;
}

Eigen::MatrixXd scale_to_unit_cube(const Eigen::MatrixXd& x, const Eigen::VectorXd& lo,
                                   const Eigen::VectorXd& hi) {
  Eigen::MatrixXd u(x.rows(), x.cols());
  for (Eigen::Index j = 0; j < x.cols(); ++j)
    u.col(j) = ((2.0 * x.col(j)).array() - (lo(j) + hi(j))) / (hi(j) - lo(j));
  return u;
}

struct LeastSquares {
  Eigen::VectorXd beta;
  Eigen::MatrixXd xtx_inverse;
  Eigen::VectorXd hat_diagonal;
};

// Relative to the largest pivot: a design this close to singular gives coefficients that
// are noise even after scaling to [-1, 1], so it is reported rather than solved.
constexpr double kRankThreshold = 1e-10;

// Empty when X is rank deficient; then *dependent holds a column the others determine.
std::optional<LeastSquares> least_squares(const Eigen::MatrixXd& X, const Eigen::VectorXd& y,
                                          Eigen::Index* dependent = nullptr) {
  const Eigen::Index n = X.rows(), m = X.cols();
  if (n < m) {
    if (dependent) *dependent = m - 1;
    return std::nullopt;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X.rows(), X.cols());
  qr.setThreshold(kRankThreshold);
  qr.compute(X);
  if (qr.rank() < m) {
    if (dependent) *dependent = qr.colsPermutation().indices()(qr.rank());
    return std::nullopt;
  }
  LeastSquares ls;
  ls.beta = qr.solve(y);
  const Eigen::MatrixXd R = qr.matrixR().topLeftCorner(m, m).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd r_inv =
      R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(m, m));
  const Eigen::MatrixXd permuted = r_inv * r_inv.transpose();
  ls.xtx_inverse = qr.colsPermutation() * permuted * qr.colsPermutation().transpose();
  ls.xtx_inverse = 0.5 * (ls.xtx_inverse + ls.xtx_inverse.transpose()).eval();
  // Leverages from the orthonormal factor, not from x_iᵀ(XᵀX)⁻¹x_i: no squared condition.
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(n, m);
  ls.hat_diagonal = q.rowwise().squaredNorm();
  return ls;
}

void check_terms(const std::vector<std::vector<int>>& terms, Eigen::Index p) {
  if (terms.empty()) throw std::invalid_argument(kWho + ": terms is empty");
  std::set<std::vector<int>> seen;
  for (std::size_t t = 0; t < terms.size(); ++t) {
    if (static_cast<Eigen::Index>(terms[t].size()) != p)
      throw std::invalid_argument(kWho + ": terms[" + std::to_string(t) + "] has " +
                                  std::to_string(terms[t].size()) + " exponents but there are " +
                                  std::to_string(p) + " inputs");
    for (int e : terms[t])
      if (e < 0)
        throw std::invalid_argument(kWho + ": terms[" + std::to_string(t) +
                                    "] has a negative exponent");
    if (!seen.insert(terms[t]).second)
      throw std::invalid_argument(kWho + ": terms[" + std::to_string(t) + "] repeats a term");
  }
}

void check_degree(int degree, const std::string& what) {
  if (degree < 1 || degree > 4)
    throw std::invalid_argument(kWho + ": " + what + " must be in 1..4, got " +
                                std::to_string(degree));
}

// For the one-standard-error rule: how far the mean CV error itself is uncertain.
double standard_error_of_mean(const Eigen::VectorXd& v) {
  const auto n = static_cast<double>(v.size());
  if (v.size() < 2) return kInf;
  const double mean = v.mean();
  return std::sqrt((v.array() - mean).square().sum() / (n - 1.0) / n);
}

}  // namespace

std::vector<std::vector<int>> PolynomialSurface::total_degree_terms(int degree, int inputs) {
  check_degree(degree, "degree");
  if (inputs < 1) throw std::invalid_argument(kWho + ": inputs must be >= 1");
  std::vector<std::vector<int>> terms;
  for (int d = 0; d <= degree; ++d) {
    // Exponent vectors of total degree d in lexicographically descending order.
    std::vector<int> e(static_cast<std::size_t>(inputs), 0);
    e[0] = d;
    while (true) {
      terms.push_back(e);
      // Next composition: move one unit from the last nonzero entry before the tail
      // rightwards, then gather the tail into the position after it.
      int k = inputs - 2;
      while (k >= 0 && e[static_cast<std::size_t>(k)] == 0) --k;
      if (k < 0) break;
      const auto uk = static_cast<std::size_t>(k);
      const int tail = e.back();
      e.back() = 0;
      --e[uk];
      e[uk + 1] = tail + 1;
    }
  }
  return terms;
}

PolynomialSurface PolynomialSurface::fit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                         const PolynomialOptions& options) {
  const auto names = detail::resolve_input_names(kWho, options.input_names, x.cols());
  detail::check_training_table(kWho, x, y, names);
  std::vector<std::vector<int>> terms;
  if (options.terms.empty()) {
    check_degree(options.degree, "degree");
    terms = total_degree_terms(options.degree, static_cast<int>(x.cols()));
  } else {
    check_terms(options.terms, x.cols());
    terms = options.terms;
  }
  const auto m = static_cast<Eigen::Index>(terms.size());
  if (x.rows() < m + 1)
    throw std::invalid_argument(kWho + ": " + std::to_string(m) + " terms need at least " +
                                std::to_string(m + 1) + " points (x rows), got " +
                                std::to_string(x.rows()));
  auto [lo, hi] = detail::resolve_box(kWho, x, options.lower, options.upper, names);

  const Eigen::MatrixXd X = design_matrix(scale_to_unit_cube(x, lo, hi), terms);
  Eigen::Index dependent = 0;
  auto ls = least_squares(X, y, &dependent);
  if (!ls)
    throw std::invalid_argument(
        kWho + ": the design matrix is rank deficient: term '" +
        term_name(terms[static_cast<std::size_t>(dependent)], names) +
        "' is (nearly) a combination of the others at these points; use fewer terms or more "
        "distinct levels per input");

  State s;
  s.terms = std::move(terms);
  s.input_names = names;
  s.lower = lo;
  s.upper = hi;
  s.x = x;
  s.y = y;
  s.coefficients = ls->beta;
  s.xtx_inverse = ls->xtx_inverse;
  s.hat_diagonal = ls->hat_diagonal;
  const double sse = (y - X * ls->beta).squaredNorm();
  s.residual_sigma = std::sqrt(sse / static_cast<double>(x.rows() - m));
  return PolynomialSurface(std::move(s));
}

PolynomialSurface PolynomialSurface::from_state(State s) {
  const std::string who = kWho + " state";
  const Eigen::Index p = s.x.cols();
  if (p < 1) throw std::invalid_argument(who + ": x has no columns");
  if (static_cast<Eigen::Index>(s.input_names.size()) != p)
    throw std::invalid_argument(who + ": input_names does not match the columns of x");
  detail::check_training_table(who, s.x, s.y, s.input_names);
  check_terms(s.terms, p);
  const auto m = static_cast<Eigen::Index>(s.terms.size());
  if (s.lower.size() != p || s.upper.size() != p || !((s.upper - s.lower).array() > 0.0).all())
    throw std::invalid_argument(who + ": lower/upper must have one entry per input, upper > lower");
  if (s.coefficients.size() != m || !s.coefficients.allFinite())
    throw std::invalid_argument(who + ": coefficients must have one finite entry per term");
  if (s.xtx_inverse.rows() != m || s.xtx_inverse.cols() != m)
    throw std::invalid_argument(who + ": xtx_inverse must be terms x terms");
  if (s.hat_diagonal.size() != s.x.rows())
    throw std::invalid_argument(who + ": hat_diagonal must have one entry per point");
  if (!(s.residual_sigma >= 0.0) || !std::isfinite(s.residual_sigma))
    throw std::invalid_argument(who + ": residual_sigma must be finite and >= 0");
  return PolynomialSurface(std::move(s));
}

std::string PolynomialSurface::description() const {
  const int d = degree();
  const auto n_terms = std::to_string(state_.terms.size());
  if (state_.terms == total_degree_terms(std::clamp(d, 1, 4), static_cast<int>(input_dimension())))
    return "polynomial surface, total degree " + std::to_string(d) + ", " + n_terms + " terms";
  return "polynomial surface, " + n_terms + " explicit terms up to degree " + std::to_string(d);
}

std::size_t PolynomialSurface::input_dimension() const {
  return static_cast<std::size_t>(state_.x.cols());
}

std::vector<std::string> PolynomialSurface::term_names() const {
  std::vector<std::string> out;
  for (const auto& t : state_.terms) out.push_back(term_name(t, state_.input_names));
  return out;
}

int PolynomialSurface::degree() const {
  int d = 0;
  for (const auto& t : state_.terms) d = std::max(d, total_degree(t));
  return d;
}

int PolynomialSurface::residual_degrees_of_freedom() const {
  return static_cast<int>(state_.y.size()) - static_cast<int>(state_.terms.size());
}

Eigen::MatrixXd PolynomialSurface::coefficient_covariance() const {
  return state_.residual_sigma * state_.residual_sigma * state_.xtx_inverse;
}

Eigen::VectorXd PolynomialSurface::standard_errors() const {
  return coefficient_covariance().diagonal().cwiseMax(0.0).cwiseSqrt();
}

namespace {

// Rows: coefficients in the unscaled inputs; columns: scaled coefficients. Expands each
// product of (a_j x_j + b_j)^e_j by the binomial theorem.
Eigen::MatrixXd unscaling_map(const std::vector<std::vector<int>>& terms, const Eigen::VectorXd& lo,
                              const Eigen::VectorXd& hi) {
  std::map<std::vector<int>, Eigen::Index> index;
  for (std::size_t t = 0; t < terms.size(); ++t) index[terms[t]] = static_cast<Eigen::Index>(t);
  const auto m = static_cast<Eigen::Index>(terms.size());
  const Eigen::VectorXd a = 2.0 / (hi - lo).array();
  const Eigen::VectorXd b = -(hi + lo).array() / (hi - lo).array();
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(m, m);
  for (std::size_t t = 0; t < terms.size(); ++t) {
    const auto& e = terms[t];
    std::vector<int> k(e.size(), 0);
    while (true) {
      double factor = 1.0;
      for (std::size_t j = 0; j < e.size(); ++j) {
        double binom = 1.0;
        for (int r = 1; r <= k[j]; ++r) binom = binom * (e[j] - r + 1) / r;
        const auto jj = static_cast<Eigen::Index>(j);
        factor *= binom * ipow(a(jj), k[j]) * ipow(b(jj), e[j] - k[j]);
      }
      if (factor != 0.0) {
        const auto it = index.find(k);
        if (it == index.end())
          throw std::logic_error(kWho + ": the term set is not closed under lowering exponents, "
                                 "so the unscaled expansion needs terms it does not have");
        T(it->second, static_cast<Eigen::Index>(t)) += factor;
      }
      // Next k <= e in odometer order.
      std::size_t j = 0;
      while (j < e.size() && k[j] == e[j]) k[j++] = 0;
      if (j == e.size()) break;
      ++k[j];
    }
  }
  return T;
}

}  // namespace

Eigen::VectorXd PolynomialSurface::unscaled_coefficients() const {
  return unscaling_map(state_.terms, state_.lower, state_.upper) * state_.coefficients;
}

Eigen::VectorXd PolynomialSurface::unscaled_standard_errors() const {
  const Eigen::MatrixXd T = unscaling_map(state_.terms, state_.lower, state_.upper);
  return (T * coefficient_covariance() * T.transpose()).diagonal().cwiseMax(0.0).cwiseSqrt();
}

double PolynomialSurface::r_squared() const {
  const Eigen::VectorXd e = state_.y - scaled_design(state_.x) * state_.coefficients;
  const double sst = (state_.y.array() - state_.y.mean()).square().sum();
  return sst > 0.0 ? 1.0 - e.squaredNorm() / sst : kNaN;
}

double PolynomialSurface::adjusted_r_squared() const {
  const auto n = static_cast<double>(state_.y.size());
  const auto dof = static_cast<double>(residual_degrees_of_freedom());
  return 1.0 - (1.0 - r_squared()) * (n - 1.0) / dof;
}

Eigen::MatrixXd PolynomialSurface::scaled_design(const Eigen::MatrixXd& points) const {
  return design_matrix(scale_to_unit_cube(points, state_.lower, state_.upper), state_.terms);
}

Eigen::VectorXd PolynomialSurface::predict_mean(const Eigen::MatrixXd& points) const {
  detail::check_points(kWho, points, state_.x.cols());
  return scaled_design(points) * state_.coefficients;
}

Eigen::VectorXd PolynomialSurface::mean_standard_error(const Eigen::MatrixXd& points) const {
  return predict(points).variance.cwiseSqrt();
}

Eigen::VectorXd PolynomialSurface::observation_standard_error(const Eigen::MatrixXd& points) const {
  const double s2 = state_.residual_sigma * state_.residual_sigma;
  return (predict(points).variance.array() + s2).sqrt();
}

Prediction PolynomialSurface::predict(const Eigen::MatrixXd& points) const {
  detail::check_points(kWho, points, state_.x.cols());
  const Eigen::MatrixXd X = scaled_design(points);
  Prediction p;
  p.mean = X * state_.coefficients;
  const double s2 = state_.residual_sigma * state_.residual_sigma;
  p.variance = (s2 * (X * state_.xtx_inverse).cwiseProduct(X).rowwise().sum()).cwiseMax(0.0);
  return p;
}

Eigen::MatrixXd PolynomialSurface::gradient(const Eigen::MatrixXd& points) const {
  detail::check_points(kWho, points, state_.x.cols());
  const Eigen::MatrixXd u = scale_to_unit_cube(points, state_.lower, state_.upper);
  const Eigen::Index p = u.cols();
  const Eigen::VectorXd du_dx = 2.0 / (state_.upper - state_.lower).array();
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(u.rows(), p);
  for (Eigen::Index i = 0; i < u.rows(); ++i)
    for (std::size_t t = 0; t < state_.terms.size(); ++t) {
      const auto& e = state_.terms[t];
      const double c = state_.coefficients(static_cast<Eigen::Index>(t));
      for (Eigen::Index j = 0; j < p; ++j) {
        const int ej = e[static_cast<std::size_t>(j)];
        if (ej == 0) continue;
        double v = c * ej * ipow(u(i, j), ej - 1);
        for (Eigen::Index k = 0; k < p; ++k)
          if (k != j) v *= ipow(u(i, k), e[static_cast<std::size_t>(k)]);
        g(i, j) += v * du_dx(j);
      }
    }
  return g;
}

LeaveOneOut PolynomialSurface::leave_one_out() const {
  const Eigen::Index n = state_.y.size();
  const auto m = static_cast<double>(state_.terms.size());
  const Eigen::VectorXd e = state_.y - scaled_design(state_.x) * state_.coefficients;
  const double sse = e.squaredNorm();
  const double dof = static_cast<double>(n) - m;
  LeaveOneOut loo;
  loo.observed = state_.y;
  loo.mean.resize(n);
  loo.variance.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double one_minus_h = 1.0 - state_.hat_diagonal(i);
    if (one_minus_h <= 1e-12) {  // the other points cannot determine the fit at x_i
      loo.mean(i) = kNaN;
      loo.variance(i) = kInf;
      continue;
    }
    const double loo_residual = e(i) / one_minus_h;
    loo.mean(i) = state_.y(i) - loo_residual;
    // Deleted residual variance: SSE without point i is SSE - e_i² / (1 - h_ii).
    const double s2_deleted =
        dof > 1.0 ? std::max(0.0, (sse - e(i) * e(i) / one_minus_h) / (dof - 1.0)) : kNaN;
    loo.variance(i) = s2_deleted / one_minus_h;
  }
  return loo;
}

DegreeSelection select_polynomial_degree(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                         const PolynomialOptions& base,
                                         const DegreeSelectionOptions& options) {
  check_degree(options.min_degree, "min_degree");
  check_degree(options.max_degree, "max_degree");
  if (options.min_degree > options.max_degree)
    throw std::invalid_argument(kWho + ": min_degree exceeds max_degree");
  const auto names = detail::resolve_input_names(kWho, base.input_names, x.cols());
  detail::check_training_table(kWho, x, y, names);
  auto [lo, hi] = detail::resolve_box(kWho, x, base.lower, base.upper, names);
  const Eigen::Index n = x.rows();
  std::vector<int> folds;
  if (options.method == CrossValidationMethod::k_fold) {
    if (options.folds < 2 || options.folds > n)
      throw std::invalid_argument(kWho + ": folds must be in 2.." + std::to_string(n) + ", got " +
                                  std::to_string(options.folds));
    folds = k_fold_assignment(static_cast<std::size_t>(n), options.folds, options.seed);
  }
  const Eigen::MatrixXd u = scale_to_unit_cube(x, lo, hi);

  std::vector<int> degrees;
  std::vector<double> mse, mse_se, cv_rmse;
  for (int d = options.min_degree; d <= options.max_degree; ++d) {
    const auto terms = PolynomialSurface::total_degree_terms(d, static_cast<int>(x.cols()));
    const auto m = static_cast<Eigen::Index>(terms.size());
    if (m > n - 1) break;  // higher degrees have even more terms
    const Eigen::MatrixXd X = design_matrix(u, terms);
    Eigen::VectorXd err2 = Eigen::VectorXd::Constant(n, kInf);
    if (options.method == CrossValidationMethod::leave_one_out) {
      if (auto ls = least_squares(X, y)) {
        const Eigen::VectorXd e = y - X * ls->beta;
        for (Eigen::Index i = 0; i < n; ++i) {
          const double one_minus_h = 1.0 - ls->hat_diagonal(i);
          if (one_minus_h > 1e-12) err2(i) = std::pow(e(i) / one_minus_h, 2);
        }
      }
    } else {
      for (int f = 0; f < options.folds; ++f) {
        std::vector<Eigen::Index> train, test;
        for (Eigen::Index i = 0; i < n; ++i)
          (folds[static_cast<std::size_t>(i)] == f ? test : train).push_back(i);
        const auto ls = least_squares(X(train, Eigen::all), y(train));
        if (!ls) continue;  // this fold's errors stay infinite
        const Eigen::VectorXd e = y(test) - X(test, Eigen::all) * ls->beta;
        for (std::size_t k = 0; k < test.size(); ++k)
          err2(test[k]) = e(static_cast<Eigen::Index>(k)) * e(static_cast<Eigen::Index>(k));
      }
    }
    const bool finite = err2.allFinite();
    mse.push_back(finite ? err2.mean() : kInf);
    mse_se.push_back(finite ? standard_error_of_mean(err2) : kInf);
    degrees.push_back(d);
    cv_rmse.push_back(std::sqrt(mse.back()));
  }
  if (degrees.empty())
    throw std::invalid_argument(kWho + ": " + std::to_string(n) +
                                " points are too few for degree " +
                                std::to_string(options.min_degree));
  const auto best = static_cast<std::size_t>(std::min_element(mse.begin(), mse.end()) - mse.begin());
  if (!std::isfinite(mse[best]))
    throw std::invalid_argument(kWho + ": no degree in " + std::to_string(options.min_degree) +
                                ".." + std::to_string(options.max_degree) +
                                " can be fitted: every design matrix (or fold) is rank deficient");
  std::size_t chosen = best;
  if (options.one_standard_error_rule)
    for (std::size_t k = 0; k < best; ++k)
      if (mse[k] <= mse[best] + mse_se[best]) {
        chosen = k;
        break;
      }
  PolynomialOptions opts = base;
  opts.terms.clear();
  opts.degree = degrees[chosen];
  opts.lower.assign(lo.data(), lo.data() + lo.size());
  opts.upper.assign(hi.data(), hi.data() + hi.size());
  return DegreeSelection{degrees[chosen], degrees, cv_rmse, mse_se,
                         PolynomialSurface::fit(x, y, opts)};
}

}  // namespace demcal::surrogate
