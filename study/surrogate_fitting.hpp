#pragma once
// Fitting a study's surrogates to its design table (`demcal fit`) and the
// inspection report of the saved ones (`demcal inspect`):
//   <output>/<study>/surrogates/<apparatus>.<observable>.json
//   <output>/<study>/reports/inspection/index.html
// cli/fit_command.hpp describes the files. The table is <output>/<study>/doe.csv
// (what `demcal doe` writes), or doe_csv (e.g. a checked-in table, so a fit
// needs no DEM run). Every row is checked against the study's [design] first.

#include "study/progress_observer.hpp"
#include "study/study_directory.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demcal::study {

struct SurrogateFitOptions {
  std::filesystem::path study;
  std::vector<std::string> overrides;  // --set
  std::filesystem::path output_dir = "out";
  std::optional<std::filesystem::path> doe_csv;  // empty: <output>/<study>/doe.csv
};

struct SurrogateFitOutcome {
  std::vector<std::filesystem::path> files;  // one per surrogate
  std::vector<std::string> warnings;         // surrogate error above the DEM's scatter, ...
};

// Fits and saves every surrogate ([surrogate] table); the set replaces the
// previous one whole or not at all. One on_message per surrogate (its model
// and validation); ConfigError for any problem of the table or the study.
SurrogateFitOutcome fit_surrogates(const SurrogateFitOptions& options, ProgressObserver& observer);

struct InspectionOutcome {
  std::filesystem::path html;         // the report's index.html
  std::vector<std::string> warnings;  // what the report found worth saying
};

// Writes the inspection report of the saved surrogates; notes (a comparison
// polynomial that could not be fitted) go to on_message.
InspectionOutcome inspect_surrogates(const SurrogateFitOptions& options,
                                     ProgressObserver& observer);

}  // namespace demcal::study
