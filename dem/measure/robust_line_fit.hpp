#pragma once
// A straight line y = intercept + slope * x fitted so that a few wild points
// cannot drag it: iteratively reweighted least squares with Tukey's bisquare
// weights, started from ordinary least squares. A pile's surface profile has
// exactly such points — a grain perched on the slope, a gap left by one that
// rolled off — and plain least squares would tilt the slope toward them.
//
// Each iteration rescales the residuals by a robust spread, MAD / 0.6745 (the
// normal-consistent median absolute deviation), so the rejection threshold
// follows the data's own roughness instead of an absolute tolerance that would
// have to be tuned per particle size.

#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace demcal::dem {

struct RobustLineFitOptions {
  // Bisquare cut-off in robust standard deviations: points beyond it get zero
  // weight. 4.685 gives 95 % of least squares' efficiency on normal noise,
  // the textbook compromise between efficiency and resistance.
  double tuning_constant = 4.685;
  int max_iterations = 100;
  // Converged when neither coefficient moves by more than this times
  // (1 + its magnitude) between iterations.
  double relative_tolerance = 1e-10;
};

struct LineFit {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  double intercept = kNaN;
  double slope = kNaN;
  // From the weighted-least-squares covariance at the final weights:
  // sigma^2 = sum(w r^2) / (sum(w) - 2), var(slope) = sigma^2 / sum(w (x - xw)^2).
  // Treating the converged weights as fixed is the usual IRLS approximation;
  // it ignores the (small) randomness of the weights themselves.
  double slope_std_error = kNaN;
  double intercept_std_error = kNaN;
  // Robust residual spread (MAD / 0.6745) at the final iteration; 0 for OLS.
  double residual_scale = 0.0;
  std::vector<double> weights;  // one per input point, in [0, 1]
  std::size_t rejected = 0;     // points with zero weight
  int iterations = 0;
  bool converged = false;
};

// Weighted least squares with the given weights (all 1: ordinary least
// squares). Throws std::invalid_argument when fewer than two points carry
// weight or their x values coincide.
LineFit fit_line_weighted(std::span<const double> x, std::span<const double> y,
                          std::span<const double> w);

// The robust fit. Needs at least 3 points with distinct x (with 2 the line
// passes through both and there is nothing to reweight); throws
// std::invalid_argument otherwise.
LineFit fit_line_bisquare(std::span<const double> x, std::span<const double> y,
                          const RobustLineFitOptions& options = {});

}  // namespace demcal::dem
