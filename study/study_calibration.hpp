#pragma once
// Calibrating a study (`demcal calibrate`, cli/calibrate_command.hpp): its
// recordings against its fitted surrogates, on every recording and, for the
// comparison the paper makes, on one observable alone (AoR by default); the
// reference point and the verification run ([calibration] verify) placed
// against the result; the report written whole into
// <output>/<study>/reports/calibration/.

#include "calibrate/report/calibration_report.hpp"
#include "study/progress_observer.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace demcal::study {

struct StudyCalibrationOptions {
  std::filesystem::path study;
  std::vector<std::string> overrides;  // --set
  std::filesystem::path output_dir = "out";
};

// [calibration] verify: another study's apparatus simulated at the calibrated
// point (the paper's conical-pile verification). The caller says how it runs:
// simulate_verification below, or anything else that yields its observables.
struct VerificationRun {
  std::filesystem::path config;        // the study config to simulate
  std::vector<std::string> overrides;  // the calibrated values, "name=value"
  std::filesystem::path output_dir;    // <study dir>/verification/<config stem>
};
struct VerificationResult {
  nlohmann::json observables = nlohmann::json::object();
  std::filesystem::path run_record;
};
using Verifier = std::function<VerificationResult(const VerificationRun&)>;

// What `demcal calibrate` verifies with: `run` simulated by study::run_simulation
// (study/simulation_run.hpp), silently, replacing an earlier run.json there.
// Throws as run_simulation.
VerificationResult simulate_verification(const VerificationRun& run);

struct StudyCalibrationOutcome {
  std::filesystem::path report;  // index.html
  std::filesystem::path json;    // calibration.json
  std::string study_name;
  calibrate::Headline headline;  // the report's headline box, for a closing summary
};

// The headline a calibration report's calibration.json keeps (what `demcal
// study` shows again when calibrate was up to date); nothing when the file
// cannot be read or holds none (a report from before the headline).
std::optional<calibrate::Headline> read_calibration_headline(
    const std::filesystem::path& calibration_json);

// ConfigError for any input problem (no [calibration], no [design], an
// `alone` observable without recordings, a reference point of the wrong size).
// Progress lines go to `observer`'s on_message.
StudyCalibrationOutcome calibrate_study_recordings(const StudyCalibrationOptions& options,
                                                   const Verifier& verify,
                                                   ProgressObserver& observer);

}  // namespace demcal::study
