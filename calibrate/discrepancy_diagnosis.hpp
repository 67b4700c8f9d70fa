#pragma once
// The missing-physics workflow of docs/design.md in one call, over surrogates and recordings
// only (the DEM runs behind the sensitivities and extended designs are the caller's):
//
//   1. detect   calibrate the base model on every target not held out; chi-square test
//               (mismatch_detection.hpp). No mismatch: stop, "no physics is added"; the
//               candidates are still scored, flagged as not needed.
//   2. locate   residual groups, trends against setup variables, subset calibrations
//               (mismatch_location.hpp).
//   3. explain  score every candidate at the base fit (candidate_score.hpp); recalibrate
//               the leading ones with theta and phi free, on their extended targets;
//               BIC and log evidence of each and of the base model (model_evidence.hpp).
//   4. model    the candidate of largest evidence, if it beats the base model and the
//               next candidate by required_log_bayes_factor; else "unexplained mismatch".
//   5. compare  chi^2/dof, residuals per target and held-out predictions, before and after.
//
// The summary is what a user reads first, e.g. "The recordings are not reproduced
// (chi2/dof = 9.1, p < 1e-6). The mismatch is in discharge_time_s at the setups
// orifice_10mm and orifice_14mm (78 % of chi^2). Best explained by cohesion:
// surface_energy_j_m2 = 0.08 (0.05-0.11); Bayes factor 140 over wall_friction, the next
// candidate. With it: chi2/dof = 1.1."

#include "calibrate/calibration.hpp"
#include "calibrate/candidate_score.hpp"
#include "calibrate/mismatch_detection.hpp"
#include "calibrate/mismatch_location.hpp"
#include "calibrate/model_evidence.hpp"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace demcal::calibrate {

// Names one target: its setup and observable (unique among the diagnosis' targets).
struct TargetKey {
  std::string setup, observable;
};

// A physics module that could be switched on, e.g. cohesion with surface_energy_j_m2.
struct CandidateModule {
  std::string name;              // unique, not empty
  CandidateParameter parameter;  // its name must differ from the base parameters'
  // d mean_i / d phi at the base fit and phi0, one entry per target passed to
  // diagnose_discrepancy (held-out ones included; they are not used), and their standard
  // errors (empty: exact). See candidate_score.hpp.
  std::vector<double> sensitivity, sensitivity_se;
  // The design extended into phi: targets whose models take (theta..., phi), matched to the
  // diagnosis' targets by setup and observable, with the same measured value and
  // sigma_measured. A target without one (or all, when empty) is extended to first order:
  // mean(theta) + s_i (phi - phi0), variance + (phi - phi0)^2 se_i^2 -- adequate near
  // phi0 only, so the fit says how many targets were linearized.
  std::vector<Target> extended_targets;
};

// The calibrations' defaults, without posterior sampling (the workflow needs minima,
// covariances and grids only).
CalibrationOptions diagnosis_calibration_defaults();

struct DiagnosisOptions {
  // Of every test in the workflow: detection, location, scores; (0, 1). Overrides the
  // alpha of `location` and `score`.
  double alpha = 0.01;
  // How many of the best-scored assessable candidates are recalibrated (>= 0).
  int leading_candidates = 2;
  // The chosen module must beat the base model and the next candidate by this log Bayes
  // factor (>= 0). The same
  // margin as ExplanationOptions::required_log_bayes_factor (calibrate/model_discrepancy.hpp),
  // so that one number decides: 3 is a Bayes factor of e^3 = 20, "strong" on Kass & Raftery's
  // scale.
  double required_log_bayes_factor = 3.0;
  // The goodness-of-fit test that decides whether candidates are fitted at all. Empty: the
  // chi-square of the fitted targets taken as independent (`detection` of the result). The
  // workflow passes its calibrated test (correlated targets, local scatter; study/
  // diagnosis_workflow.hpp), so that a mismatch only that test sees is still explained or
  // not, rather than left unexplained with no candidate fitted.
  std::optional<MismatchDetection> deciding_detection;
  // Of every calibration (base, candidates, subsets). Overrides `location.calibration`.
  CalibrationOptions calibration = diagnosis_calibration_defaults();
  // Targets kept out of every fit and predicted before and after.
  std::vector<TargetKey> held_out;
  LocationOptions location;
  ScoreOptions score;
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const DiagnosisOptions& options);

// One target before and after (after: the chosen module; NaN when none is chosen).
struct TargetComparison {
  std::string setup, observable;
  bool held_out = false;
  double measured = 0.0, sigma_measured = 0.0;
  double predicted_before = 0.0, sigma_total_before = 0.0, residual_before = 0.0;
  double predicted_after = 0.0, sigma_total_after = 0.0, residual_after = 0.0;
};

// A leading candidate recalibrated with theta and phi free.
struct CandidateFit {
  std::string name;
  CandidateParameter parameter;
  int linearized_targets = 0;     // fitted targets extended to first order (no design given)
  CalibrationResult calibration;  // parameters: the base parameters, then phi
  ModelEvidence evidence;
  BayesFactor over_base;  // this model over the base model
  double phi = 0.0;       // at the best minimum
  // Interval at the calibration's confidence: phi -/+ z SE from the covariance (z from
  // chi^2(1)), clipped to the bounds, when the covariance exists and phi is off its bounds;
  // otherwise the profile of chi^2 over the grid's other axes against min + chi^2(1)
  // quantile, interpolated between nodes; NaN when neither exists.
  double phi_lower = 0.0, phi_upper = 0.0;
  std::string interval_method;  // "covariance", "grid profile", "none"
  Eigen::VectorXd theta;        // base parameters at the best minimum
  Eigen::VectorXd theta_shift;  // theta - base theta_hat, parameter units
  double chi_square_per_dof = 0.0;
};

enum class DiagnosisOutcome {
  reproduced,   // no mismatch: no physics added
  untestable,   // too few targets for a test
  explained,    // a module beats the base model and the next one by the required Bayes factor
  unexplained,  // mismatch, and no candidate explains it
};
const char* to_string(DiagnosisOutcome outcome);  // "reproduced", "untestable", ...

struct DiscrepancyDiagnosis {
  DiagnosisOutcome outcome = DiagnosisOutcome::untestable;
  MismatchDetection detection;
  CalibrationResult base;
  ModelEvidence base_evidence;
  bool location_available = false;  // located only when there is a mismatch
  MismatchLocation location;
  std::vector<CandidateScore> scores;  // ranked
  bool scores_needed = false;          // false: no mismatch, the scores are for information
  std::vector<CandidateFit> fits;      // recalibrated candidates, largest evidence first
  int chosen = -1;                     // index into fits; -1 when none is chosen
  // Of the chosen fit (else of the best fit, when any): over the base model, and over the
  // next candidate by evidence (NaN and "" when there is none).
  double bayes_factor_over_base = 0.0, bayes_factor_over_next = 0.0;
  std::string next_candidate;
  double chi_square_per_dof_before = 0.0,
         chi_square_per_dof_after = 0.0;  // after: NaN if none chosen
  std::vector<TargetComparison> fitted_targets, held_out_targets;
  std::vector<std::string> notes;
  std::string summary;

  // Calibration grids are large; leave them out unless asked. NaN -> null.
  nlohmann::json to_json(bool include_grids = false) const;
};

// Throws std::invalid_argument naming the offending input: as CalibrationProblem for the
// parameters and targets; two targets with the same setup and observable; a held-out
// target that is not a target, or listed twice; a setup variable of a setup no target
// has; a candidate as score_candidate (sensitivity length against `targets`), with a
// repeated name, a parameter named like a base parameter, or an extended target that is
// not a target, repeats one, has a model without (parameters + 1) inputs or a measured
// value or sigma_measured that differs from the target's; an option out of range.
DiscrepancyDiagnosis diagnose_discrepancy(const std::vector<ParameterBounds>& parameters,
                                          const std::vector<Target>& targets,
                                          const std::vector<CandidateModule>& candidates,
                                          const SetupVariables& setup_variables = {},
                                          const DiagnosisOptions& options = {});

}  // namespace demcal::calibrate
