#pragma once
// The targets of a study's calibration: each recording (config/recordings_csv.hpp)
// joined with the surrogate fitted for its setup and observable
// (<study dir>/surrogates/<setup>.<observable>.json, `demcal fit`), and the
// DEM's replicate scatter of that surrogate's design, divided by
// sqrt(repeats) because a recorded mean of several tests scatters less than
// one test. Shared by `demcal calibrate` and `demcal diagnose`.

#include "calibrate/calibration_problem.hpp"
#include "calibrate/recording.hpp"
#include "config/calibration_config.hpp"
#include "config/study_config.hpp"
#include "surrogate/surrogate_fit.hpp"

#include <filesystem>
#include <vector>

namespace demcal::study {

// The study's [design] parameters as calibration bounds (ConfigError without [design]).
std::vector<calibrate::ParameterBounds> design_bounds(const config::StudyConfig& study);

// Reads a saved surrogate; ConfigError naming the file when it is missing or unreadable.
surrogate::FittedSurrogate load_surrogate(const std::filesystem::path& file);

// One target per recording. ConfigError (naming the recordings file and line)
// when a recording has no surrogate or the surrogate's inputs are not the
// study's [design] parameters.
std::vector<calibrate::Target> calibration_targets(
    const config::StudyConfig& study, const std::filesystem::path& study_dir,
    const std::vector<calibrate::Recording>& recordings);

// The solver options a [calibration] table asks for.
calibrate::CalibrationOptions calibration_options(const config::CalibrationConfig& config);

// The study's recordings file, read against its apparatus names.
std::vector<calibrate::Recording> study_recordings(const config::StudyConfig& study);

}  // namespace demcal::study
