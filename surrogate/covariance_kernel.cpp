#include "surrogate/covariance_kernel.hpp"

#include <cmath>
#include <stdexcept>

namespace demcal::surrogate {
namespace {
const double kSqrt5 = std::sqrt(5.0);
}

std::string to_string(CovarianceKernel kernel) {
  switch (kernel) {
    case CovarianceKernel::matern52: return "matern52";
    case CovarianceKernel::squared_exponential: return "squared_exponential";
  }
  throw std::invalid_argument("covariance kernel: unknown enumerator");
}

CovarianceKernel covariance_kernel_from_string(const std::string& name) {
  if (name == "matern52") return CovarianceKernel::matern52;
  if (name == "squared_exponential") return CovarianceKernel::squared_exponential;
  throw std::invalid_argument("covariance kernel: unknown kernel '" + name +
                              "' (expected matern52 or squared_exponential)");
}

double kernel_correlation(CovarianceKernel kernel, double r) {
  switch (kernel) {
    case CovarianceKernel::matern52:
      return (1.0 + kSqrt5 * r + 5.0 / 3.0 * r * r) * std::exp(-kSqrt5 * r);
    case CovarianceKernel::squared_exponential: return std::exp(-0.5 * r * r);
  }
  throw std::invalid_argument("covariance kernel: unknown enumerator");
}

double kernel_radial_factor(CovarianceKernel kernel, double r) {
  switch (kernel) {
    case CovarianceKernel::matern52: return 5.0 / 3.0 * (1.0 + kSqrt5 * r) * std::exp(-kSqrt5 * r);
    case CovarianceKernel::squared_exponential: return std::exp(-0.5 * r * r);
  }
  throw std::invalid_argument("covariance kernel: unknown enumerator");
}

}  // namespace demcal::surrogate
