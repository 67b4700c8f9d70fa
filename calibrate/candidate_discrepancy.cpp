#include "calibrate/candidate_discrepancy.hpp"

#include "calibrate/detail/number_text.hpp"

#include <algorithm>
#include <stdexcept>

namespace demcal::calibrate {

nlohmann::json CandidateWithDiscrepancy::to_json() const {
  return {{"name", name},
          {"available", available},
          {"log_evidence", detail::number_json(log_evidence)},
          {"log_evidence_without", detail::number_json(log_evidence_without)},
          {"log_bayes_factor_over_base_with_discrepancy",
           detail::number_json(log_bayes_factor_over_base_with_discrepancy)},
          {"bias_amplitude", detail::number_json(bias_amplitude)},
          {"process_amplitude", detail::number_json(process_amplitude)},
          {"note", note}};
}

std::vector<CandidateWithDiscrepancy> candidates_with_discrepancy(
    const std::vector<ParameterBounds>& parameters, const std::vector<Target>& targets,
    const std::vector<TargetKey>& held_out, const std::vector<CandidateModule>& modules,
    const DiscrepancyDiagnosis& diagnosis, const DiscrepancyEvidence& base_with_discrepancy,
    const SetupVariables& setup_variables, const DiscrepancyOptions& options) {
  const auto is_held_out = [&](const Target& t) {
    return std::any_of(held_out.begin(), held_out.end(), [&](const TargetKey& k) {
      return k.setup == t.setup && k.observable == t.observable;
    });
  };
  std::vector<CandidateWithDiscrepancy> out;
  for (const CandidateFit& f : diagnosis.fits) {
    CandidateWithDiscrepancy c;
    c.name = f.name;
    const auto m = std::find_if(modules.begin(), modules.end(),
                                [&](const CandidateModule& x) { return x.name == f.name; });
    if (m == modules.end())
      throw std::invalid_argument("candidates_with_discrepancy: no candidate module named \"" +
                                  f.name + "\" for the fit of that name");
    // The candidate's targets: each fitted base target's extended surrogate, in the base
    // targets' order (the discrepancy's structure is built from setups and observables).
    std::vector<Target> extended;
    for (const Target& t : targets) {
      if (is_held_out(t)) continue;
      const auto e = std::find_if(
          m->extended_targets.begin(), m->extended_targets.end(),
          [&](const Target& x) { return x.setup == t.setup && x.observable == t.observable; });
      if (e == m->extended_targets.end()) {
        c.note = "no extended surrogate of " + t.setup + " " + t.observable +
                 " (a first-order extension): not formed";
        break;
      }
      extended.push_back(*e);
    }
    if (c.note.empty()) {
      if (f.theta.size() != static_cast<Eigen::Index>(parameters.size()))
        throw std::invalid_argument("candidates_with_discrepancy: the fit of \"" + f.name +
                                    "\" has " + std::to_string(f.theta.size()) +
                                    " base parameters, not " + std::to_string(parameters.size()));
      std::vector<ParameterBounds> bounds = parameters;
      bounds.push_back({f.parameter.name, f.parameter.lower, f.parameter.upper});
      Eigen::VectorXd at(f.theta.size() + 1);
      at << f.theta, f.phi;
      try {
        const CalibrationProblem problem(bounds, extended);
        const DiscrepancyEvidence d = discrepancy_evidence(problem, at, setup_variables, options);
        c.available = true;
        c.log_evidence = d.evidence.log_evidence;
        c.log_evidence_without = d.log_evidence_base;
        c.log_bayes_factor_over_base_with_discrepancy =
            d.evidence.log_evidence - base_with_discrepancy.evidence.log_evidence;
        c.bias_amplitude = d.bias_amplitude;
        c.process_amplitude = d.process_amplitude;
      } catch (const std::runtime_error& e) {
        c.note = std::string("not formed: ") + e.what();
      }
    }
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace demcal::calibrate
