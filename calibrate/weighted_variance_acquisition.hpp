#pragma once
// Where the next runs of an adaptive design go: the points whose runs would most reduce the
// surrogates' variance where the recordings put the parameters (docs/adaptive_design.md).
//
//   w(g)      posterior weight of grid node g: exp(log_posterior(g)), normalized, with the
//             current surrogates (their variance included, so an unsure surrogate spreads
//             the weight and the design explores)
//   s_i^2     target i's noise variance, sigma_measured^2 + sigma_dem^2
//   V_i(g)    surrogate i's predictive variance at g
//   V_i(g|x)  the same after a run at x (noise: one run's replicate variance)
//
//   a(x) = sum_g w(g) sum_i [V_i(g) - V_i(g|x)] / s_i^2
//
// the expected drop of the posterior-weighted integrated variance of the standardized
// residuals (a weighted IMSE, Sacks et al. 1989; with posterior weights as in Sürer, Plumlee
// & Wild 2024). V_i(g|x) does not depend on the value the run will return, so the batch rule
// is the kriging believer (Ginsbourger, Le Riche & Carraro 2010): after choosing x_1, each
// GP is refitted with (x_1, its predicted mean) and the same hyperparameters, and x_2 is the
// maximizer of a(x) under the refitted GPs, and so on. The weights are kept for the whole
// batch: the believed values leave every predicted mean where it was.

#include "calibrate/adaptive_design_options.hpp"
#include "calibrate/calibration_problem.hpp"

#include <Eigen/Core>

#include <vector>

namespace demcal::calibrate {

// The nodes that carry the posterior: the acquisition grid's nodes by decreasing weight
// until 99.9 % of the weight or options.integration_points nodes, weights renormalized.
struct PosteriorWeights {
  Eigen::MatrixXd points;   // rows, parameter units, by decreasing weight
  Eigen::VectorXd weights;  // sum to 1
};
// `exponent` in (0, 1] tempers the weights, w ∝ posterior^exponent: 1 is the posterior; a
// smaller one flattens it so that the edges of the high-posterior set weigh more
// (AdaptiveDesignOptions::acquisition_tempering).
PosteriorWeights posterior_weights(const CalibrationProblem& problem,
                                   const AdaptiveDesignOptions& options, double exponent = 1.0);

// The mean of two weightings over the same acquisition grid (nodes matched exactly), by
// decreasing weight: the integral then covers where either posterior put the parameters.
PosteriorWeights average_weights(const PosteriorWeights& a, const PosteriorWeights& b);

// sum_g w(g) mean_i V_i(g) / s_i^2: how much of the targets' noise variance the surrogates'
// own variance adds where the posterior is. Below ~0.25 the region is set by the data (the
// surrogate widens sigma_total by less than ~12 %).
double weighted_surrogate_variance(const CalibrationProblem& problem,
                                   const PosteriorWeights& weights);

struct AcquisitionChoice {
  Eigen::VectorXd theta;  // parameter units
  double value = 0.0;     // a(x) when chosen, under the GPs that believe the earlier choices
};

// Up to `count` points by the kriging believer. Every target's model must be a
// surrogate::GaussianProcess (std::invalid_argument otherwise). `new_run_noise_variance`:
// per target, the noise variance of one new run (the replicate variance; 0 when unknown).
// `design_points`: the distinct points already run (rows, parameter units); candidates
// closer than options.min_separation (bound-scaled) to them or to an earlier choice are
// skipped, so fewer than `count` come back when the candidates run out.
// sum_i sum_g w(g) [V_i(g) - V_i(g | points)] / s_i^2: the joint drop of the weighted
// variance after runs at `points` (rows, parameter units), the GPs believing each in turn, as
// choose_batch computes it; for valuing a batch chosen under other weights.
double batch_variance_drop(const CalibrationProblem& problem, const PosteriorWeights& weights,
                           const std::vector<double>& new_run_noise_variance,
                           const Eigen::MatrixXd& points);

std::vector<AcquisitionChoice> choose_batch(const CalibrationProblem& problem,
                                            const PosteriorWeights& weights,
                                            const std::vector<double>& new_run_noise_variance,
                                            const Eigen::MatrixXd& design_points, int count,
                                            const AdaptiveDesignOptions& options);

}  // namespace demcal::calibrate
