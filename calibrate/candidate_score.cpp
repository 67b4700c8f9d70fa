#include "calibrate/candidate_score.hpp"

#include "calibrate/detail/number_text.hpp"

#include "calibrate/mismatch_detection.hpp"

#include <gsl/gsl_cdf.h>

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>

namespace demcal::calibrate {
namespace {

// Singular values of J below this fraction of the largest count as zero in the projector:
// a rank-deficient base fit (AoR alone) then projects out only the directions it can move.
constexpr double kProjectorRankTolerance = 1e-10;
// Within this fraction of its range from a bound, a parameter counts as at the bound.
constexpr double kAtBoundFraction = 1e-6;

using detail::fmt;
using detail::number_json;

void check_candidate(const CandidateSignature& c, Eigen::Index n) {
  const std::string who = "score_candidate: candidate '" + c.name + "'";
  if (c.name.empty()) throw std::invalid_argument("score_candidate: a candidate has no name");
  const CandidateParameter& q = c.parameter;
  if (q.name.empty()) throw std::invalid_argument(who + ": its parameter has no name");
  if (!std::isfinite(q.lower) || !std::isfinite(q.upper) || !(q.lower < q.upper))
    throw std::invalid_argument(who + ": parameter '" + q.name + "': lower (" + fmt(q.lower, 6) +
                                ") must be below upper (" + fmt(q.upper, 6) + "), both finite");
  if (!(q.off_value >= q.lower && q.off_value <= q.upper))
    throw std::invalid_argument(who + ": parameter '" + q.name + "': off_value " + fmt(q.off_value, 6) +
                                " lies outside [" + fmt(q.lower, 6) + ", " + fmt(q.upper, 6) + "]");
  if (static_cast<Eigen::Index>(c.sensitivity.size()) != n)
    throw std::invalid_argument(who + ": sensitivity has " + std::to_string(c.sensitivity.size()) +
                                " entries but there are " + std::to_string(n) + " targets");
  for (std::size_t i = 0; i < c.sensitivity.size(); ++i)
    if (!std::isfinite(c.sensitivity[i]))
      throw std::invalid_argument(who + ": sensitivity[" + std::to_string(i) + "] is not finite");
  if (!c.sensitivity_se.empty()) {
    if (static_cast<Eigen::Index>(c.sensitivity_se.size()) != n)
      throw std::invalid_argument(who + ": sensitivity_se has " + std::to_string(c.sensitivity_se.size()) +
                                  " entries but there are " + std::to_string(n) + " targets (or leave it empty)");
    for (std::size_t i = 0; i < c.sensitivity_se.size(); ++i)
      if (!(c.sensitivity_se[i] >= 0.0) || !std::isfinite(c.sensitivity_se[i]))
        throw std::invalid_argument(who + ": sensitivity_se[" + std::to_string(i) + "] must be finite and >= 0, got " +
                                    fmt(c.sensitivity_se[i], 6));
  }
}

std::string score_statement(const CandidateScore& s, double off_value) {
  const std::string head = s.name + " (" + s.parameter_name + ")";
  switch (s.status) {
    case ScoreStatus::cannot_be_assessed:
      return head + " cannot be assessed: its sensitivities are within their noise of zero.";
    case ScoreStatus::confounded:
      return head + " cannot be told apart from a change of the base parameters: they produce the same signature.";
    case ScoreStatus::assessed: break;
  }
  if (!s.sign_allowed)
    return head + " does not help: its signature would need " + s.parameter_name + " " +
           (s.phi_step < 0.0 ? "below" : "above") + " " + fmt(off_value, 3) + ", which it cannot take.";
  std::string t = head + " would remove chi^2 = " + fmt(s.lagrange_multiplier) + " of " +
                  fmt(s.base_chi_square) + " (" + fmt(100.0 * s.explained_fraction, 2) + " %) with " +
                  s.parameter_name + " ~ " + fmt(s.phi_estimate) + " (linearized), " + p_value_text(s.p_value);
  if (!s.estimate_inside_bounds) t += "; the estimate lies beyond the parameter's bounds";
  return t + ".";
}

}  // namespace

void validate(const CandidateSignature& candidate, std::size_t targets) {
  check_candidate(candidate, static_cast<Eigen::Index>(targets));
}

ParameterSide allowed_side(const CandidateParameter& q) {
  if (q.off_value <= q.lower) return ParameterSide::above_only;
  if (q.off_value >= q.upper) return ParameterSide::below_only;
  return ParameterSide::both;
}

void validate(const ScoreOptions& o) {
  if (!(o.alpha > 0.0 && o.alpha < 1.0))
    throw std::invalid_argument("score_candidate: alpha must lie in (0, 1), got " + fmt(o.alpha, 6));
  if (!(o.noise_z > 0.0) || !std::isfinite(o.noise_z))
    throw std::invalid_argument("score_candidate: noise_z must be > 0, got " + fmt(o.noise_z, 6));
  if (!(o.confounded_fraction >= 0.0 && o.confounded_fraction < 1.0))
    throw std::invalid_argument("score_candidate: confounded_fraction must lie in [0, 1), got " +
                                fmt(o.confounded_fraction, 6));
}

const char* to_string(ScoreStatus status) {
  switch (status) {
    case ScoreStatus::assessed: return "assessed";
    case ScoreStatus::cannot_be_assessed: return "cannot_be_assessed";
    case ScoreStatus::confounded: return "confounded";
  }
  return "assessed";
}

CandidateScore score_candidate(const CalibrationProblem& base, const Eigen::VectorXd& theta,
                               const CandidateSignature& candidate, const ScoreOptions& options) {
  validate(options);
  const Eigen::Index n = base.target_count();
  check_candidate(candidate, n);

  Eigen::MatrixXd d_r;
  const Eigen::VectorXd r = base.residuals(theta, &d_r);
  // Columns of the parameters the fit can still move (see "Active bounds" in the header).
  const Eigen::VectorXd gradient = 2.0 * d_r.transpose() * r;  // d chi^2 / d theta
  const Eigen::VectorXd lower = base.lower(), upper = base.upper(), range = base.range();
  std::vector<Eigen::Index> free_columns;
  for (Eigen::Index k = 0; k < theta.size(); ++k) {
    const double tol = kAtBoundFraction * range(k);
    const bool pressed_low = theta(k) - lower(k) <= tol && gradient(k) > 0.0;
    const bool pressed_high = upper(k) - theta(k) <= tol && gradient(k) < 0.0;
    if (!pressed_low && !pressed_high) free_columns.push_back(k);
  }
  Eigen::MatrixXd jac(n, static_cast<Eigen::Index>(free_columns.size()));
  for (std::size_t c = 0; c < free_columns.size(); ++c) jac.col(static_cast<Eigen::Index>(c)) = -d_r.col(free_columns[c]);
  const Eigen::VectorXd sigma = base.evaluate(theta.transpose()).sigma_total.row(0).transpose();
  const Eigen::VectorXd s = Eigen::Map<const Eigen::VectorXd>(candidate.sensitivity.data(), n);
  const Eigen::VectorXd tau = candidate.sensitivity_se.empty()
                                  ? Eigen::VectorXd(Eigen::VectorXd::Zero(n))
                                  : Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(candidate.sensitivity_se.data(), n));
  const Eigen::VectorXd j = s.cwiseQuotient(sigma);
  const Eigen::VectorXd noise_var = tau.cwiseQuotient(sigma).cwiseAbs2();

  // M x = x - U_r U_r^T x with U_r the left singular vectors of J's non-zero singular values.
  // Every parameter pressed against a bound: nothing mimics the candidate, M = I.
  Eigen::MatrixXd u(n, 0);
  if (jac.cols() > 0) {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jac, Eigen::ComputeThinU);
    const Eigen::VectorXd sv = svd.singularValues();
    Eigen::Index rank = 0;
    for (Eigen::Index k = 0; k < sv.size(); ++k)
      if (sv(0) > 0.0 && sv(k) > kProjectorRankTolerance * sv(0)) ++rank;
    u = svd.matrixU().leftCols(rank);
  }
  const auto project = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return x - u * (u.transpose() * x); };
  const Eigen::VectorXd mj = project(j);
  const Eigen::VectorXd mr = project(r);
  const Eigen::VectorXd m_diag = Eigen::VectorXd::Ones(n) - u.rowwise().squaredNorm();

  CandidateScore sc;
  sc.name = candidate.name;
  sc.parameter_name = candidate.parameter.name;
  sc.base_chi_square = r.squaredNorm();
  sc.phi_estimate = candidate.parameter.off_value;
  const double jmj = j.dot(mj);
  const double jj = j.squaredNorm();
  sc.orthogonal_fraction = jj > 0.0 ? jmj / jj : 0.0;

  bool within_noise = true;
  for (Eigen::Index i = 0; i < n; ++i)
    if (std::abs(s(i)) > options.noise_z * tau(i)) within_noise = false;
  const double noise_in_jmj = m_diag.dot(noise_var);
  sc.signature_within_noise = within_noise;
  if (within_noise || (noise_in_jmj > 0.0 && jmj <= options.noise_z * options.noise_z * noise_in_jmj)) {
    sc.status = ScoreStatus::cannot_be_assessed;
  } else if (!(jmj > options.confounded_fraction * jj)) {
    sc.status = ScoreStatus::confounded;
  }
  if (sc.status != ScoreStatus::assessed) {
    sc.statement = score_statement(sc, candidate.parameter.off_value);
    if (sc.status == ScoreStatus::cannot_be_assessed && !within_noise)
      sc.statement = sc.name + " (" + sc.parameter_name + ") cannot be assessed at the base fit: the probes see it, " +
                     "but the part of its signature the base parameters cannot mimic (" +
                     fmt(100.0 * sc.orthogonal_fraction, 2) + " %) is within the probes' noise.";
    return sc;
  }

  const double t_num = mr.dot(j);
  const double variance = jmj + mr.cwiseAbs2().dot(noise_var);
  sc.phi_step = t_num / jmj;
  sc.phi_step_se = std::sqrt(variance) / jmj;
  sc.phi_estimate = candidate.parameter.off_value + sc.phi_step;
  sc.estimate_inside_bounds =
      sc.phi_estimate >= candidate.parameter.lower && sc.phi_estimate <= candidate.parameter.upper;
  const ParameterSide side = allowed_side(candidate.parameter);
  sc.sign_allowed = side == ParameterSide::both || (side == ParameterSide::above_only && sc.phi_step > 0.0) ||
                    (side == ParameterSide::below_only && sc.phi_step < 0.0);
  if (sc.sign_allowed) {
    sc.lagrange_multiplier = t_num * t_num / variance;
    sc.lagrange_multiplier_plain = t_num * t_num / jmj;
  }
  if (side == ParameterSide::both) {
    sc.p_value = gsl_cdf_chisq_Q(t_num * t_num / variance, 1.0);
  } else {
    const double z = (side == ParameterSide::above_only ? t_num : -t_num) / std::sqrt(variance);
    sc.p_value = gsl_cdf_ugaussian_Q(z);
  }
  sc.significant = sc.p_value < options.alpha;
  sc.explained_fraction = sc.base_chi_square > 0.0 ? sc.lagrange_multiplier / sc.base_chi_square : 0.0;
  sc.statement = score_statement(sc, candidate.parameter.off_value);
  return sc;
}

std::vector<CandidateScore> rank_candidates(const CalibrationProblem& base, const Eigen::VectorXd& theta,
                                            const std::vector<CandidateSignature>& candidates,
                                            const ScoreOptions& options) {
  std::set<std::string> names;
  for (const CandidateSignature& c : candidates)
    if (!names.insert(c.name).second)
      throw std::invalid_argument("rank_candidates: candidate '" + c.name + "' is listed twice");
  std::vector<CandidateScore> scores;
  for (const CandidateSignature& c : candidates) scores.push_back(score_candidate(base, theta, c, options));
  const auto order = [](const CandidateScore& s) {
    return s.status == ScoreStatus::assessed ? 0 : (s.status == ScoreStatus::confounded ? 1 : 2);
  };
  std::stable_sort(scores.begin(), scores.end(), [&](const CandidateScore& a, const CandidateScore& b) {
    if (order(a) != order(b)) return order(a) < order(b);
    return a.lagrange_multiplier > b.lagrange_multiplier;
  });
  for (std::size_t k = 0; k < scores.size(); ++k) scores[k].rank = static_cast<int>(k) + 1;
  return scores;
}

nlohmann::json CandidateScore::to_json() const {
  return {{"name", name},
          {"parameter", parameter_name},
          {"status", to_string(status)},
          {"lagrange_multiplier", number_json(lagrange_multiplier)},
          {"lagrange_multiplier_plain", number_json(lagrange_multiplier_plain)},
          {"p_value", number_json(p_value)},
          {"significant", significant},
          {"phi_step", number_json(phi_step)},
          {"phi_step_se", number_json(phi_step_se)},
          {"phi_estimate", number_json(phi_estimate)},
          {"sign_allowed", sign_allowed},
          {"estimate_inside_bounds", estimate_inside_bounds},
          {"base_chi_square", number_json(base_chi_square)},
          {"explained_fraction", number_json(explained_fraction)},
          {"orthogonal_fraction", number_json(orthogonal_fraction)},
          {"signature_within_noise", signature_within_noise},
          {"rank", rank},
          {"statement", statement}};
}

}  // namespace demcal::calibrate
