#pragma once
// One simulation from a config file, what `demcal simulate` runs (the command,
// cli/simulate_command.hpp, only prints). Two kinds of config:
//   a simulation config: assembled, stepped to [run] end_time_s or until at
//     rest, VTK snapshots every [output] snapshot_interval_s;
//   a study config (with [apparatus.*] tables, config/study_config.hpp): one
//     apparatus, chosen by `apparatus` when the study defines several, run
//     with its own protocol to the end of its event (fill, settle, release,
//     come to rest); run.json then holds its observables under their stable
//     names, its series and details.
// Either writes <output directory>/run.json (study/run_record.hpp) and, with
// [output] vtk = true, the VTK series.
//
// Errors: config::ConfigError for every input problem (a bad key, --apparatus
// on a simulation config, an existing run.json without `overwrite`), all found
// before anything runs. A run that fails (dem::InstabilityError, ...) still
// writes run.json with stopped_because = "error", then the error is rethrown.
//
// Progress: ProgressObserver::on_simulation_step, every 64 steps.

#include "study/progress_observer.hpp"
#include "study/run_record.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demcal::study {

struct SimulationRunOptions {
  std::filesystem::path config;
  // "dotted.key=value"; in a study, mu_s and mu_r stand for the particle-particle
  // sliding and rolling friction (config::study_override_aliases).
  std::vector<std::string> overrides;
  std::optional<std::string> output_dir;  // replaces output.directory
  std::optional<int> threads;             // replaces simulation.threads (study.threads)
  std::optional<std::string> apparatus;   // study configs: which apparatus to run
  bool overwrite = false;                 // allow replacing an earlier run.json
};

struct SimulationRunOutcome {
  std::filesystem::path run_record;  // <output directory>/run.json
  RunResults results;
  std::string name;       // the simulation's, or the study's
  std::string apparatus;  // study configs: the apparatus run; empty otherwise
  // The other engine that ran it ([engine], "lammps" or "liggghts"); empty for demcal's
  // own, which alone fills end_time_s, steps and particle_steps.
  std::string engine;
  // Study configs: ApparatusResult::observables (the stable names always present).
  nlohmann::json observables = nlohmann::json::object();
  double end_time_s = 0.0;  // simulated time reached
  std::int64_t steps = 0;
  std::size_t particles = 0;
  double particle_steps = 0.0;  // particles x steps, summed over the run
};

SimulationRunOutcome run_simulation(const SimulationRunOptions& options,
                                    ProgressObserver& observer);

}  // namespace demcal::study
