#pragma once
// The run record: one JSON file per run (<output dir>/run.json) holding what
// was run (engine version, the fully resolved inputs), how (seed, threads,
// time step) and what came out (final state, wall loads, outputs). It is the
// unit a calibration campaign collects, so it is never silently overwritten.

#include "cli/simulation_config.hpp"
#include "cli/study_config.hpp"
#include "dem/apparatus/apparatus.hpp"
#include "dem/output/vtk_writer.hpp"

#include <toml++/toml.h>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

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
  std::string phase;  // apparatus runs: the phase the run was in when it ended
};

// TOML to JSON; non-finite numbers become the strings "inf", "-inf", "nan"
// (JSON has no literal for them) and dates and times their TOML text.
nlohmann::json toml_to_json(const toml::node& node);

nlohmann::json make_run_record(const SimulationConfig& config, const RunResults& results);

// The VTK series of a run in `dir` when `enabled` (its paths noted in `results`), else null.
std::unique_ptr<dem::VtkSeries> open_vtk_series(const std::filesystem::path& dir, bool enabled,
                                                RunResults& results);

// The record of one apparatus run of a study: the same header and results as
// a plain run (inputs = the study resolved for this apparatus), plus
// "apparatus", and the ApparatusResult's "observables", "series" and "details".
// `result` is null when the run failed; the stable observables
// (stable_observable_names) are always present, null where not measured.
nlohmann::json make_apparatus_run_record(const StudyConfig& study, const StudyApparatus& apparatus,
                                         const RunResults& results,
                                         const dem::ApparatusResult* result);

// angle_of_repose_deg, discharge_time_s, mass_flow_rate_kg_s, bulk_density_kg_m3:
// the names a campaign reads from every apparatus run (every design table has them).
const std::vector<std::string>& stable_observable_names();
// discharge_t25_s, discharge_t50_s, discharge_t75_s: the m(t) series in three numbers --
// the time from the orifice's opening until 25, 50 and 75 % of the mass that finally
// passed had passed -- so that recordings, surrogates and the mismatch location can
// follow the segments of the discharge (a cohesive fill slows its end, air drag all of
// it). Read off the record's series.discharged_mass, so runs stored before these names
// existed give them too; null without a finished discharge (no m(t), or a clog).
const std::vector<std::string>& series_observable_names();
// The stable names, then the series ones: what a design table, a recording or a
// surrogate may name.
const std::vector<std::string>& observable_names();
// The physical range of an observable, as words ("a number in [0, 90] (degrees)"),
// and whether `value` lies in it: a recording, a design-table cell or a stored
// run outside it is refused (an AoR of 200 deg, a negative time, 1e308 kg/m3).
std::string observable_range_text(const std::string& observable);
bool observable_in_range(const std::string& observable, double value);
// The series observables of a run record's "series" and "observables" (see above).
nlohmann::json series_observables(const nlohmann::json& series, const nlohmann::json& observables);
// `observables` with every stable name present (null where not measured).
nlohmann::json with_stable_observables(nlohmann::json observables);

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

}  // namespace demcal::cli
