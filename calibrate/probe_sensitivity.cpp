#include "calibrate/probe_sensitivity.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace demcal::calibrate {
namespace {

void check(const ProbeMean& p, double single_run_sd, const char* who) {
  if (!std::isfinite(p.phi) || !std::isfinite(p.mean))
    throw std::invalid_argument(std::string(who) + ": a probe's phi and mean must be finite");
  if (!(p.runs >= 1.0) || !std::isfinite(p.runs))
    throw std::invalid_argument(std::string(who) + ": a probe is the mean of at least one run, got " +
                                std::to_string(p.runs));
  if (!(single_run_sd >= 0.0) || !std::isfinite(single_run_sd))
    throw std::invalid_argument(std::string(who) +
                                ": single_run_sd must be finite and >= 0, got " +
                                std::to_string(single_run_sd));
}

}  // namespace

ProbeSensitivity secant_sensitivity(const ProbeMean& a, const ProbeMean& b, double single_run_sd) {
  check(a, single_run_sd, "secant_sensitivity");
  check(b, single_run_sd, "secant_sensitivity");
  const double span = a.phi - b.phi;
  if (span == 0.0)
    throw std::invalid_argument("secant_sensitivity: the two probes ran at the same phi");
  ProbeSensitivity s;
  s.value = (a.mean - b.mean) / span;
  s.standard_error = single_run_sd * std::sqrt(1.0 / a.runs + 1.0 / b.runs) / std::abs(span);
  return s;
}

ProbeSensitivity sensitivity_against_prediction(const ProbeMean& a, double base_phi,
                                                double predicted_mean, double predicted_variance,
                                                double single_run_sd) {
  check(a, single_run_sd, "sensitivity_against_prediction");
  if (!std::isfinite(base_phi) || !std::isfinite(predicted_mean))
    throw std::invalid_argument(
        "sensitivity_against_prediction: base_phi and predicted_mean must be finite");
  if (!(predicted_variance >= 0.0) || !std::isfinite(predicted_variance))
    throw std::invalid_argument(
        "sensitivity_against_prediction: predicted_variance must be finite and >= 0");
  const double dphi = a.phi - base_phi;
  if (dphi == 0.0)
    throw std::invalid_argument(
        "sensitivity_against_prediction: the probe ran at the base value of phi");
  ProbeSensitivity s;
  s.value = (a.mean - predicted_mean) / dphi;
  s.standard_error =
      std::sqrt(single_run_sd * single_run_sd / a.runs + predicted_variance) / std::abs(dphi);
  return s;
}

}  // namespace demcal::calibrate
