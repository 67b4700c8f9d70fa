#pragma once
// Variance-based sensitivity: which inputs the output depends on, alone (first order) and
// with all their interactions (total), for independent uniform inputs over a box. Used to
// show e.g. that the angle of repose barely informs one friction coefficient.

#include "surrogate/surrogate_model.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace demcal::surrogate {

enum class SobolSampling {
  sobol_sequence,  // GSL's Sobol sequence (at most 20 inputs); converges ~1/N
  pseudo_random,   // GSL's Mersenne Twister seeded with `seed`; converges ~1/sqrt(N)
};

struct SobolOptions {
  std::size_t base_samples = 8192;  // N; the function is evaluated N (p + 2) times
  SobolSampling sampling = SobolSampling::sobol_sequence;
  std::uint64_t seed = 1;  // pseudo-random base samples and bootstrap resampling
  int bootstrap_resamples = 0;  // 0: no confidence intervals
  double confidence_level = 0.95;
};

struct SobolIndices {
  std::vector<double> first_order;  // Saltelli (2010) estimator, one per input
  std::vector<double> total;        // Jansen (1999) estimator, one per input
  // Percentile bootstrap intervals over the N base rows; empty without bootstrap.
  std::vector<double> first_order_lower, first_order_upper;
  std::vector<double> total_lower, total_upper;
  double mean = 0.0;      // of the output over the box
  double variance = 0.0;  // of the output over the box
  std::size_t evaluations = 0;
};

// f evaluated at single points.
using PointFunction = std::function<double(std::span<const double>)>;
// f evaluated at many points at once (rows), returning one value per row: lets a surrogate
// predict in blocks.
using BatchFunction = std::function<Eigen::VectorXd(const Eigen::MatrixXd&)>;

// Throws std::invalid_argument naming the problem: bounds of different sizes, empty or
// inverted, too few base samples, more than 20 inputs with the Sobol sequence, a
// confidence level outside (0, 1), zero output variance, or f returning a non-finite value.
SobolIndices sobol_indices(const PointFunction& f, const std::vector<double>& lower,
                           const std::vector<double>& upper, const SobolOptions& options = {});
SobolIndices sobol_indices_batch(const BatchFunction& f, const std::vector<double>& lower,
                                 const std::vector<double>& upper,
                                 const SobolOptions& options = {});
// Of a surrogate's predicted mean.
SobolIndices sobol_indices(const SurrogateModel& model, const std::vector<double>& lower,
                           const std::vector<double>& upper, const SobolOptions& options = {});

}  // namespace demcal::surrogate
