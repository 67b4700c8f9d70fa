#pragma once
// `demcal export <study> --to liggghts|lammps|edem-csv|json`: the calibrated
// material card (engines/material_card.hpp) from a study's calibration
// output. The calibrated values are the joint calibration's best minimum and
// their 95 % intervals the likelihood-ratio region's extent
// (<output>/<study>/reports/calibration/calibration.json, what `demcal
// calibrate` writes); every other parameter is the study's as written. The
// card states the engine the study was calibrated on ([engine], demcal when
// absent) and its version (from the run store), the contact model, the
// reductions of the study's first apparatus (coarse graining, reduced
// modulus), and warns when the target engine is not the calibrated one.

#include "engines/material_card.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demcal::study {

struct MaterialExportOptions {
  std::filesystem::path study;
  std::vector<std::string> overrides;  // --set
  std::filesystem::path output_dir = "out";
  std::string to;  // "liggghts" | "lammps" | "edem-csv" | "json"
  // Where the card goes; default <output>/<study>/material/<study>.<to>.<ext>.
  std::optional<std::filesystem::path> card;
};

struct MaterialExportOutcome {
  std::filesystem::path card;
  std::vector<std::string> warnings;  // the target engine is not the calibrated one, ...
  engines::MaterialCardInput input;   // what the card was written from
};

// ConfigError for an unknown format, a study without [design] or a
// calibration, a calibrated parameter the card cannot hold; std::runtime_error
// when the target engine cannot express the material (the refusal).
MaterialExportOutcome export_material_card(const MaterialExportOptions& options);

// The card's input from a study and its calibration.json (exposed for tests).
engines::MaterialCardInput material_card_input(const std::filesystem::path& study,
                                               const std::vector<std::string>& overrides,
                                               const std::filesystem::path& calibration_json,
                                               const std::filesystem::path& runs_dir);

}  // namespace demcal::study
