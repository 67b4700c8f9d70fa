#include "calibrate/model_evidence.hpp"

#include "calibrate/detail/number_text.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace demcal::calibrate {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Bound-scaled distance within which theta_hat counts as lying on a bound (as
// Minimum::at_bound).
constexpr double kAtBoundTolerance = 1e-6;

using detail::fmt;
using detail::number_json;

// A Bayes factor for sentences: 140, 3.2, "> 1e6" beyond the range where digits matter.
std::string factor_text(double log_b) {
  if (log_b > std::log(1e6)) return "> 1e6";
  return fmt(std::exp(log_b), 2);
}

}  // namespace

const char* to_string(EvidenceMethod method) {
  switch (method) {
    case EvidenceMethod::laplace: return "laplace";
    case EvidenceMethod::grid: return "grid";
    case EvidenceMethod::none: return "none";
  }
  return "none";
}

ModelEvidence model_evidence(const CalibrationResult& result, const std::string& model_name) {
  if (result.minima.empty())
    throw std::invalid_argument("model_evidence: the calibration result of '" + model_name + "' has no minimum");
  const Minimum& best = result.minima.front();
  ModelEvidence e;
  e.model = model_name;
  e.data = result.targets;
  e.parameters = static_cast<int>(result.parameters.size());
  e.targets = static_cast<int>(result.targets.size());
  e.chi_square_min = best.chi_squared;
  const double log_2pi = std::log(2.0 * std::numbers::pi);
  double normalisation = 0.0;  // sum_i log(2 pi sigma_i^2)
  for (double s : best.sigma_total) normalisation += log_2pi + 2.0 * std::log(s);
  e.log_likelihood_max = -0.5 * (best.chi_squared + normalisation);
  e.bic = -2.0 * e.log_likelihood_max + e.parameters * std::log(static_cast<double>(e.targets));
  double log_box = 0.0;
  for (std::size_t j = 0; j < result.parameters.size(); ++j) {
    const ParameterBounds& b = result.parameters[j];
    log_box += std::log(b.upper - b.lower);
    const double u = (best.theta(static_cast<Eigen::Index>(j)) - b.lower) / (b.upper - b.lower);
    if (u <= kAtBoundTolerance || u >= 1.0 - kAtBoundTolerance) ++e.parameters_at_bound;
  }
  e.log_prior_density = -log_box;

  e.log_evidence_laplace = kNaN;
  if (best.covariance_available) {
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(best.covariance);
    const Eigen::VectorXd d = ldlt.vectorD();
    if (ldlt.info() == Eigen::Success && (d.array() > 0.0).all()) {
      e.laplace_available = true;
      e.log_evidence_laplace = e.log_likelihood_max + e.log_prior_density + 0.5 * e.parameters * log_2pi +
                               0.5 * d.array().log().sum() - e.parameters_at_bound * std::log(2.0);
    }
  }
  if (!e.laplace_available)
    e.notes.push_back("No Gauss-Newton covariance at the best minimum (rank-deficient Jacobian): the Laplace "
                      "evidence is not available.");

  e.log_evidence_grid = kNaN;
  const LikelihoodRegion& reg = result.region;
  if (reg.available && !reg.log_posterior.empty()) {
    const std::vector<double> w = grid_cell_measures(reg.axes);
    double top = -std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < w.size(); ++k)
      if (w[k] > 0.0) top = std::max(top, reg.log_posterior[k]);
    if (std::isfinite(top)) {
      double sum = 0.0;
      for (std::size_t k = 0; k < w.size(); ++k)
        if (w[k] > 0.0 && std::isfinite(reg.log_posterior[k])) sum += w[k] * std::exp(reg.log_posterior[k] - top);
      // log_posterior omits the 2 pi of the normalisation.
      e.log_evidence_grid = top + std::log(sum) - 0.5 * e.targets * log_2pi + e.log_prior_density;
      e.grid_available = true;
      e.grid_resolved = reg.resolved;
    }
  }

  if (e.laplace_available && e.parameters_at_bound == 0) {
    e.method = EvidenceMethod::laplace;
  } else if (e.grid_available && (e.grid_resolved || !e.laplace_available)) {
    e.method = EvidenceMethod::grid;
    if (e.laplace_available)
      e.notes.push_back("The best minimum lies on " + std::to_string(e.parameters_at_bound) +
                        " bound(s): the evidence integrates the likelihood-ratio grid instead of the Laplace "
                        "approximation, which would assume the Gaussian extends past the bound.");
    else
      e.notes.push_back("The evidence integrates the likelihood-ratio grid.");
  } else if (e.laplace_available) {
    e.method = EvidenceMethod::laplace;
    e.notes.push_back("The best minimum lies on a bound and no resolved grid is available: the Laplace evidence is "
                      "corrected by log 2 per parameter on a bound, an upper bound on the true value.");
  } else {
    e.method = EvidenceMethod::none;
    e.notes.push_back("Neither the Laplace approximation nor a grid is available: no evidence.");
  }
  e.log_evidence = e.method == EvidenceMethod::laplace ? e.log_evidence_laplace
                   : e.method == EvidenceMethod::grid  ? e.log_evidence_grid
                                                       : kNaN;
  if (e.grid_available && !e.grid_resolved)
    e.notes.push_back("The likelihood-ratio grid spans fewer than 5 nodes across the region along some axis: the "
                      "grid evidence is coarse.");
  if (e.laplace_available && e.grid_available && e.grid_resolved && e.parameters_at_bound == 0 &&
      std::abs(e.log_evidence_laplace - e.log_evidence_grid) > 1.0)
    e.notes.push_back("The Laplace and grid evidences differ by " +
                      fmt(std::abs(e.log_evidence_laplace - e.log_evidence_grid), 2) +
                      " (natural log): the posterior is far from Gaussian.");
  return e;
}

std::string kass_raftery_strength(double b) {
  if (std::isnan(b)) return "n/a";
  const double x = b >= 1.0 ? b : 1.0 / b;
  if (x < 3.0) return "not worth more than a bare mention";
  if (x < 20.0) return "positive";
  if (x < 150.0) return "strong";
  return "very strong";
}

BayesFactor bayes_factor(const ModelEvidence& a, const ModelEvidence& b) {
  if (a.data.size() != b.data.size())
    throw std::invalid_argument("bayes_factor: '" + a.model + "' was fitted to " + std::to_string(a.data.size()) +
                                " targets and '" + b.model + "' to " + std::to_string(b.data.size()));
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    const TargetSummary& x = a.data[i];
    const TargetSummary& y = b.data[i];
    if (x.setup != y.setup || x.observable != y.observable || x.measured != y.measured)
      throw std::invalid_argument("bayes_factor: target " + std::to_string(i) + " differs: '" + a.model + "' has " +
                                  x.setup + " " + x.observable + " = " + fmt(x.measured, 6) + ", '" + b.model +
                                  "' has " + y.setup + " " + y.observable + " = " + fmt(y.measured, 6));
  }
  if (a.method == EvidenceMethod::none || b.method == EvidenceMethod::none)
    throw std::invalid_argument("bayes_factor: '" + (a.method == EvidenceMethod::none ? a.model : b.model) +
                                "' has no evidence");
  BayesFactor f;
  f.model_a = a.model;
  f.model_b = b.model;
  f.log_bayes_factor = a.log_evidence - b.log_evidence;
  f.bayes_factor = std::exp(f.log_bayes_factor);
  f.delta_bic = a.bic - b.bic;
  f.strength = kass_raftery_strength(f.bayes_factor);
  const bool a_wins = f.log_bayes_factor >= 0.0;
  f.reading = (a_wins ? a.model : b.model) + " is favoured over " + (a_wins ? b.model : a.model) +
              ": Bayes factor " + factor_text(std::abs(f.log_bayes_factor)) + " (" + f.strength + ").";
  return f;
}

nlohmann::json ModelEvidence::to_json() const {
  nlohmann::json notes_json = notes;
  return {{"model", model},
          {"parameters", parameters},
          {"targets", targets},
          {"chi_square_min", number_json(chi_square_min)},
          {"log_likelihood_max", number_json(log_likelihood_max)},
          {"bic", number_json(bic)},
          {"bic_convention", "-2 log L(theta_hat) + k ln n, L Gaussian with its normalisation"},
          {"log_prior_density", number_json(log_prior_density)},
          {"laplace_available", laplace_available},
          {"parameters_at_bound", parameters_at_bound},
          {"log_evidence_laplace", number_json(log_evidence_laplace)},
          {"grid_available", grid_available},
          {"grid_resolved", grid_resolved},
          {"log_evidence_grid", number_json(log_evidence_grid)},
          {"method", to_string(method)},
          {"log_evidence", number_json(log_evidence)},
          {"notes", notes_json}};
}

nlohmann::json BayesFactor::to_json() const {
  return {{"model_a", model_a},
          {"model_b", model_b},
          {"log_bayes_factor", number_json(log_bayes_factor)},
          {"bayes_factor", number_json(bayes_factor)},
          {"delta_bic", number_json(delta_bic)},
          {"strength", strength},
          {"reading", reading}};
}

}  // namespace demcal::calibrate
