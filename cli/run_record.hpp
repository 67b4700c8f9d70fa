#pragma once
// The run record: one JSON file per run (<output dir>/run.json) holding what
// was run (engine version, the fully resolved inputs), how (seed, threads,
// time step) and what came out (final state, wall loads, outputs). It is the
// unit a calibration campaign collects, so it is never silently overwritten.

#include "cli/simulation_config.hpp"

#include <toml++/toml.h>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <string>

namespace demcal::cli {

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
};

// TOML to JSON; non-finite numbers become the strings "inf", "-inf", "nan"
// (JSON has no literal for them) and dates and times their TOML text.
nlohmann::json toml_to_json(const toml::node& node);

nlohmann::json make_run_record(const SimulationConfig& config, const RunResults& results);

std::filesystem::path run_record_path(const std::filesystem::path& output_dir);

// Throws ConfigError when <output_dir>/run.json exists and `overwrite` is false:
// an earlier run's record is the evidence of that run and must not be lost by accident.
void check_no_previous_run(const std::filesystem::path& output_dir, bool overwrite);

// Writes <output_dir>/run.json atomically.
void write_run_record(const std::filesystem::path& output_dir, const nlohmann::json& record);

}  // namespace demcal::cli
