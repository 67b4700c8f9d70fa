#pragma once
// `demcal diagnose <study.toml>`: when no parameter set of the base model
// reproduces the recordings, find where they part, name the physics the model
// left out, add it and show the fit improve. The workflow is
// study/diagnosis_workflow.hpp (what runs, in order, and what it writes);
// this command runs its steps (`demcal study`, `demcal doe`) and prints.

#include "study/diagnosis_workflow.hpp"
#include "study/run_evaluator.hpp"

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace demcal::cli {

struct DiagnoseOptions {
  std::filesystem::path study;
  std::vector<std::string> overrides;
  std::filesystem::path output_dir = "out";
  std::filesystem::path run_store;  // empty: each study's own; else shared by all (DoeOptions)
  int jobs = 2;
  bool quiet = false;
  const study::RunEvaluator* evaluator = nullptr;  // null: the DEM (DoeOptions)
};

using DiagnoseOutcome = study::DiagnosisOutcome;

DiagnoseOutcome diagnose(const DiagnoseOptions& options, std::ostream& out, std::ostream& log);

}  // namespace demcal::cli
