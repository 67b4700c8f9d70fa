#include "calibrate/detail/truncated_normal.hpp"

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace demcal::calibrate::detail {

TruncatedNormal::TruncatedNormal(double mean, double sd, double lower, double upper)
    : mean_(mean), sd_(sd), lower_(lower), upper_(upper) {
  if (!(sd >= 0.0) || !std::isfinite(sd) || !std::isfinite(mean))
    throw std::invalid_argument("TruncatedNormal: the mean must be finite and sd >= 0");
  if (!(lower < upper))
    throw std::invalid_argument("TruncatedNormal: the bounds must satisfy lower < upper");
  if (sd == 0.0) return;
  if (mean > upper) {
    mirrored_ = true;
    mean_ = -mean;
    lower_ = -upper;
    upper_ = -lower;
  }
  alpha_ = (lower_ - mean_) / sd_;
  beta_ = (upper_ - mean_) / sd_;
  mass_ = alpha_ > 0.0 ? gsl_cdf_ugaussian_Q(alpha_) - gsl_cdf_ugaussian_Q(beta_)
                       : gsl_cdf_ugaussian_P(beta_) - gsl_cdf_ugaussian_P(alpha_);
}

double TruncatedNormal::mean_std() const {
  if (mass_ > 0.0)
    return std::clamp((gsl_ran_ugaussian_pdf(alpha_) - gsl_ran_ugaussian_pdf(beta_)) / mass_,
                      alpha_, beta_);
  // The tail beyond alpha >> 1 is exponential with rate alpha.
  return std::min(alpha_ + 1.0 / alpha_, beta_);
}

double TruncatedNormal::quantile_std(double q) const {
  if (mass_ > 0.0) {
    const double x =
        alpha_ > 0.0
            ? gsl_cdf_ugaussian_Qinv(std::max(gsl_cdf_ugaussian_Q(alpha_) - q * mass_, 0.0))
            : gsl_cdf_ugaussian_Pinv(std::min(gsl_cdf_ugaussian_P(alpha_) + q * mass_, 1.0));
    return std::clamp(x, alpha_, beta_);
  }
  return std::min(alpha_ - std::log1p(-std::min(q, 1.0 - 1e-16)) / alpha_, beta_);
}

double TruncatedNormal::mean() const {
  if (sd_ == 0.0) return std::clamp(mean_, lower_, upper_);
  const double x = mean_ + sd_ * mean_std();
  return mirrored_ ? -x : x;
}

double TruncatedNormal::quantile(double q) const {
  if (!(q >= 0.0 && q <= 1.0))
    throw std::invalid_argument("TruncatedNormal::quantile: q must lie in [0, 1]");
  if (sd_ == 0.0) return std::clamp(mean_, lower_, upper_);
  return mirrored_ ? -(mean_ + sd_ * quantile_std(1.0 - q)) : mean_ + sd_ * quantile_std(q);
}

}  // namespace demcal::calibrate::detail
