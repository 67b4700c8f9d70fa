#pragma once
// The run record: one JSON file per run (<output dir>/run.json) holding what
// was run (engine version, the fully resolved inputs), how (seed, threads,
// time step) and what came out (final state, wall loads, outputs). It is the
// unit a calibration campaign collects, so it is never silently overwritten.

#include "config/observables.hpp"
#include "config/simulation_config.hpp"
#include "config/study_config.hpp"
#include "dem/apparatus/apparatus.hpp"
#include "dem/output/vtk_writer.hpp"

#include <toml++/toml.h>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace demcal::study {

// The DEMCAL_VERSION this library was built with ("unknown" if none).
std::string engine_version();

struct RunResults {
  std::string stopped_because;  // "at_rest" | "end_time" | "error"
  std::string error;            // the message, when stopped_because == "error"
  double wall_time_s = 0.0;
  double time_step_s = 0.0;                // 0 when the run failed before resolving it
  std::filesystem::path vtk_series;        // particles .pvd; empty without VTK output
  std::filesystem::path vtk_walls_series;  // walls .pvd
  std::size_t snapshots = 0;
  std::string phase;  // apparatus runs: the phase the run was in when it ended
};

// TOML to JSON; non-finite numbers become the strings "inf", "-inf", "nan"
// (JSON has no literal for them) and dates and times their TOML text.
nlohmann::json toml_to_json(const toml::node& node);

nlohmann::json make_run_record(const config::SimulationConfig& config, const RunResults& results);

// The VTK series of a run in `dir` when `enabled` (its paths noted in `results`), else null.
std::unique_ptr<dem::VtkSeries> open_vtk_series(const std::filesystem::path& dir, bool enabled,
                                                RunResults& results);

// The record of one apparatus run of a study: the same header and results as
// a plain run (inputs = the study resolved for this apparatus), plus
// "apparatus", and the ApparatusResult's "observables", "series" and "details".
// `result` is null when the run failed; the stable observables
// (stable_observable_names) are always present, null where not measured.
nlohmann::json make_apparatus_run_record(const config::StudyConfig& study,
                                         const config::StudyApparatus& apparatus,
                                         const RunResults& results,
                                         const dem::ApparatusResult* result);

std::filesystem::path run_record_path(const std::filesystem::path& output_dir);

// Throws ConfigError when <output_dir>/run.json exists and `overwrite` is false:
// an earlier run's record is the evidence of that run and must not be lost by accident.
void check_no_previous_run(const std::filesystem::path& output_dir, bool overwrite);

// check_no_previous_run, then, with `overwrite`, removes the replaced run's
// snapshots (they would otherwise linger beside the new ones); creates the directory.
void prepare_output_directory(const std::filesystem::path& output_dir, bool overwrite);

// Writes <output_dir>/run.json atomically.
void write_run_record(const std::filesystem::path& output_dir, const nlohmann::json& record);

// The record of a run that failed: into run.json, unless run.json holds a run
// that did not fail (an --overwrite that failed must not replace a good result);
// then into run.failed.json beside it. Returns the file written.
std::filesystem::path write_failed_run_record(const std::filesystem::path& output_dir,
                                              const nlohmann::json& record);

}  // namespace demcal::study
