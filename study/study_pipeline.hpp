#pragma once
// `demcal study`: the whole pipeline of a study in one call — the design's
// runs, fit, inspect, calibrate — each later stage skipped while its inputs
// have not changed since it last ran (the stage cache, study/stage_cache.hpp,
// keeps their digests in <output>/<study>/stages.json; the design's runs are
// reused from the run store by the campaign itself).
//
// A stage's inputs:
//   fit        doe.csv, the [surrogate] and [design] tables;
//   inspect    those and the surrogate files;
//   calibrate  those, the [calibration] table and the recordings file.
// Refitting forgets inspect and calibrate, so they run again after it.
//
// The caller runs the stages (StudyPipelineSteps): the command line runs its
// own `doe`, `fit`, `inspect` and `calibrate`, which print as they always do.
// A skipped stage is reported to the observer ("fit: up to date (...)",
// on_message) and to StudyPipelineSteps::skipped.
//
// Errors: ConfigError when the study cannot be read; whatever a step throws.

#include "study/progress_observer.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace demcal::study {

struct StudyPipelineOptions {
  std::filesystem::path study;
  std::vector<std::string> overrides;  // --set
  std::filesystem::path output_dir = "out";
  bool force = false;  // run fit, inspect and calibrate even when up to date
};

class StudyPipelineSteps {
 public:
  virtual ~StudyPipelineSteps() = default;
  // Runs the design into the store and writes doe.csv; false when runs were
  // left undone (the pipeline stops there).
  virtual bool run_design() = 0;
  virtual void fit() = 0;
  virtual void inspect() = 0;
  virtual void calibrate() = 0;
  // `stage` ("inspect" or "calibrate") of the study named `study_name` was up
  // to date: `report` (its index.html) is the one it wrote before.
  virtual void skipped(const std::string& stage, const std::string& study_name,
                       const std::filesystem::path& report) {
    (void)stage;
    (void)study_name;
    (void)report;
  }
};

// Returns the calibration report's index.html (the inspection report's when the
// study has no [calibration]); an empty path when run_design() left runs undone.
std::filesystem::path run_study_pipeline(const StudyPipelineOptions& options,
                                         StudyPipelineSteps& steps, ProgressObserver& observer);

}  // namespace demcal::study
