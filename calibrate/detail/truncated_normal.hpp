#pragma once
// A normal distribution N(mean, sd^2) restricted to [lower, upper]: what a
// Gaussian (Laplace) posterior becomes under a uniform prior on a bounded
// parameter. Its mean and quantiles always lie inside the bounds, so an
// estimate is never reported outside its own interval, as a clipped
// Gaussian's could be (mean 1.65, interval clipped to 1.08-1.10).
//
// Accurate far into the tails: when the bounds lie on one side of the mean the
// upper-tail functions are used, and when even they underflow (the bounds more
// than ~37 sd away) the tail's exponential limit is: beyond a bound at distance
// d from the mean the mass decays at rate d / sd^2, so the mean is the bound
// plus sd^2 / d (the Mills-ratio asymptote).

namespace demcal::calibrate::detail {

class TruncatedNormal {
 public:
  // Requires sd >= 0 and lower < upper (std::invalid_argument otherwise).
  // sd = 0 is the point mass at mean clamped to the bounds.
  TruncatedNormal(double mean, double sd, double lower, double upper);

  double mean() const;
  // The q-quantile, q in [0, 1].
  double quantile(double q) const;

 private:
  // Bounds wholly below the mean are mirrored to lie wholly above it, where
  // the upper-tail functions are accurate; the results are mirrored back.
  bool mirrored_ = false;
  double mean_ = 0.0, sd_ = 0.0, lower_ = 0.0, upper_ = 0.0;
  double alpha_ = 0.0, beta_ = 0.0;  // standardized bounds
  double mass_ = 0.0;                // probability of [lower, upper] (0 when it underflows)
  double mean_std() const;           // mean in standardized units, mirrored frame
  double quantile_std(double q) const;
};

}  // namespace demcal::calibrate::detail
