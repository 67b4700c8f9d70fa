#pragma once
// The [calibration] table of a study config: what `demcal calibrate` fits the
// surrogates to, and how hard it looks. Every key but `recordings` is optional, and
// `recordings` too when the study measures its recordings from raw series
// ([raw_recordings], config/raw_recordings.hpp): a laboratory with only profiles and m(t)
// files needs no hand-made CSV.
//
//   [calibration]
//   recordings = "recordings.csv"     # relative to the study file; config/recordings_csv.hpp
//   alone = "angle_of_repose_deg"     # the single observable calibrated alone for the
//                                     #   comparison ("" = none); default: AoR if recorded
//   confidence = 0.95                 # of every region, (0, 1)
//   grid_points_per_axis = 121        # the likelihood-ratio grid, 11..1001
//   multistart_points = 16            # Ceres starts, 1..1000
//   mcmc_samples = 20000              # per chain after burn-in, 0 (no MCMC) ..10^7
//   mcmc_burn_in = 4000
//   mcmc_chains = 2                   # 1..16
//   seed = 1                          # starts and MCMC
//   verify = ""                       # opt: a study config (relative to this file) whose
//                                     #   apparatus is simulated at the calibrated point, e.g.
//                                     #   the paper's conical-pile check; "" = none
//   reference_label = "paper"         # opt: a point drawn on the key figure, e.g. the
//   reference_point = [0.3, 0.52]     #   paper's pair or the truth of synthetic recordings
//                                     #   (one value per [design] parameter, in its order)

#include "config/design_config.hpp"
#include "config/toml_reader.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demcal::config {

struct CalibrationConfig {
  // Resolved against the study file's directory; empty: none (the study's recordings all
  // come from [raw_recordings]).
  std::filesystem::path recordings;
  std::optional<std::string> alone;  // nullopt: the default rule
  double confidence = 0.95;
  int grid_points_per_axis = 121;
  int multistart_points = 16;
  int mcmc_samples = 20000;
  int mcmc_burn_in = 4000;
  int mcmc_chains = 2;
  std::uint64_t seed = 1;
  std::filesystem::path verify;  // resolved against the study file's directory; empty = none
  std::string reference_label;
  std::vector<double> reference_point;
};

// `design`: the study's, when it has one; the reference point must lie in its box.
// `has_raw_recordings`: the study has a [raw_recordings] table, so `recordings` may be
// left out.
std::optional<CalibrationConfig> read_calibration(
    reader::Table& root, const std::string& study_file,
    const std::optional<DesignConfig>& design = std::nullopt, bool has_raw_recordings = false);

}  // namespace demcal::config
