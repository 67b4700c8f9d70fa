#pragma once
// Posterior sampling: adaptive Metropolis (Haario, Saksman & Tamminen 2001, Bernoulli 7:
// 223-242) on CalibrationProblem::log_posterior, i.e. a uniform prior inside the bounds
// and a Gaussian likelihood with sigma_total(theta). Deterministic for a seed (GSL MT19937).
//
// The proposal is Gaussian in bound-scaled units: for the first 500 steps of a chain its
// covariance is 2.38^2/p (J^T J + 100 I)^-1 with J the Jacobian at the start (the 100 I
// keeps weak directions at a tenth of the box), afterwards 2.38^2/p times the chain's
// running covariance plus 1e-10 I, updated every step as in the paper. Proposals outside
// the bounds are rejected. Chains do not cross between separated minima: with several minima
// the pooled samples weigh each by its number of chains, not by its posterior mass.

#include "calibrate/calibration_problem.hpp"
#include "calibrate/confidence_region.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace demcal::calibrate {

struct MarginalPosterior {
  std::string name;
  double mean = 0.0, sd = 0.0;
  // Equal-tailed interval at the options' confidence: the (1 - c)/2 and (1 + c)/2
  // quantiles (2.5 % and 97.5 % at 0.95).
  double lower = 0.0, median = 0.0, upper = 0.0;
  // Sum over chains of n / integrated autocorrelation time (Geyer's initial positive
  // sequence).
  double effective_sample_size = 0.0;
  // Gelman-Rubin potential scale reduction over the chains; NaN with one chain.
  double r_hat = 0.0;
  std::vector<double> histogram_edges;    // histogram_bins + 1, over the samples' range
  std::vector<double> histogram_density;  // histogram_bins, integrates to 1
};

// Highest-posterior-density region on the likelihood region's grid. Its level is the
// (1 - confidence) quantile of the samples' log posterior, so the region holds
// `confidence` of the samples; the nodes inside are those whose log posterior reaches the
// level. (A histogram of 20000 samples over 121^2 cells would be mostly empty cells.)
struct CredibleRegion {
  bool available = false;
  double log_posterior_level = 0.0;
  std::vector<bool> inside;  // per node, LikelihoodRegion layout
  std::size_t nodes_inside = 0;
  double area = 0.0;  // parameter units, as LikelihoodRegion::area
};

struct PosteriorSummary {
  bool available = false;  // false when options.mcmc_samples == 0
  // Kept samples, chain after chain (rows), parameters (columns), and their log posterior.
  Eigen::MatrixXd samples;
  Eigen::VectorXd log_posterior;
  int chains = 0;
  int samples_per_chain = 0;
  double acceptance_rate = 0.0;  // of the kept steps, over all chains
  Eigen::VectorXd mean;
  Eigen::MatrixXd covariance;  // sample covariance, parameter units
  std::vector<MarginalPosterior> marginals;
  CredibleRegion credible_region;
};

// Chain k starts at starts[k % starts.size()] (inside the bounds); each runs
// options.mcmc_burn_in + options.mcmc_samples / options.mcmc_chains steps. The credible
// region is filled when `grid` is available. Throws std::invalid_argument when starts is
// empty or a start lies outside the bounds.
PosteriorSummary sample_posterior(const CalibrationProblem& problem,
                                  const std::vector<Eigen::VectorXd>& starts,
                                  const CalibrationOptions& options,
                                  const LikelihoodRegion* grid = nullptr);

// HPD region of `posterior` on `grid` (see CredibleRegion).
CredibleRegion credible_region(const PosteriorSummary& posterior, const LikelihoodRegion& grid,
                               double confidence);

}  // namespace demcal::calibrate
