#pragma once
// `demcal fit <study.toml>`: fits (study/surrogate_fitting.hpp) the study's surrogates ([surrogate]
// table, config/surrogate_config.hpp) to its design table and saves each as JSON:
//   <output>/<study>/surrogates/<apparatus>.<observable>.json
// (model with every coefficient and hyperparameter, the spec, the DEM's
// replicate scatter, leave-one-out validation). The table is
// <output>/<study>/doe.csv (what `demcal doe` writes), or --doe FILE (e.g. a
// checked-in doe.csv, so a fit needs no DEM run).
//
// `demcal inspect <study.toml>` writes the surrogate inspection report from the
// saved surrogates: <output>/<study>/reports/inspection/index.html.

#include "study/study_directory.hpp"
#include "study/surrogate_fitting.hpp"

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace demcal::cli {

struct FitOptions {
  std::filesystem::path study;
  std::vector<std::string> overrides;
  std::filesystem::path output_dir = "out";
  std::optional<std::filesystem::path> doe_csv;
  bool quiet = false;
};

struct FitOutcome {
  std::vector<std::filesystem::path> files;  // one per surrogate
  std::vector<std::string> warnings;         // surrogate error above the DEM's scatter, ...
};

FitOutcome fit(const FitOptions& options, std::ostream& out, std::ostream& log);

// Returns the report's index.html.
std::filesystem::path inspect(const FitOptions& options, std::ostream& out, std::ostream& log);

using study::study_directory;

}  // namespace demcal::cli
