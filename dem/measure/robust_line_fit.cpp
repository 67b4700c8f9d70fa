#include "dem/measure/robust_line_fit.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace demcal::dem {
namespace {

double median_of(std::vector<double> v) {
  const std::size_t n = v.size();
  const std::size_t mid = n / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  const double upper = v[mid];
  if (n % 2 == 1) return upper;
  const double lower = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid));
  return 0.5 * (lower + upper);
}

// 1 / Phi^-1(3/4): makes the MAD an unbiased sigma for normal residuals.
constexpr double kMadToSigma = 1.0 / 0.6744897501960817;

}  // namespace

LineFit fit_line_weighted(std::span<const double> x, std::span<const double> y,
                          std::span<const double> w) {
  if (x.size() != y.size() || x.size() != w.size())
    throw std::invalid_argument("line fit: x, y and weights must have the same length");
  // Centring on the weighted mean keeps the normal equations well conditioned
  // when x sits far from the origin (a pile away from x = 0).
  double sw = 0.0, swx = 0.0, swy = 0.0;
  std::size_t carrying = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(w[i] > 0.0)) continue;
    ++carrying;
    sw += w[i];
    swx += w[i] * x[i];
    swy += w[i] * y[i];
  }
  if (carrying < 2)
    throw std::invalid_argument("line fit: fewer than two points carry weight (" +
                                std::to_string(carrying) + ")");
  const double xm = swx / sw;
  const double ym = swy / sw;
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(w[i] > 0.0)) continue;
    sxx += w[i] * (x[i] - xm) * (x[i] - xm);
    sxy += w[i] * (x[i] - xm) * (y[i] - ym);
  }
  if (!(sxx > 0.0)) throw std::invalid_argument("line fit: all weighted x values coincide");

  LineFit fit;
  fit.slope = sxy / sxx;
  fit.intercept = ym - fit.slope * xm;
  double swrr = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(w[i] > 0.0)) continue;
    const double r = y[i] - fit.intercept - fit.slope * x[i];
    swrr += w[i] * r * r;
  }
  // The weight sum is the effective number of points; with bisquare weights
  // it can dip below 3 on tiny data sets, and one degree of freedom is the
  // least that keeps the variance finite and honest-sized.
  const double dof = std::max(sw - 2.0, 1.0);
  const double sigma2 = swrr / dof;
  fit.slope_std_error = std::sqrt(sigma2 / sxx);
  fit.intercept_std_error = std::sqrt(sigma2 * (1.0 / sw + xm * xm / sxx));
  fit.weights.assign(w.begin(), w.end());
  fit.rejected = static_cast<std::size_t>(
      std::count_if(w.begin(), w.end(), [](double v) { return !(v > 0.0); }));
  fit.converged = true;
  return fit;
}

LineFit fit_line_bisquare(std::span<const double> x, std::span<const double> y,
                          const RobustLineFitOptions& options) {
  if (x.size() != y.size())
    throw std::invalid_argument("robust line fit: x and y must have the same length");
  if (x.size() < 3)
    throw std::invalid_argument("robust line fit: needs at least 3 points (got " +
                                std::to_string(x.size()) + ")");
  if (!(options.tuning_constant > 0.0) || options.max_iterations < 1)
    throw std::invalid_argument(
        "robust line fit: tuning_constant and max_iterations must be positive");

  const std::size_t n = x.size();
  std::vector<double> w(n, 1.0);
  LineFit fit = fit_line_weighted(x, y, w);

  // Residuals far below the data's own magnitude are rounding, not spread; a
  // scale that small would reject every point that is not exactly on a line.
  double y_span = 0.0;
  for (std::size_t i = 0; i < n; ++i) y_span = std::max(y_span, std::abs(y[i] - y[0]));
  const double negligible_scale = 1e-12 * (y_span + std::abs(y[0]));

  std::vector<double> r(n), abs_r(n);
  double scale = 0.0;
  fit.converged = false;
  for (int it = 1; it <= options.max_iterations; ++it) {
    for (std::size_t i = 0; i < n; ++i) {
      r[i] = y[i] - fit.intercept - fit.slope * x[i];
      abs_r[i] = std::abs(r[i]);
    }
    scale = kMadToSigma * median_of(abs_r);
    if (!(scale > negligible_scale)) {
      // At least half the points lie on the line already: nothing to reweight.
      fit.iterations = it - 1;
      fit.converged = true;
      break;
    }
    const double cut = options.tuning_constant * scale;
    for (std::size_t i = 0; i < n; ++i) {
      const double u = r[i] / cut;
      w[i] = std::abs(u) < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
    }
    LineFit next = fit_line_weighted(x, y, w);
    const bool settled = std::abs(next.slope - fit.slope) <=
                             options.relative_tolerance * (1.0 + std::abs(fit.slope)) &&
                         std::abs(next.intercept - fit.intercept) <=
                             options.relative_tolerance * (1.0 + std::abs(fit.intercept));
    fit = std::move(next);
    fit.iterations = it;
    fit.converged = settled;
    if (settled) break;
  }
  fit.residual_scale = scale;
  if (fit.weights.size() != n) fit.weights.assign(n, 1.0);
  return fit;
}

}  // namespace demcal::dem
