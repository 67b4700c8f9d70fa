#pragma once
// The probability that a Gaussian vector lies in a box, in log form: the mass a uniform prior
// on the box keeps of a linear-Gaussian posterior, which the evidence of a linearized model
// must carry when the posterior's centre lies near or beyond a bound (calibrate/
// model_discrepancy.cpp). Accurate far into the tails (log masses of -1e4 and below), where
// the mass itself underflows.
//
// Method: the first coordinate's mass is exact; the rest, conditioned on it, is integrated
// over its restricted law in that law's quantile by Gauss-Legendre (48 nodes a coordinate),
// recursively. Exact in one dimension; for two or three coordinates its error is below 1e-3
// of the log mass in the tests (grid quadrature, correlations up to 0.95). A first version used
// Mendell & Elston's (1974) sequential approximation, which was off by 0.18 in log mass for a
// correlation of -0.95 at a corner (17 % of the mass); it was replaced before use.

#include <Eigen/Core>

#include <vector>

namespace demcal::calibrate::detail {

// log P(lower <= x <= upper) for x ~ N(mean, covariance). Throws std::invalid_argument when
// the sizes differ, a lower bound is not below its upper one, or a variance is not positive.
double log_box_probability(const Eigen::VectorXd& mean, const Eigen::MatrixXd& covariance,
                           const std::vector<double>& lower, const std::vector<double>& upper);

// log P(a <= z <= b) for a standard normal z, a < b (either may be infinite).
double log_standard_normal_mass(double a, double b);

}  // namespace demcal::calibrate::detail
