#pragma once
// The calibration report: one HTML page that opens with a headline box — per parameter
// the calibrated value, its 95 % intervals from the likelihood-ratio region and the
// posterior, the Gauss-Newton +- (marked local), whether AoR + time and AoR alone
// identify it; then the area ratio, the parts of each region (islands between design
// points flagged), the reference point and the fit, in words. Then the key figure as
// filled panels — AoR alone | AoR + time | the posterior — with iso-lines labelled with
// their units, the surrogates' uncertainty and Sobol indices over the 95 % region, the
// solver's notes, the minima with chi-square and residuals, and the MCMC marginals
// (best point and reference marked) and traces. The CSV/JSON behind every figure is
// written beside it; docs/guide.md explains each section.

#include "calibrate/calibration.hpp"
#include "calibrate/region_components.hpp"

#include <filesystem>
#include <memory>
#include <optional>
#include <limits>
#include <string>
#include <vector>

namespace demcal::calibrate {

struct ReferencePoint {
  std::string label;  // e.g. "paper (0.3, 0.52)" or "truth"
  std::vector<double> theta;
  // chi^2(theta) - chi^2_min of each calibration (NaN: not evaluated), and
  // whether theta lies in its 95 % likelihood-ratio region: what a recovery
  // check of synthetic recordings asks.
  double delta_chi_square_joint = std::numeric_limits<double>::quiet_NaN();
  double delta_chi_square_alone = std::numeric_limits<double>::quiet_NaN();
  bool inside_joint = false, inside_alone = false;
};

struct CalibrationReportOptions {
  std::string study_name;
  // The design's points (rows, parameters' order; may be empty): drawn on the key figure,
  // and a part of a 95 % region that holds none of them is flagged as existing only
  // between design points.
  Eigen::MatrixXd design_points;
  // The surrogate of each of the joint calibration's targets (same order; may be empty):
  // their uncertainty and Sobol indices are reported over the 95 % region, where they
  // matter, not only over the box.
  std::vector<std::shared_ptr<const surrogate::SurrogateModel>> models;
  std::vector<ReferencePoint> references;
  // Free text (plain) appended under the key figure, e.g. what a verification run gave.
  std::vector<std::string> remarks;
};

struct CalibrationReportFiles {
  std::filesystem::path html, json;
};

// `alone` may be null (no single-observable comparison); `joint` is the
// calibration on every recording. Needs 2 parameters for the plane figure
// (other counts get the tables and marginals only).
CalibrationReportFiles write_calibration_report(const std::filesystem::path& directory,
                                                const CalibrationResult* alone,
                                                const CalibrationResult& joint,
                                                const CalibrationReportOptions& options);

// The headline: one row per parameter, cells in plain words, and the sentences under it
// (area ratio, parts of the regions, reference points, fit). The HTML box, the JSON's
// "headline" and the console's closing summary are all made from it, so they agree.
struct Headline {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> sentences;
};
Headline calibration_headline(const CalibrationResult* alone, const CalibrationResult& joint,
                              const CalibrationReportOptions& options);

// "2 recordings for 2 parameters: no degrees of freedom left, the fit can match any data"
// or "chi² = 1.2 on 3 degrees of freedom, p = 0.75".
std::string fit_text(const CalibrationResult& r);

// "mu_s is identified: its 95 % region spans 0.47-0.58, clear of both bounds" etc.
std::vector<std::string> identification_statements(const CalibrationResult& r, const std::string& label);

}  // namespace demcal::calibrate
