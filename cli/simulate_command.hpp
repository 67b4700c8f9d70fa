#pragma once
// `demcal simulate`: config -> assembled simulation -> stepped to the end time
// or until at rest -> VTK snapshots and run.json. A study config (one with
// [apparatus.*] tables, config/study_config.hpp) runs one apparatus instead
// (cli/apparatus_command.hpp).

#include "study/run_record.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace demcal::dem {
class Simulation;
}

namespace demcal::cli {

struct SimulateOptions {
  std::filesystem::path config;
  std::vector<std::string> overrides;     // "dotted.key=value"
  std::optional<std::string> output_dir;  // replaces output.directory
  std::optional<int> threads;             // replaces simulation.threads (study.threads)
  std::optional<std::string> apparatus;   // study configs: which apparatus to run
  bool overwrite = false;                 // allow replacing an earlier run.json
  bool quiet = false;                     // no summary line (paths are still printed)
  bool progress = false;                  // a live progress line on `progress_stream`
};

struct SimulateOutcome {
  std::filesystem::path run_record;
  study::RunResults results;
  // Study configs: ApparatusResult::observables (the stable names always present).
  nlohmann::json observables = nlohmann::json::object();
};

// One status line on a terminal, rewritten in place about twice a second.
class ProgressLine {
 public:
  ProgressLine(std::ostream& os, bool enabled);

  // `phase` leads the line when not empty (apparatus runs), with the wall time
  // spent so far. `end_s` is the simulated time the run, or the phase, ends at
  // the latest; the estimate of the time left is shown only when it is finite.
  void update(const dem::Simulation& sim, std::string_view phase = {},
              double end_s = std::numeric_limits<double>::infinity());
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  std::ostream& os_;
  bool enabled_;
  Clock::time_point start_;
  Clock::time_point last_;
  double last_particle_steps_ = 0.0;
  // Where the current phase began, for its own rate: the first phase's rate
  // says little about the next one's (a settling fill vs. a discharge).
  std::string phase_;
  double phase_start_s_ = 0.0;
  Clock::time_point phase_start_;
  std::size_t width_ = 0;
  bool shown_ = false;
};

// Throws ConfigError for problems with the inputs (all found before any
// computing) and other exceptions (dem::InstabilityError, ...) when the run
// fails; a failed run still leaves a run.json with stopped_because = "error".
SimulateOutcome simulate(const SimulateOptions& options, std::ostream& out,
                         std::ostream& progress_stream);

}  // namespace demcal::cli
