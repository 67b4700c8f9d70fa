#include "surrogate/scatter_trend.hpp"

#include <gsl/gsl_cdf.h>
#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace demcal::surrogate {
namespace {

// The log-likelihood of the sample variances given log sigma^2 per point, up to a constant.
double log_likelihood(const Eigen::VectorXd& s2, const Eigen::VectorXd& half_nu,
                      const Eigen::VectorXd& log_sigma2) {
  double l = 0.0;
  for (Eigen::Index k = 0; k < s2.size(); ++k)
    l -= half_nu(k) * (s2(k) * std::exp(-log_sigma2(k)) + log_sigma2(k));
  return l;
}

}  // namespace

ScatterTrend fit_scatter_trend(const Eigen::MatrixXd& x_unit,
                               const Eigen::VectorXd& sample_variance,
                               const Eigen::VectorXi& degrees_of_freedom) {
  const Eigen::Index n = sample_variance.size();
  if (x_unit.rows() != n || degrees_of_freedom.size() != n)
    throw std::invalid_argument(
        "scatter trend: x_unit, sample_variance and degrees_of_freedom differ in length");
  for (Eigen::Index k = 0; k < n; ++k) {
    if (!(sample_variance(k) >= 0.0) || !std::isfinite(sample_variance(k)))
      throw std::invalid_argument("scatter trend: sample_variance must be finite and >= 0");
    if (degrees_of_freedom(k) < 1)
      throw std::invalid_argument("scatter trend: degrees_of_freedom must be >= 1");
    if (!x_unit.row(k).allFinite())
      throw std::invalid_argument("scatter trend: x_unit must be finite");
  }
  const Eigen::Index p = x_unit.cols();
  ScatterTrend t;
  t.points = static_cast<int>(n);
  t.degrees_of_freedom = static_cast<int>(p);
  const Eigen::VectorXd half_nu = degrees_of_freedom.cast<double>() / 2.0;
  const double pooled = half_nu.dot(sample_variance) / half_nu.sum();
  if (n <= p + 1 || !(pooled > 0.0)) return t;

  Eigen::MatrixXd X(n, p + 1);
  X.col(0).setOnes();
  X.rightCols(p) = x_unit;
  // Fisher information of b: X^T diag(nu / 2) X, the same at every b.
  const Eigen::MatrixXd info = X.transpose() * half_nu.asDiagonal() * X;
  const Eigen::LDLT<Eigen::MatrixXd> solve(info);
  if (solve.info() != Eigen::Success || solve.rcond() < 1e-12) return t;

  Eigen::VectorXd b = Eigen::VectorXd::Zero(p + 1);
  b(0) = std::log(pooled);
  Eigen::VectorXd eta = X * b;
  double l = log_likelihood(sample_variance, half_nu, eta);
  const double l_constant = l;  // b = (log pooled, 0, ...) is the constant model's optimum
  for (int iteration = 0; iteration < 100; ++iteration) {
    Eigen::VectorXd score(p + 1);
    score.setZero();
    for (Eigen::Index k = 0; k < n; ++k)
      score += half_nu(k) * (sample_variance(k) * std::exp(-eta(k)) - 1.0) * X.row(k).transpose();
    Eigen::VectorXd step = solve.solve(score);
    // Halve a step that does not raise the likelihood (a zero sample variance pulls its
    // point's sigma towards zero without bound; the halving keeps the ascent monotone).
    double l_new = -std::numeric_limits<double>::infinity();
    Eigen::VectorXd eta_new;
    for (int halving = 0; halving < 30; ++halving) {
      eta_new = X * (b + step);
      l_new = log_likelihood(sample_variance, half_nu, eta_new);
      if (l_new >= l) break;
      step /= 2.0;
    }
    if (!(l_new >= l)) break;
    b += step;
    eta = eta_new;
    const double gain = l_new - l;
    l = l_new;
    if (gain < 1e-10 * (1.0 + std::abs(l))) break;
  }
  t.tested = true;
  t.log_variance_coefficients.assign(b.data(), b.data() + b.size());
  t.likelihood_ratio = std::max(0.0, 2.0 * (l - l_constant));
  t.p_value = gsl_cdf_chisq_Q(t.likelihood_ratio, static_cast<double>(p));
  t.sd_smallest = std::exp(0.5 * eta.minCoeff());
  t.sd_largest = std::exp(0.5 * eta.maxCoeff());
  return t;
}

std::string describe(const ScatterTrend& trend, double alpha) {
  char buf[320];
  if (!trend.tested) {
    std::snprintf(buf, sizeof buf,
                  "whether the scatter changes over the inputs is not tested (%d replicated "
                  "points, more than %d needed, and a scatter above zero)",
                  trend.points, trend.degrees_of_freedom + 1);
  } else if (trend.p_value < alpha) {
    std::snprintf(buf, sizeof buf,
                  "the scatter changes over the inputs (p = %.2g against a constant scatter, "
                  "%d replicated points): fitted sd from %.4g to %.4g at the replicated points, "
                  "so the pooled scatter holds nowhere in particular",
                  trend.p_value, trend.points, trend.sd_smallest, trend.sd_largest);
  } else {
    std::snprintf(buf, sizeof buf,
                  "no change of the scatter over the inputs is detected (p = %.2g, %d "
                  "replicated points)",
                  trend.p_value, trend.points);
  }
  return buf;
}

}  // namespace demcal::surrogate
