#pragma once
// The surrogate inspection report: one HTML page (index.html) with SVG figures
// and the CSV/JSON behind each, for the surrogates of one study. It answers
// "can the calibration trust these models?": how well each predicts runs it
// was not fitted to (leave-one-out parity and standardized residuals, Q²,
// RMSE against the DEM's own scatter), what it looks like over the parameter
// box (maps with the design points), what it is made of (coefficients with
// standard errors, or hyperparameters), and which parameter drives it (Sobol
// indices).

#include "surrogate/surrogate_fit.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demcal::calibrate {

struct InspectedSurrogate {
  std::string setup;  // the apparatus, e.g. "sandglass"
  surrogate::FittedSurrogate fit;
  Eigen::MatrixXd design_x;  // the runs' inputs (for the maps)
  // The runs' values of this observable, one per row of design_x; NaN where a run gave
  // none (a pile that spread flat has no angle of repose). Empty: all gave one.
  Eigen::VectorXd design_y;
  // For a Gaussian process: a polynomial fitted to the same runs (degree by
  // leave-one-out), whose coefficient table with standard errors is the
  // paper-style regression equation; it is shown, not used.
  std::optional<surrogate::FittedSurrogate> companion_polynomial;
};

struct InspectionReportOptions {
  std::string study_name;
  std::vector<std::string> parameter_names;
  std::vector<double> lower, upper;
  int map_points_per_axis = 81;
  std::size_t sobol_base_samples = 16384;
};

struct InspectionReportFiles {
  std::filesystem::path html;  // <directory>/index.html
  std::filesystem::path json;  // <directory>/inspection.json: the numbers of every table
  std::vector<std::string> warnings;
};

// The model in words, as the report and the console write it ("..., nugget from
// replicates, 22 points" where the model stores per-point nuggets taken from replicates).
std::string surrogate_description(const surrogate::FittedSurrogate& fit);

// Writes the report into `directory` (created). Throws std::runtime_error when
// gnuplot fails, std::invalid_argument on inconsistent inputs.
InspectionReportFiles write_inspection_report(const std::filesystem::path& directory,
                                              const std::vector<InspectedSurrogate>& surrogates,
                                              const InspectionReportOptions& options);

}  // namespace demcal::calibrate
