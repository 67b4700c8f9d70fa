#pragma once
// Each candidate physics with the generic model discrepancy on top of it, against the base
// model with the same discrepancy (issue 19; docs/model_discrepancy.md, "Candidate plus
// discrepancy"). For information: the verdict is still decide_explanation's.
//
// Why it is measured: recordings made by another engine differ from demcal's model by a form
// error that no physics removes. A candidate that is the missing physics then explains part
// of the mismatch, not all of it, and loses to the discrepancy alone (the cross-engine blind
// test, tests/concealed/lammps/README.md); the question it should be asked is whether it
// still helps once a discrepancy takes the rest:
//
//   log B = log Z(candidate + discrepancy) - log Z(base + discrepancy)
//
// Both evidences are discrepancy_evidence's (linearized at the model's own fit, the
// discrepancy's amplitudes integrated over their prior), the candidate's with its parameter
// and its extended surrogates, so the two are on one scale. At tau = 0 the candidate's is its
// own Laplace evidence at that fit (`log_evidence_without`), which should be close to the one
// diagnose_discrepancy reports.

#include "calibrate/discrepancy_diagnosis.hpp"
#include "calibrate/model_discrepancy.hpp"

#include <nlohmann/json.hpp>

#include <limits>
#include <string>
#include <vector>

namespace demcal::calibrate {

struct CandidateWithDiscrepancy {
  std::string name;
  bool available = false;  // false: `note` says why nothing was formed
  double log_evidence = std::numeric_limits<double>::quiet_NaN();  // candidate + discrepancy
  // The same formula at tau = 0: the candidate alone, linearized at its fit.
  double log_evidence_without = std::numeric_limits<double>::quiet_NaN();
  // log_evidence - log Z(base + discrepancy).
  double log_bayes_factor_over_base_with_discrepancy = std::numeric_limits<double>::quiet_NaN();
  // Posterior modes of the discrepancy's amplitudes with the candidate, in sigma_total units.
  double bias_amplitude = std::numeric_limits<double>::quiet_NaN();
  double process_amplitude = std::numeric_limits<double>::quiet_NaN();
  std::string note;

  nlohmann::json to_json() const;  // NaN -> null
};

// One entry per fit of `diagnosis` (in its order). `targets` and `held_out` as passed to
// diagnose_discrepancy; `modules` the candidates passed to it (matched to the fits by name);
// `base_with_discrepancy` judge_against_discrepancy's evidence. A candidate whose fitted
// targets are not all given extended surrogates (a first-order extension) is left out with a
// note, as is one whose linearization fails (a rank-deficient Jacobian). Throws
// std::invalid_argument as CalibrationProblem and discrepancy_evidence do.
std::vector<CandidateWithDiscrepancy> candidates_with_discrepancy(
    const std::vector<ParameterBounds>& parameters, const std::vector<Target>& targets,
    const std::vector<TargetKey>& held_out, const std::vector<CandidateModule>& modules,
    const DiscrepancyDiagnosis& diagnosis, const DiscrepancyEvidence& base_with_discrepancy,
    const SetupVariables& setup_variables = {}, const DiscrepancyOptions& options = {});

}  // namespace demcal::calibrate
