#pragma once
// A competitor that is not physics: generic model discrepancy (Kennedy & O'Hagan 2001).
// A named physics module must beat it, not only the base model, before the diagnosis
// names it; otherwise the report says that the recordings differ from the model by a
// pattern no candidate explains, and widens the parameters' region by that discrepancy.
// The maths, the prior and the margin: docs/model_discrepancy.md.
//
// Model, in units of each target's own sigma_total (so one prior serves every observable):
//
//   y_i = f_i(theta) + sigma_i delta_i + sigma_i eps_i,   eps ~ N(0, I),
//   delta ~ N(0, tau_b^2 B + tau_g^2 G),
//   B_ij = 1 when i and j measure the same observable (a per-observable bias),
//   G_ij = [same observable] exp(-1/2 sum_v ((x_v(i) - x_v(j)) / (l range_v))^2), a
//          Gaussian process over the setup variables both setups have (G_ij = 0 when they
//          share none; G_ii = 1: a setup without variables gets an independent offset).
//
// Hyperprior: tau_b and tau_g independent, log-uniform on [min_amplitude, max_amplitude];
// the length scale l is fixed (with three or four setups it cannot be learned). The
// evidence integrates theta (uniform on the box) analytically after linearizing f at the
// base fit, and log tau on a grid:
//
//   Z = mean over the (tau_b, tau_g) grid of  pi(theta) (2 pi)^(p/2) |A|^(-1/2)
//       N(e; 0, D S D) exp(+1/2 e^T S^-1 F A^-1 F^T S^-1 e) P_box,
//   S = I + tau_b^2 B + tau_g^2 G, A = F^T S^-1 F, e = (y - f(theta_hat)) / sigma,
//   F = the standardized Jacobian d f / d theta / sigma, D = diag(sigma),
//   P_box = the mass of N(theta_hat + A^-1 F^T S^-1 e, A^-1) inside the design box.
//
// At tau = 0 and an interior fit this is model_evidence's Laplace evidence of the base model
// (the same linearization), so the two are on one scale and bayes_factor() applies. P_box
// keeps a fit on a bound from being credited with the fit beyond it that the linear step
// reaches (until 2026-12-07 the integral ran over all of R^p; tests/concealed/stage6/).

#include "calibrate/calibration_problem.hpp"
#include "calibrate/discrepancy_diagnosis.hpp"
#include "calibrate/mismatch_detection.hpp"
#include "calibrate/mismatch_location.hpp"
#include "calibrate/model_evidence.hpp"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace demcal::calibrate {

struct DiscrepancyOptions {
  // Range of the log-uniform hyperprior of both amplitudes, in sigma_total units. The
  // lower end is far below the noise (a discrepancy of 0.1 sigma cannot be seen); the
  // upper end, 30 sigma, is larger than any mismatch a surrogate study leaves unexplained.
  // The prior's width in log tau, log(300) = 5.7, bounds the Occam factor an amplitude the
  // data need can cost (about log(width / posterior width)). An unbounded, vague prior
  // would let the discrepancy absorb anything: Brynjarsdottir & O'Hagan's (2014) warning.
  double min_amplitude = 0.1;
  double max_amplitude = 30.0;
  int amplitude_nodes = 25;  // per amplitude, log-spaced, both ends included (>= 2)
  // Length scale of the setup process as a fraction of each variable's range over the
  // setups (> 0): 0.5 lets it bend once across the setups, not follow each one.
  double length_scale = 0.5;
  // Confidence of the widened intervals; (0, 1).
  double confidence = 0.95;
  // A target's discrepancy is named when its posterior mean exceeds this many posterior
  // standard deviations (> 0).
  double named_z = 2.0;
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const DiscrepancyOptions& options);

// The discrepancy's posterior at one target, in the observable's units.
struct TargetDiscrepancy {
  std::string setup, observable;
  double mean = 0.0, sd = 0.0;
  double z = 0.0;  // mean / sd
  double sigma_total = 0.0;
  bool named = false;  // |z| >= named_z
};

struct DiscrepancyEvidence {
  // As a ModelEvidence named "discrepancy" (method laplace, data = the base targets), so
  // that bayes_factor(candidate, evidence) compares it with any candidate fitted to the
  // same targets.
  ModelEvidence evidence;
  double log_evidence_base = 0.0;  // the same formula at tau = 0 (model_evidence's Laplace)
  // Posterior modes of the amplitudes (grid nodes), in sigma_total units.
  double bias_amplitude = 0.0, process_amplitude = 0.0;
  // theta with the discrepancy: the Laplace posterior averaged over the amplitudes'
  // posterior (mixture), in parameter units. That Gaussian (unconstrained_theta,
  // covariance) may reach outside the bounds; under the uniform prior each marginal is
  // restricted to its bounds, and theta and the intervals (central, at
  // options.confidence) are that restricted marginal's mean and quantiles, so theta
  // always lies inside [lower, upper] and inside the bounds.
  std::vector<std::string> parameter_names;
  std::vector<ParameterBounds> bounds;
  Eigen::VectorXd theta, unconstrained_theta;
  Eigen::MatrixXd covariance;
  std::vector<double> lower, upper;
  // The base fit's intervals by the same rule without the discrepancy, for "widened by".
  std::vector<double> base_lower, base_upper;
  std::vector<TargetDiscrepancy> targets;  // in the targets' order
  std::vector<std::string> notes;

  nlohmann::json to_json() const;  // NaN -> null
};

// At the base model's best minimum theta_hat (parameter units). Throws
// std::invalid_argument when theta_hat has the wrong size, a setup variable is not
// finite, or an option is out of range; std::runtime_error when the base Jacobian is rank
// deficient (no evidence can be formed; the caller reports the base fit as unidentified).
DiscrepancyEvidence discrepancy_evidence(const CalibrationProblem& base,
                                         const Eigen::VectorXd& theta_hat,
                                         const SetupVariables& setup_variables = {},
                                         const DiscrepancyOptions& options = {});

struct ExplanationOptions {
  // A physics is named only when its log evidence exceeds the discrepancy's, the base
  // model's and every other candidate's by at least this: 3.0 is a Bayes factor of
  // e^3 = 20, the start of "strong" on Kass & Raftery's (1995) scale (2 ln B >= 6).
  double required_log_bayes_factor = 3.0;
};

void validate(const ExplanationOptions& options);

enum class Explanation {
  none_needed,  // no mismatch (or untestable): neither physics nor discrepancy
  physics,      // a candidate beats the discrepancy, the base model and the others by the margin
  discrepancy,  // a mismatch that no single candidate explains better than a generic
                // discrepancy and than every other candidate (see `indistinguishable`)
};
const char* to_string(Explanation explanation);  // "none_needed", "physics", "discrepancy"

struct ExplanationDecision {
  Explanation verdict = Explanation::none_needed;
  std::string physics;         // the candidate named; empty unless verdict is physics
  std::string best_candidate;  // largest evidence among the candidates; empty when none
  double log_bayes_factor_over_discrepancy = 0.0;  // best candidate over it; NaN: none
  double log_bayes_factor_over_base = 0.0;         // best candidate over base; NaN: none
  // The candidate of second largest evidence, and the best one's log Bayes factor over it
  // (NaN when fewer than two candidates have evidence).
  std::string runner_up;
  double log_bayes_factor_over_runner_up = 0.0;
  // When the best candidate beats the discrepancy and the base by the margin but not every
  // other candidate: the best and each candidate within the margin of it, largest evidence
  // first. These recordings cannot tell them apart, so none is named (a wrong name is worse
  // than none). Empty otherwise.
  std::vector<std::string> indistinguishable;
  double required_log_bayes_factor = 3.0;
  // What a user reads first: for a discrepancy, which observables and setups differ, by how
  // much, and the parameters with their widened intervals.
  std::string statement;

  nlohmann::json to_json() const;  // NaN -> null
};

// The rule: no mismatch -> none_needed; else the candidate of largest evidence is named
// when it beats the discrepancy, the base model and the runner-up candidate by
// required_log_bayes_factor; else discrepancy (with `indistinguishable` filled when only
// the runner-up stood in the way). Candidates without evidence (NaN) are skipped. Throws
// std::invalid_argument when a candidate was fitted to other targets than the
// discrepancy's (as bayes_factor).
ExplanationDecision decide_explanation(const MismatchDetection& detection,
                                       const ModelEvidence& base,
                                       const std::vector<ModelEvidence>& candidates,
                                       const DiscrepancyEvidence& discrepancy,
                                       const ExplanationOptions& options = {});

// The whole competition after diagnose_discrepancy, in one call for the workflow: the
// discrepancy's evidence on the targets the base model was fitted to (`targets` without
// `held_out`, as passed to diagnose_discrepancy), then decide_explanation with every fitted
// candidate's evidence. When the base Jacobian is rank deficient (no Laplace evidence),
// available is false, a note says so and the diagnosis stands as it is.
struct DiscrepancyJudgement {
  bool available = false;
  DiscrepancyEvidence discrepancy;
  ExplanationDecision decision;
  std::string note;
  nlohmann::json to_json() const;
};

// Throws std::invalid_argument as discrepancy_evidence and decide_explanation do.
DiscrepancyJudgement judge_against_discrepancy(const std::vector<ParameterBounds>& parameters,
                                               const std::vector<Target>& targets,
                                               const std::vector<TargetKey>& held_out,
                                               const DiscrepancyDiagnosis& diagnosis,
                                               const SetupVariables& setup_variables = {},
                                               const DiscrepancyOptions& discrepancy_options = {},
                                               const ExplanationOptions& explanation_options = {});

}  // namespace demcal::calibrate
