#pragma once
// Raw recordings: each repeat's measured surface profile h(x) and mass series m(t), as the
// laboratory took them, measured here with the definitions demcal applies to its own runs
// (issue 19) instead of numbers a user derived by hand. A study table per setup:
//
//   [raw_recordings.sandglass]
//   profiles = ["raw/pile-1.csv", "raw/pile-2.csv", "raw/pile-3.csv"]   # opt, one per repeat
//   mass_series = ["raw/mass-1.csv", "raw/mass-2.csv", "raw/mass-3.csv"]  # opt, one per repeat
//   grain_diameter_m = 4.5e-4       # with profiles: the grains' median diameter (> 0), the
//                                   #   AoR rule's bin unit, as for a run's particles
//   height_reading_error_m = 2e-4   # with profiles: sd of one height reading (> 0)
//   fill_mass_kg = 0.34             # with mass_series: the charge (> 0); the engine's runs
//                                   #   use their fill too
//   mass_reading_error_kg = 1e-3    # with mass_series: sd of one balance reading (> 0)
//   time_reading_error_s = 5e-3     # with mass_series: sd of one clock reading (> 0)
//
// Paths are relative to the study file. At least one of profiles and mass_series; the
// setup must be an apparatus of the study. Files, strict (a bad cell is a ConfigError naming
// file:line:column and what was expected):
//   profile:  header position_m,height_m; rows of finite numbers, a height may be empty (no
//             reading there); positions along the pile's long axis, heights above its floor;
//             at least 4 readings;
//   m(t):     header time_s,discharged_mass_kg; time >= 0 strictly increasing, mass finite,
//             >= 0 and at most fill_mass_kg; at least 2 samples.
//
// What is measured, with demcal's own functions (dem/measure):
//   angle_of_repose_deg            measure_profile_angle_of_repose (the slice rule of every
//                                  run's pile: bins of 1.5 diameters, fit band 15-85 % of the
//                                  crest, both sides);
//   discharge_time_s, mass_flow_rate_kg_s
//                                  analyse_discharge with the sandglass's options (98 % of
//                                  the final mass; the 20-80 % steady window), a stall being
//                                  a gain below 3 mass reading errors;
//   discharge_t25_s, _t50_s, _t75_s
//                                  config::series_observables, as the design tables read them.
// Each observable's recording is the mean over the repeats that gave a value; its sigma is
// the reading error propagated to one repeat's value and averaged over the repeats
// (sqrt(sum sigma_k^2) / n); `repeats` is n, so that the calibration adds the DEM's
// test-to-test scatter over sqrt(n) (config/recordings_csv.hpp). The repeats' own sd is
// reported beside it: the observed test-to-test scatter, for comparison with the DEM's.

#include "calibrate/recording.hpp"
#include "config/toml_reader.hpp"

#include <filesystem>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace demcal::config {

struct RawSetupRecordings {
  std::string setup;
  std::vector<std::filesystem::path> profiles, mass_series;
  double grain_diameter_m = 0.0;
  double height_reading_error_m = 0.0;
  double fill_mass_kg = 0.0;
  double mass_reading_error_kg = 0.0;
  double time_reading_error_s = 0.0;
  std::size_t line = 0;
};

struct RawRecordingsConfig {
  std::vector<RawSetupRecordings> setups;  // in the study's apparatus order
};

// Reads [raw_recordings] if present; `setups` are the study's apparatus names, `study_file`
// the file relative paths start from.
std::optional<RawRecordingsConfig> read_raw_recordings(reader::Table& root,
                                                       const std::vector<std::string>& setups,
                                                       const std::string& study_file);

struct SurfaceProfile {
  std::vector<double> position_m, height_m;  // NaN height: no reading
};
struct MassSeries {
  std::vector<double> time_s, mass_kg;
};

// The readers, from a stream (`file` names it in messages; fuzzing, tests) or a path.
SurfaceProfile read_surface_profile_csv(std::istream& in, const std::string& file);
SurfaceProfile read_surface_profile_csv(const std::filesystem::path& path);
MassSeries read_mass_series_csv(std::istream& in, const std::string& file, double fill_mass_kg);
MassSeries read_mass_series_csv(const std::filesystem::path& path, double fill_mass_kg);

// One observable measured from the repeats.
struct RawMeasurement {
  std::string setup, observable;
  std::vector<double> values;        // per repeat that gave one
  std::vector<double> reading_sigma;  // per value: the reading error propagated to it
  double mean = 0.0;
  double sigma = 0.0;         // the reading error of the mean
  double repeats_sd = 0.0;    // sd over the repeats (NaN with one)
  std::vector<std::string> skipped;  // "raw/pile-2.csv: no valid side" and the like
};

// The observables of one repeat's profile / m(t), with the reading error propagated:
// name -> (value, sigma). Observables the data cannot give are left out, with the reason
// in `skipped` (a pile with fewer than 2 valid sides, a discharge that had not finished).
std::map<std::string, std::pair<double, double>> measure_profile(const SurfaceProfile& profile,
                                                                 double grain_diameter_m,
                                                                 double height_reading_error_m,
                                                                 std::string* skipped = nullptr);
std::map<std::string, std::pair<double, double>> measure_mass_series(
    const MassSeries& series, double fill_mass_kg, double mass_reading_error_kg,
    double time_reading_error_s, std::string* skipped = nullptr);

// Reads and measures every file of the study's raw recordings. ConfigError naming the file
// for a bad file, or the setup when no repeat gave an observable at all.
std::vector<RawMeasurement> measure_raw_recordings(const RawRecordingsConfig& config);

// As recordings (calibrate/recording.hpp), with repeats = the values' count.
std::vector<calibrate::Recording> to_recordings(const std::vector<RawMeasurement>& measured);

// One line per observable for the report: "sandglass discharge_time_s = 4.12 s from 3
// repeats (sd 0.05 s); reading error of the mean 0.006 s".
std::vector<std::string> raw_recording_lines(const std::vector<RawMeasurement>& measured);

}  // namespace demcal::config
