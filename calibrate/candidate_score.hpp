#pragma once
// Step 3 of the missing-physics workflow, the cheap part: which candidate physics module
// could explain the mismatch, judged at the base fit from a few DEM runs per candidate
// instead of a new design. The score (Lagrange-multiplier) test:
//
//   r   whitened residuals at the base fit, r_i = (y_i - f_i) / sigma_total_i
//   J   whitened base Jacobian d f / d theta / sigma_total (n x p)
//   j   whitened sensitivity, j_i = s_i / sigma_total_i, s_i = d mean_i / d phi at
//       (theta_hat, phi0), phi0 the value that switches the module off
//   M   = I - J (J^T J)^+ J^T: what the base parameters cannot mimic
//
//   LM = (r^T M j)^2 / (j^T M j) ~ chi^2(1) if the module is not needed,
//   phi_hat - phi0 = r^T M j / j^T M j (linearized estimate).
//
// For a model linear in theta and phi, LM is exactly the drop in chi^2 that refitting
// with phi free would bring.
//
// Active bounds. A base parameter at a bound that the fit presses against (chi^2 would
// fall further outside) cannot move in that direction, so it cannot mimic the signature
// there: its column is left out of J. Otherwise a base fit pinned at, say, the lowest
// friction of the box would "absorb" any candidate that also lowers the angle of repose.
//
// J is -(d r / d theta) from CalibrationProblem::residuals: r = (y - f) / sigma, so
// d r / d theta = -(d f / d theta) / sigma minus a term from the surrogate variance's
// slope (kept: it is part of the direction the fit can move in). Only span(J) enters M,
// so the sign does not matter.
//
// Noisy sensitivities. s comes from a few noisy DEM runs, with standard errors tau_i. Given
// r, the numerator T = (M r)^T j then varies by Var_s(T) = sum_i (M r)_i^2 tau_i^2 /
// sigma_i^2 on top of its variance j^T M j over the data, and the reported LM is
//
//   LM = T^2 / (j^T M j + sum_i (M r)_i^2 tau_i^2 / sigma_i^2)
//
// (errors in variables, delta method). It equals the plain LM when tau = 0 and is never
// larger; the test stays valid under the null because r and s come from independent runs.
// phi_hat is left as T / j^T M j: noise in s inflates j^T M j and so shrinks phi_hat
// slightly toward phi0 (attenuation); its standard error includes both variance terms.

#include "calibrate/calibration_problem.hpp"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace demcal::calibrate {

// The new physics' parameter. Which way it may move is read from its bounds: off_value
// equal to the lower bound means phi >= phi0 only (surface energy, from 0), equal to the
// upper bound phi <= phi0 only, anywhere else either way.
struct CandidateParameter {
  std::string name;        // e.g. "surface_energy_j_m2"; not empty
  double off_value = 0.0;  // phi0, in [lower, upper]
  double lower = 0.0;
  double upper = 1.0;  // finite, > lower
};

// Where the candidate's parameter may go from off_value; from the bounds, see above.
enum class ParameterSide { both, above_only, below_only };
ParameterSide allowed_side(const CandidateParameter& parameter);

// What one candidate module predicts at the base fit.
struct CandidateSignature {
  std::string name;  // e.g. "cohesion"; not empty
  CandidateParameter parameter;
  // d mean_i / d phi at (theta_hat, phi0), per target of the base problem, in observable
  // units per parameter unit.
  std::vector<double> sensitivity;
  // Standard errors of the sensitivities, per target (>= 0); empty: taken as exact.
  std::vector<double> sensitivity_se;
};

struct ScoreOptions {
  double alpha = 0.01;  // a candidate is significant when its p-value is below; (0, 1)
  // A candidate cannot be assessed when every |s_i| <= noise_z * se_i, or when the part of
  // its signature the base parameters cannot mimic (j^T M j) is no larger than noise_z^2
  // times what the sensitivities' noise alone would give (sum_i M_ii se_i^2 / sigma_i^2);
  // > 0.
  double noise_z = 2.0;
  // Its signature is confounded with the base parameters (a change of theta mimics it)
  // when j^T M j <= confounded_fraction * j^T j; [0, 1).
  double confounded_fraction = 1e-6;
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const ScoreOptions& options);

enum class ScoreStatus {
  assessed,
  cannot_be_assessed,  // its sensitivities are within their noise of 0
  confounded,          // a change of the base parameters produces the same signature
};
// "assessed", "cannot_be_assessed", "confounded".
const char* to_string(ScoreStatus status);

struct CandidateScore {
  std::string name, parameter_name;
  ScoreStatus status = ScoreStatus::assessed;
  // LM with the sensitivity-noise term (see above); 0 when the linearized estimate has the
  // forbidden sign or the candidate is not assessed.
  double lagrange_multiplier = 0.0;
  double lagrange_multiplier_plain = 0.0;  // the same without the noise term (the textbook LM)
  // Two-sided parameter: P(chi^2(1) >= LM). One-sided: P(Z >= z), z = T / sqrt(variance)
  // signed toward the allowed side (so a forbidden-sign estimate has p > 0.5). 1 when not
  // assessed.
  double p_value = 1.0;
  bool significant = false;  // assessed and p_value < alpha
  // Linearized estimate of phi - phi0, its standard error, and phi0 + that step.
  double phi_step = 0.0, phi_step_se = 0.0, phi_estimate = 0.0;
  bool sign_allowed = true;
  bool estimate_inside_bounds = true;  // phi_estimate within the parameter's bounds
  double base_chi_square = 0.0;
  double explained_fraction = 0.0;   // lagrange_multiplier / base_chi_square
  double orthogonal_fraction = 0.0;  // j^T M j / j^T j
  // Every |s_i| <= noise_z * se_i: the probes saw nothing. When false and the status is
  // still cannot_be_assessed, the probes saw an effect but the base parameters mimic all
  // of it that stands out of the noise; only a refit with phi free can tell.
  bool signature_within_noise = false;
  int rank = 0;                      // 1 = most promising (set by rank_candidates)
  std::string statement;             // one sentence

  nlohmann::json to_json() const;  // NaN -> null
};

// Throws std::invalid_argument naming the candidate and what is wrong (see
// score_candidate) when it does not fit a problem of `targets` targets.
void validate(const CandidateSignature& candidate, std::size_t targets);

// At theta (the base fit, parameter units). Throws std::invalid_argument naming the
// candidate and what is wrong: an empty name, a parameter with no name, bounds not finite or
// lower >= upper, off_value outside them, sensitivity or sensitivity_se of the wrong
// length (they must have one entry per target of `base`), a non-finite entry, a negative
// standard error; or theta of the wrong size.
CandidateScore score_candidate(const CalibrationProblem& base, const Eigen::VectorXd& theta,
                               const CandidateSignature& candidate, const ScoreOptions& options = {});

// Every candidate scored, then ranked: assessed ones by LM (largest first; ties keep the
// input order), then confounded, then those that cannot be assessed. Throws as
// score_candidate, and when two candidates share a name.
std::vector<CandidateScore> rank_candidates(const CalibrationProblem& base, const Eigen::VectorXd& theta,
                                            const std::vector<CandidateSignature>& candidates,
                                            const ScoreOptions& options = {});

}  // namespace demcal::calibrate
