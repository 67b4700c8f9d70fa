#pragma once
// `demcal simulate`: one simulation config, or one apparatus of a study config,
// run to its end (study/simulation_run.hpp does the work; this prints a live
// progress line, the summary and the paths written).

#include "study/simulation_run.hpp"

#include <ostream>

namespace demcal::cli {

struct SimulateOptions : study::SimulationRunOptions {
  bool quiet = false;     // no summary line (paths are still printed)
  bool progress = false;  // a live progress line on `progress_stream`
};

using SimulateOutcome = study::SimulationRunOutcome;

// Throws as study::run_simulation: ConfigError for problems with the inputs
// (all found before any computing) and other exceptions (dem::InstabilityError,
// ...) when the run fails, after writing run.json with stopped_because = "error".
SimulateOutcome simulate(const SimulateOptions& options, std::ostream& out,
                         std::ostream& progress_stream);

}  // namespace demcal::cli
