#include "calibrate/mismatch_detection.hpp"

#include "calibrate/detail/number_text.hpp"

#include <gsl/gsl_cdf.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace demcal::calibrate {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Below this a p-value is printed as a bound: its digits mean nothing once the chi-square
// approximation's own error dominates.
constexpr double kSmallestPrintedP = 1e-6;

using detail::fmt;
using detail::number_json;

void check_alpha(double alpha) {
  if (!(alpha > 0.0 && alpha < 1.0))
    throw std::invalid_argument("detect_mismatch: alpha must lie in (0, 1), got " + fmt(alpha, 6));
}

}  // namespace

const char* to_string(MismatchVerdict verdict) {
  switch (verdict) {
    case MismatchVerdict::reproduced: return "reproduced";
    case MismatchVerdict::mismatch: return "mismatch";
    case MismatchVerdict::untestable: return "untestable";
  }
  return "untestable";
}

std::string p_value_text(double p) {
  if (std::isnan(p)) return "p = n/a";
  if (p < kSmallestPrintedP) return "p < 1e-6";
  return "p = " + fmt(p, 2);
}

MismatchDetection detect_mismatch(double chi_square, int targets, int parameters,
                                  const DetectionOptions& options) {
  check_alpha(options.alpha);
  if (!(chi_square >= 0.0) || !std::isfinite(chi_square))
    throw std::invalid_argument("detect_mismatch: chi_square must be finite and >= 0, got " +
                                fmt(chi_square, 6));
  if (targets < 0) throw std::invalid_argument("detect_mismatch: targets must be >= 0, got " + std::to_string(targets));
  if (parameters < 0)
    throw std::invalid_argument("detect_mismatch: parameters must be >= 0, got " + std::to_string(parameters));

  MismatchDetection d;
  d.chi_square = chi_square;
  d.targets = targets;
  d.parameters = parameters;
  d.degrees_of_freedom = targets - parameters;
  d.alpha = options.alpha;
  if (d.degrees_of_freedom < 1) {
    d.verdict = MismatchVerdict::untestable;
    d.chi_square_per_dof = kNaN;
    d.p_value = kNaN;
    d.statement = "The test cannot be made: " + std::to_string(targets) + " recording" +
                  (targets == 1 ? "" : "s") + " for " + std::to_string(parameters) + " parameter" +
                  (parameters == 1 ? "" : "s") +
                  " leave no degrees of freedom, so the base model can match any such data.";
    return d;
  }
  d.chi_square_per_dof = chi_square / d.degrees_of_freedom;
  d.p_value = gsl_cdf_chisq_Q(chi_square, d.degrees_of_freedom);
  const std::string numbers = "(chi2/dof = " + fmt(d.chi_square_per_dof, 2) + ", " + p_value_text(d.p_value) + ")";
  if (d.p_value < options.alpha) {
    d.verdict = MismatchVerdict::mismatch;
    d.statement = "The recordings are not reproduced " + numbers + ".";
  } else {
    d.verdict = MismatchVerdict::reproduced;
    d.statement = "The base model reproduces the recordings " + numbers + ": no physics is added.";
  }
  return d;
}

MismatchDetection detect_mismatch(const CalibrationResult& base, const DetectionOptions& options) {
  if (base.minima.empty()) throw std::invalid_argument("detect_mismatch: the calibration result has no minimum");
  return detect_mismatch(base.minima.front().chi_squared, static_cast<int>(base.targets.size()),
                         static_cast<int>(base.parameters.size()), options);
}

nlohmann::json MismatchDetection::to_json() const {
  return {{"chi_square", number_json(chi_square)},
          {"targets", targets},
          {"parameters", parameters},
          {"degrees_of_freedom", degrees_of_freedom},
          {"chi_square_per_dof", number_json(chi_square_per_dof)},
          {"p_value", number_json(p_value)},
          {"alpha", alpha},
          {"verdict", to_string(verdict)},
          {"statement", statement}};
}

}  // namespace demcal::calibrate
