#include "surrogate/cross_validation.hpp"

#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>

namespace demcal::surrogate {

ValidationMetrics validation_metrics(const LeaveOneOut& loo) {
  const Eigen::Index n = loo.observed.size();
  if (n == 0) throw std::invalid_argument("validation metrics: no leave-one-out predictions");
  if (loo.mean.size() != n || loo.variance.size() != n)
    throw std::invalid_argument("validation metrics: observed, mean and variance differ in size (" +
                                std::to_string(n) + ", " + std::to_string(loo.mean.size()) + ", " +
                                std::to_string(loo.variance.size()) + ")");
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  constexpr double inf = std::numeric_limits<double>::infinity();
  ValidationMetrics m;
  m.standardized_residuals.resize(n);
  double press = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    // A point the model cannot predict without itself counts as an infinite error.
    const double r = std::isfinite(loo.mean(i)) ? loo.observed(i) - loo.mean(i) : inf;
    press += r * r;
    const double v = loo.variance(i);
    m.standardized_residuals(i) = (v > 0.0 && std::isfinite(v) && std::isfinite(r)) ? r / std::sqrt(v) : nan;
    if (std::isfinite(m.standardized_residuals(i)))
      m.max_abs_standardized_residual =
          std::max(m.max_abs_standardized_residual, std::abs(m.standardized_residuals(i)));
  }
  const double ss_tot = (loo.observed.array() - loo.observed.mean()).square().sum();
  m.press = press;
  m.q_squared = ss_tot > 0.0 ? 1.0 - press / ss_tot : nan;
  m.rmse = std::sqrt(press / static_cast<double>(n));
  return m;
}

ScatterCheck check_against_scatter(double loo_rmse, double run_to_run_sd,
                                   const std::string& output_name, int replicates_per_point,
                                   int scatter_degrees_of_freedom) {
  const std::string who = "scatter check for '" + output_name + "'";
  if (!(loo_rmse >= 0.0))
    throw std::invalid_argument(who + ": loo_rmse must be >= 0 and not NaN");
  if (!(run_to_run_sd >= 0.0) || !std::isfinite(run_to_run_sd))
    throw std::invalid_argument(who + ": run_to_run_sd must be finite and >= 0");
  if (replicates_per_point < 1)
    throw std::invalid_argument(who + ": replicates_per_point must be >= 1");
  if (scatter_degrees_of_freedom < 0)
    throw std::invalid_argument(who + ": scatter_degrees_of_freedom must be >= 0");
  const double noise_var = run_to_run_sd * run_to_run_sd / replicates_per_point;
  ScatterCheck c;
  c.surrogate_error = std::sqrt(std::max(0.0, loo_rmse * loo_rmse - noise_var));
  const double nu = scatter_degrees_of_freedom;
  c.scatter_bound = scatter_degrees_of_freedom > 0
                        ? run_to_run_sd * std::sqrt(nu / gsl_cdf_chisq_Pinv(0.05, nu))
                        : run_to_run_sd;
  c.within_scatter = c.surrogate_error <= c.scatter_bound;
  char bound[160] = "";
  if (scatter_degrees_of_freedom > 0)
    std::snprintf(bound, sizeof bound,
                  " (from %d degrees of freedom: at most %.4g at 95 %% confidence)",
                  scatter_degrees_of_freedom, c.scatter_bound);
  char buf[480];
  std::snprintf(buf, sizeof buf,
                "surrogate for '%s': leave-one-out RMSE %.4g, of which %.4g is surrogate error "
                "after removing the noise of %d-run means; DEM run-to-run scatter %.4g%s%s",
                output_name.c_str(), loo_rmse, c.surrogate_error, replicates_per_point,
                run_to_run_sd, bound,
                c.within_scatter ? ""
                                 : ": the surrogate is worse than rerunning the DEM (add design "
                                   "points or change the model)");
  c.message = buf;
  return c;
}

std::vector<int> k_fold_assignment(std::size_t n, int folds, std::uint64_t seed) {
  if (folds < 2 || static_cast<std::size_t>(folds) > n)
    throw std::invalid_argument("k-fold assignment: folds must be in 2.." + std::to_string(n) +
                                ", got " + std::to_string(folds));
  std::vector<int> fold(n);
  for (std::size_t i = 0; i < n; ++i) fold[i] = static_cast<int>(i % static_cast<std::size_t>(folds));
  // Fisher-Yates with mt19937_64 drawn directly: std::shuffle and the standard
  // distributions are implementation-defined, the raw engine output is not.
  std::mt19937_64 rng(seed);
  for (std::size_t i = n; i-- > 1;) {
    const std::size_t j = static_cast<std::size_t>(rng() % (i + 1));
    std::swap(fold[i], fold[j]);
  }
  return fold;
}

}  // namespace demcal::surrogate
