#include "calibrate/posterior_sampling.hpp"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_statistics_double.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

namespace demcal::calibrate {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Steps with the Jacobian-based proposal before adaptation starts (Haario's t0).
constexpr int kAdaptationStart = 500;
// Haario's epsilon, in bound-scaled units: keeps the proposal non-singular.
constexpr double kProposalFloor = 1e-10;
// (J^T J + kWeakPrecision I)^-1: a direction the data do not constrain is proposed at
// 1/sqrt(kWeakPrecision) of the box instead of far outside it.
constexpr double kWeakPrecision = 100.0;

struct RngDeleter {
  void operator()(gsl_rng* r) const { gsl_rng_free(r); }
};

// Integrated autocorrelation time by Geyer's (1992) initial monotone positive sequence.
double autocorrelation_time(const double* x, int n) {
  if (n < 4) return 1.0;
  double mean = 0.0;
  for (int t = 0; t < n; ++t) mean += x[t];
  mean /= n;
  double c0 = 0.0;
  for (int t = 0; t < n; ++t) c0 += (x[t] - mean) * (x[t] - mean);
  c0 /= n;
  // A chain that never moved carries one sample's worth of information.
  if (!(c0 > 0.0)) return static_cast<double>(n);
  const auto rho = [&](int lag) {
    double c = 0.0;
    for (int t = 0; t + lag < n; ++t) c += (x[t] - mean) * (x[t + lag] - mean);
    return c / (n * c0);
  };
  double tau = -1.0;
  double previous = std::numeric_limits<double>::infinity();
  for (int k = 0; 2 * k + 1 < n; ++k) {
    double gamma = rho(2 * k) + rho(2 * k + 1);
    if (!(gamma > 0.0)) break;
    gamma = std::min(gamma, previous);
    previous = gamma;
    tau += 2.0 * gamma;
  }
  return std::max(tau, 1.0 / n);
}

Eigen::MatrixXd initial_proposal(const CalibrationProblem& problem, const Eigen::VectorXd& theta) {
  const Eigen::Index p = problem.parameter_count();
  Eigen::MatrixXd j;
  problem.residuals(theta, &j);
  Eigen::MatrixXd precision = Eigen::MatrixXd::Identity(p, p) * kWeakPrecision;
  if (j.allFinite()) {
    const Eigen::MatrixXd ju = j * problem.range().asDiagonal();
    precision += ju.transpose() * ju;
  }
  return precision.inverse() * (2.38 * 2.38 / static_cast<double>(p));
}

}  // namespace

CredibleRegion credible_region(const PosteriorSummary& posterior, const LikelihoodRegion& grid,
                               double confidence) {
  CredibleRegion c;
  if (!posterior.available || !grid.available || posterior.log_posterior.size() == 0) return c;
  std::vector<double> lp(posterior.log_posterior.data(),
                         posterior.log_posterior.data() + posterior.log_posterior.size());
  std::sort(lp.begin(), lp.end());
  c.available = true;
  c.log_posterior_level = gsl_stats_quantile_from_sorted_data(lp.data(), 1, lp.size(), 1.0 - confidence);
  const std::vector<double> weights = grid_cell_measures(grid.axes);
  c.inside.assign(grid.log_posterior.size(), false);
  for (std::size_t k = 0; k < grid.log_posterior.size(); ++k)
    if (grid.log_posterior[k] >= c.log_posterior_level) {
      c.inside[k] = true;
      ++c.nodes_inside;
      c.area += weights[k];
    }
  return c;
}

PosteriorSummary sample_posterior(const CalibrationProblem& problem,
                                  const std::vector<Eigen::VectorXd>& starts,
                                  const CalibrationOptions& options, const LikelihoodRegion* grid) {
  validate(options);
  PosteriorSummary out;
  if (options.mcmc_samples == 0) return out;
  if (starts.empty()) throw std::invalid_argument("posterior sampling: no start point");
  for (std::size_t s = 0; s < starts.size(); ++s)
    if (!problem.inside_bounds(starts[s]))
      throw std::invalid_argument("posterior sampling: start " + std::to_string(s) +
                                  " lies outside the bounds or has the wrong size");

  const Eigen::Index p = problem.parameter_count();
  const int chains = options.mcmc_chains;
  const int kept = (options.mcmc_samples + chains - 1) / chains;
  const int burn_in = options.mcmc_burn_in;
  const double scale = 2.38 * 2.38 / static_cast<double>(p);
  out.available = true;
  out.chains = chains;
  out.samples_per_chain = kept;
  out.samples.resize(static_cast<Eigen::Index>(chains) * kept, p);
  out.log_posterior.resize(out.samples.rows());

  std::unique_ptr<gsl_rng, RngDeleter> rng(gsl_rng_alloc(gsl_rng_mt19937));
  if (!rng) throw std::runtime_error("posterior sampling: cannot allocate a GSL generator");
  gsl_rng_set(rng.get(), static_cast<unsigned long>(options.seed));

  long accepted = 0;
  Eigen::VectorXd z(p);
  for (int c = 0; c < chains; ++c) {
    const Eigen::VectorXd& start = starts[static_cast<std::size_t>(c) % starts.size()];
    Eigen::VectorXd u = problem.to_unit(start);
    double lp = problem.log_posterior(start);
    if (!std::isfinite(lp))
      throw std::runtime_error("posterior sampling: the log posterior at start " +
                               std::to_string(static_cast<std::size_t>(c) % starts.size()) +
                               " is not finite");
    Eigen::MatrixXd chol = Eigen::LLT<Eigen::MatrixXd>(initial_proposal(problem, start)).matrixL();
    // Running mean and scatter of the chain (Welford), for the adapted covariance.
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(p);
    Eigen::MatrixXd scatter = Eigen::MatrixXd::Zero(p, p);
    for (int t = 0; t < burn_in + kept; ++t) {
      if (t >= kAdaptationStart) {
        const Eigen::MatrixXd cov = scatter / static_cast<double>(t - 1) +
                                    kProposalFloor * Eigen::MatrixXd::Identity(p, p);
        const Eigen::LLT<Eigen::MatrixXd> llt(scale * cov);
        if (llt.info() == Eigen::Success) chol = llt.matrixL();
      }
      for (Eigen::Index j = 0; j < p; ++j) z(j) = gsl_ran_gaussian_ziggurat(rng.get(), 1.0);
      const Eigen::VectorXd proposal = u + chol * z;
      // The uniform draw is taken for every step, so that the random stream (and thus the
      // chain) does not depend on which proposals fall outside the box.
      const double log_uniform = std::log(gsl_rng_uniform_pos(rng.get()));
      bool accept = false;
      if ((proposal.array() >= 0.0).all() && (proposal.array() <= 1.0).all()) {
        const double lp_new = problem.log_posterior(problem.from_unit(proposal));
        if (log_uniform < lp_new - lp) {
          u = proposal;
          lp = lp_new;
          accept = true;
        }
      }
      const Eigen::VectorXd delta = u - mean;
      mean += delta / static_cast<double>(t + 1);
      scatter += delta * (u - mean).transpose();
      if (t >= burn_in) {
        const Eigen::Index row = static_cast<Eigen::Index>(c) * kept + (t - burn_in);
        out.samples.row(row) = problem.from_unit(u).transpose();
        out.log_posterior(row) = lp;
        if (accept) ++accepted;
      }
    }
  }
  const double total = static_cast<double>(out.samples.rows());
  out.acceptance_rate = static_cast<double>(accepted) / total;
  out.mean = out.samples.colwise().mean().transpose();
  const Eigen::MatrixXd centred = out.samples.rowwise() - out.mean.transpose();
  out.covariance = centred.transpose() * centred / std::max(total - 1.0, 1.0);

  const double tail = 0.5 * (1.0 - options.confidence);
  for (Eigen::Index j = 0; j < p; ++j) {
    MarginalPosterior m;
    m.name = problem.parameters()[static_cast<std::size_t>(j)].name;
    std::vector<double> x(out.samples.col(j).data(), out.samples.col(j).data() + out.samples.rows());
    m.mean = out.mean(j);
    m.sd = std::sqrt(std::max(out.covariance(j, j), 0.0));
    m.effective_sample_size = 0.0;
    std::vector<double> chain_mean(static_cast<std::size_t>(chains)), chain_var(static_cast<std::size_t>(chains));
    for (int c = 0; c < chains; ++c) {
      const double* xc = x.data() + static_cast<std::size_t>(c) * static_cast<std::size_t>(kept);
      m.effective_sample_size += std::min(static_cast<double>(kept), kept / autocorrelation_time(xc, kept));
      chain_mean[static_cast<std::size_t>(c)] = gsl_stats_mean(xc, 1, static_cast<std::size_t>(kept));
      chain_var[static_cast<std::size_t>(c)] =
          kept > 1 ? gsl_stats_variance(xc, 1, static_cast<std::size_t>(kept)) : 0.0;
    }
    m.r_hat = kNaN;
    if (chains >= 2 && kept >= 2) {
      const double w = gsl_stats_mean(chain_var.data(), 1, chain_var.size());
      const double b_over_n = gsl_stats_variance(chain_mean.data(), 1, chain_mean.size());
      const double var_plus = (kept - 1.0) / kept * w + b_over_n;
      if (w > 0.0) m.r_hat = std::sqrt(var_plus / w);
    }
    std::sort(x.begin(), x.end());
    m.lower = gsl_stats_quantile_from_sorted_data(x.data(), 1, x.size(), tail);
    m.median = gsl_stats_quantile_from_sorted_data(x.data(), 1, x.size(), 0.5);
    m.upper = gsl_stats_quantile_from_sorted_data(x.data(), 1, x.size(), 1.0 - tail);
    double lo = x.front(), hi = x.back();
    if (!(hi > lo)) {
      // All samples equal: a bin of a thousandth of the range around them.
      const double h = 5e-4 * problem.range()(j);
      lo -= h;
      hi += h;
    }
    const int bins = options.histogram_bins;
    const double width = (hi - lo) / bins;
    m.histogram_edges.resize(static_cast<std::size_t>(bins) + 1);
    for (int b = 0; b <= bins; ++b) m.histogram_edges[static_cast<std::size_t>(b)] = lo + b * width;
    m.histogram_edges.back() = hi;
    std::vector<double> counts(static_cast<std::size_t>(bins), 0.0);
    for (double v : x) {
      const int b = std::clamp(static_cast<int>((v - lo) / width), 0, bins - 1);
      counts[static_cast<std::size_t>(b)] += 1.0;
    }
    m.histogram_density.resize(static_cast<std::size_t>(bins));
    for (int b = 0; b < bins; ++b)
      m.histogram_density[static_cast<std::size_t>(b)] = counts[static_cast<std::size_t>(b)] / (total * width);
    out.marginals.push_back(std::move(m));
  }
  if (grid) out.credible_region = credible_region(out, *grid, options.confidence);
  return out;
}

}  // namespace demcal::calibrate
