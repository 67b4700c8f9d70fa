#include "calibrate/detail/box_probability.hpp"

#include "calibrate/detail/truncated_normal.hpp"

#include <gsl/gsl_integration.h>
#include <gsl/gsl_sf_erf.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace demcal::calibrate::detail {

namespace {

// log of the upper tail Q(x) = P(z > x), accurate for large x (GSL's log erfc).
double log_q(double x) {
  if (x == std::numeric_limits<double>::infinity()) return -std::numeric_limits<double>::infinity();
  if (x == -std::numeric_limits<double>::infinity()) return 0.0;
  return gsl_sf_log_erfc(x / std::numbers::sqrt2) - std::numbers::ln2;
}

// log(e^u - e^v) for u >= v.
double log_diff_exp(double u, double v) {
  if (v == -std::numeric_limits<double>::infinity()) return u;
  return u + std::log1p(-std::exp(v - u));
}

// Gauss-Legendre nodes per conditioned coordinate: p coordinates cost 48^(p-1) one-dimensional
// masses (2 304 for the three parameters of a candidate's fit).
constexpr std::size_t kQuadratureNodes = 48;

}  // namespace

double log_standard_normal_mass(double a, double b) {
  if (!(a < b)) throw std::invalid_argument("log_standard_normal_mass: needs a < b");
  // Mirror so that the interval is not wholly below 0, where the upper tails are accurate.
  if (b <= 0.0) return log_standard_normal_mass(-b, -a);
  if (a >= 0.0) return log_diff_exp(log_q(a), log_q(b));
  // a < 0 < b: 1 - Q(-a) - Q(b).
  return std::log1p(-std::exp(log_q(-a)) - std::exp(log_q(b)));
}

double log_box_probability(const Eigen::VectorXd& mean, const Eigen::MatrixXd& covariance,
                           const std::vector<double>& lower, const std::vector<double>& upper) {
  const Eigen::Index p = mean.size();
  if (p < 1 || covariance.rows() != p || covariance.cols() != p ||
      lower.size() != static_cast<std::size_t>(p) || upper.size() != static_cast<std::size_t>(p))
    throw std::invalid_argument(
        "log_box_probability: the covariance must be p x p and the bounds have p entries, p = " +
        std::to_string(p));
  for (Eigen::Index i = 0; i < p; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!(lower[k] < upper[k]))
      throw std::invalid_argument("log_box_probability: lower bound " + std::to_string(i) +
                                  " is not below the upper one");
    if (!(covariance(i, i) > 0.0) || !std::isfinite(covariance(i, i)))
      throw std::invalid_argument("log_box_probability: variance " + std::to_string(i) +
                                  " is not positive");
  }
  const double s = std::sqrt(covariance(0, 0));
  const double a = (lower[0] - mean(0)) / s, b = (upper[0] - mean(0)) / s;
  const double log_first = log_standard_normal_mass(a, b);
  if (p == 1) return log_first;
  // The rest given the first coordinate x: Gaussian with mean m_r + c_r0 (x - m_0) / c_00 and
  // covariance C_rr - c_r0 c_0r / c_00. Its box mass is integrated over x distributed as the
  // first coordinate restricted to its interval, in that law's quantile u (uniform on (0, 1)),
  // by Gauss-Legendre: the integrand is then smooth even when the interval lies far in a
  // tail, where the law is near an exponential from the bound.
  const Eigen::Index r = p - 1;
  const Eigen::VectorXd c0 = covariance.col(0).tail(r);
  const Eigen::MatrixXd conditional =
      covariance.bottomRightCorner(r, r) - c0 * c0.transpose() / covariance(0, 0);
  const std::vector<double> rest_lower(lower.begin() + 1, lower.end()),
      rest_upper(upper.begin() + 1, upper.end());
  const TruncatedNormal first(mean(0), s, lower[0], upper[0]);
  gsl_integration_glfixed_table* table = gsl_integration_glfixed_table_alloc(kQuadratureNodes);
  std::vector<double> terms;
  for (std::size_t k = 0; k < kQuadratureNodes; ++k) {
    double u = 0.0, w = 0.0;
    gsl_integration_glfixed_point(0.0, 1.0, k, &u, &w, table);
    const double x = first.quantile(u);
    const Eigen::VectorXd m = mean.tail(r) + c0 * ((x - mean(0)) / covariance(0, 0));
    terms.push_back(std::log(w) + log_box_probability(m, conditional, rest_lower, rest_upper));
  }
  gsl_integration_glfixed_table_free(table);
  const double top = *std::max_element(terms.begin(), terms.end());
  double sum = 0.0;
  for (double t : terms) sum += std::exp(t - top);
  return log_first + top + std::log(sum);
}

}  // namespace demcal::calibrate::detail
