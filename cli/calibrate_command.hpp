#pragma once
// `demcal calibrate <study.toml>`: the inverse problem (the work is
// study/study_calibration.hpp; this prints its lines and headline). Reads the study's
// recordings ([calibration] recordings, config/recordings_csv.hpp) and its fitted
// surrogates (<output>/<study>/surrogates/<setup>.<observable>.json, `demcal
// fit`), calibrates on every recording and, for the comparison the paper
// makes, on one observable alone (AoR by default), and writes
//   <output>/<study>/reports/calibration/index.html   the report (key figure)
//   <output>/<study>/reports/calibration/calibration.json
// With [calibration] verify = "<study config>", it then simulates that study's
// apparatus at the calibrated point (the paper's conical-pile verification)
// into <output>/<study>/verification/<config stem>/run.json and adds its
// observables to the report.
//
// `demcal study <study.toml>`: the whole pipeline in one command — doe, fit,
// inspect, calibrate — each stage skipped when its inputs have not changed
// since it last ran (study/study_pipeline.hpp: a digest of its inputs is kept
// in <output>/<study>/stages.json; `doe` itself reuses every stored run).

#include "cli/doe_command.hpp"
#include "cli/fit_command.hpp"

#include <filesystem>
#include <ostream>

namespace demcal::cli {

struct CalibrateOutcome {
  std::filesystem::path report;
  std::filesystem::path json;
};

CalibrateOutcome calibrate_study(const FitOptions& options, std::ostream& out, std::ostream& log);

struct StudyOptions {
  DoeOptions doe;           // study, overrides, output_dir, jobs, ...
  bool force = false;       // rerun fit, inspect and calibrate even if unchanged
};

// Returns the calibration report's path (or the inspection report's when the
// study has no [calibration]). Returns an empty path when runs were left undone.
std::filesystem::path run_study(const StudyOptions& options, std::ostream& out, std::ostream& log);

}  // namespace demcal::cli
