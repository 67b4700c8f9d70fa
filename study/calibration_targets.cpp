#include "study/calibration_targets.hpp"

#include "calibrate/scatter_budget.hpp"
#include "config/doe_csv.hpp"
#include "config/recordings_csv.hpp"
#include "config/toml_reader.hpp"

#include <cmath>
#include <fstream>

namespace demcal::study {

using demcal::config::CalibrationConfig;
using demcal::config::ConfigError;
using demcal::config::StudyConfig;
using demcal::config::read_recordings_csv;

namespace fs = std::filesystem;

std::vector<calibrate::ParameterBounds> design_bounds(const StudyConfig& study) {
  if (!study.design)
    throw ConfigError(study.file + ": the study has no [design] table; calibrate needs its bounds");
  std::vector<calibrate::ParameterBounds> params;
  for (const auto& p : study.design->spec.parameters) params.push_back({p.name, p.lower, p.upper});
  return params;
}

surrogate::FittedSurrogate load_surrogate(const fs::path& file) {
  std::ifstream in =
      config::open_input_file(file, "a surrogate file (JSON) written by `demcal fit`",
                              "no such surrogate; run `demcal fit` first");
  try {
    return surrogate::fitted_surrogate_from_json(nlohmann::json::parse(in));
  } catch (const std::exception& e) {
    throw ConfigError(file.string() + ": not a surrogate file (" + e.what() + ")");
  }
}

calibrate::CalibrationOptions calibration_options(const CalibrationConfig& cc) {
  calibrate::CalibrationOptions co;
  co.confidence = cc.confidence;
  co.grid_points_per_axis = cc.grid_points_per_axis;
  co.multistart_points = cc.multistart_points;
  co.mcmc_samples = cc.mcmc_samples;
  co.mcmc_burn_in = cc.mcmc_burn_in;
  co.mcmc_chains = cc.mcmc_chains;
  co.seed = cc.seed;
  return co;
}

std::vector<calibrate::Recording> study_recordings(const StudyConfig& study) {
  if (!study.calibration)
    throw ConfigError(study.file + ": the study has no [calibration] table (recordings = \"...\")");
  std::vector<std::string> setups;
  std::vector<config::RecordedSetup> kinds;
  for (const auto& a : study.apparatus) {
    setups.push_back(a.name);
    kinds.push_back({a.name, a.kind});
  }
  std::vector<calibrate::Recording> all;
  if (!study.calibration->recordings.empty()) {
    all = read_recordings_csv(study.calibration->recordings, setups);
    // A row naming an observable its setup's kind does not measure (io/observable_registry.hpp).
    config::require_measured_by_setups(all, study.calibration->recordings, kinds);
  }
  if (!study.raw_recordings) return all;
  // The raw series measured as the runs are (config/raw_recordings.hpp), beside the numbers.
  for (auto r : to_recordings(measure_raw_recordings(*study.raw_recordings))) {
    for (const auto& raw : study.raw_recordings->setups)
      if (raw.setup == r.setup) {
        r.file = study.file;
        r.line = raw.line;
        config::require_measured_by_setup(r, study.file, raw.line, kinds,
                                          "[raw_recordings." + r.setup + "]");
      }
    for (const auto& a : all)
      if (a.setup == r.setup && a.observable == r.observable)
        throw ConfigError(study.calibration->recordings.string() + ":" + std::to_string(a.line) +
                          ": " + r.setup + " " + r.observable +
                          " is also measured from [raw_recordings." + r.setup +
                          "]; give it once");
    all.push_back(r);
  }
  return all;
}

std::vector<calibrate::Target> calibration_targets(
    const StudyConfig& study, const fs::path& study_dir,
    const std::vector<calibrate::Recording>& recordings) {
  const auto params = design_bounds(study);
  std::vector<std::string> names;
  for (const auto& p : params) names.push_back(p.name);
  std::vector<calibrate::Target> all;
  for (const auto& r : recordings) {
    const fs::path file = study_dir / "surrogates" / (r.setup + "." + r.observable + ".json");
    if (!fs::exists(file))
      throw ConfigError(r.file + ":" + std::to_string(r.line) + ": " + r.setup + " " +
                        r.observable + " is recorded but has no surrogate (" + file.string() +
                        "); add it to [surrogate] observables and run `demcal fit`");
    const auto fit = load_surrogate(file);
    if (fit.model->input_names() != names)
      throw ConfigError(file.string() +
                        ": the surrogate's inputs differ from the study's [design] parameters; "
                        "run `demcal fit` again");
    calibrate::Target t;
    t.setup = r.setup;
    t.observable = r.observable;
    t.measured = r.value;
    t.sigma_measured = r.sigma;
    // The value is a mean of r.repeats tests: its test-to-test scatter is the
    // DEM's single-run scatter over sqrt(repeats).
    t.sigma_dem = calibrate::recording_dem_sigma(fit.scatter.sd, r.repeats);
    t.model = fit.model;
    all.push_back(t);
  }
  return all;
}

}  // namespace demcal::study
