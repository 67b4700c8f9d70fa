#pragma once
// Stationary correlation functions of the Gaussian process, written in the scaled distance
// r = sqrt(sum_j (d_j / l_j)^2) so that one length scale per input (automatic relevance)
// costs nothing extra.

#include <string>

namespace demcal::surrogate {

enum class CovarianceKernel {
  matern52,             // twice differentiable: the usual choice for physical responses
  squared_exponential,  // infinitely smooth; ill-conditioned for dense designs
};

// "matern52" / "squared_exponential"; the parser throws std::invalid_argument naming the
// unknown value.
std::string to_string(CovarianceKernel kernel);
CovarianceKernel covariance_kernel_from_string(const std::string& name);

// Correlation rho(r), 1 at r = 0.
double kernel_correlation(CovarianceKernel kernel, double r);

// g(r) = -(1/r) d rho / dr, finite at r = 0. Both derivatives the GP needs follow from it:
// d rho / d d_j = -g(r) d_j / l_j^2 and d rho / d log l_j = g(r) d_j^2 / l_j^2.
double kernel_radial_factor(CovarianceKernel kernel, double r);

}  // namespace demcal::surrogate
