#pragma once
// Step 1 of the missing-physics workflow (docs/design.md): does the calibrated base model
// reproduce the recordings at all? The chi-square of the standardized residuals at the
// best minimum against its n - p degrees of freedom.

#include "calibrate/calibration.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace demcal::calibrate {

struct DetectionOptions {
  // A mismatch is declared when the chi-square p-value falls below alpha; (0, 1). With
  // 0.01 a correct model raises a false alarm in 1 calibration out of 100.
  double alpha = 0.01;
};

enum class MismatchVerdict {
  reproduced,  // p >= alpha: no physics is added
  mismatch,    // p < alpha
  untestable,  // fewer targets than parameters + 1: the fit can match any data
};

// "reproduced", "mismatch", "untestable".
const char* to_string(MismatchVerdict verdict);

struct MismatchDetection {
  double chi_square = 0.0;
  int targets = 0, parameters = 0;
  int degrees_of_freedom = 0;       // targets - parameters
  double chi_square_per_dof = 0.0;  // NaN when untestable
  double p_value = 0.0;             // P(chi^2(dof) >= chi_square); NaN when untestable
  double alpha = 0.01;
  MismatchVerdict verdict = MismatchVerdict::untestable;
  // One sentence for the report, e.g. "The recordings are not reproduced (chi2/dof = 9.1,
  // p < 1e-6)."
  std::string statement;

  bool mismatch() const { return verdict == MismatchVerdict::mismatch; }
  nlohmann::json to_json() const;  // NaN -> null
};

// From the base model's calibration (minima[0], every recording that was fitted).
// Throws std::invalid_argument when the result has no minimum or alpha is not in (0, 1).
MismatchDetection detect_mismatch(const CalibrationResult& base, const DetectionOptions& options = {});

// The same from the numbers alone. Throws std::invalid_argument naming chi_square (< 0 or
// not finite), targets, parameters (< 0) or alpha.
MismatchDetection detect_mismatch(double chi_square, int targets, int parameters,
                                  const DetectionOptions& options = {});

// "p < 1e-6" below 1e-6, else "p = 0.012" (two significant digits); "p = n/a" for NaN.
// Shared by the workflow's sentences so that every p-value reads alike.
std::string p_value_text(double p);

}  // namespace demcal::calibrate
