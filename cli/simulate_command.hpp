#pragma once
// `demcal simulate`: config -> assembled simulation -> stepped to the end time
// or until at rest -> VTK snapshots and run.json.

#include "cli/run_record.hpp"

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace demcal::cli {

struct SimulateOptions {
  std::filesystem::path config;
  std::vector<std::string> overrides;     // "dotted.key=value"
  std::optional<std::string> output_dir;  // replaces output.directory
  std::optional<int> threads;             // replaces simulation.threads
  bool overwrite = false;                 // allow replacing an earlier run.json
  bool quiet = false;                     // no summary line (paths are still printed)
  bool progress = false;                  // a live progress line on `progress_stream`
};

struct SimulateOutcome {
  std::filesystem::path run_record;
  RunResults results;
};

// Throws ConfigError for problems with the inputs (all found before any
// computing) and other exceptions (dem::InstabilityError, ...) when the run
// fails; a failed run still leaves a run.json with stopped_because = "error".
SimulateOutcome simulate(const SimulateOptions& options, std::ostream& out,
                         std::ostream& progress_stream);

}  // namespace demcal::cli
