#pragma once
// The recordings of a study (DESIGN.md "Files"): a CSV with the header
//   setup,observable,value,sigma,unit[,repeats]
// one row per measured quantity, e.g.
//   sandglass,angle_of_repose_deg,41.57,1.0,deg
//   sandglass,discharge_time_s,6.56,0.15,s
// sigma is the measurement's own uncertainty (instrument, reading); the
// test-to-test scatter is supplied by the DEM's replicate scatter, divided by
// sqrt(repeats) when the value is the mean of several tests (the optional
// column repeats, an integer >= 1, default 1).
// and, for time series, CSVs with the header time_s,<quantity> (e.g.
// time_s,discharged_mass_kg). Every row is checked: the setup must be an
// apparatus of the study, the observable one demcal measures (and, through
// require_measured_by_setups, one the setup's apparatus kind measures), the unit the
// observable's (as io/observable_registry.hpp declares it), the value and sigma finite numbers with
// sigma > 0, no observable twice for a setup. A bad row is a ConfigError naming
// file:line and the reason; nothing is calibrated from a file with one.

#include "calibrate/recording.hpp"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace demcal::config {

// `setups`: the study's apparatus names.
std::vector<calibrate::Recording> read_recordings_csv(const std::filesystem::path& path,
                                                      const std::vector<std::string>& setups);
// The same from a stream; `file` names it in messages (fuzzing, tests).
std::vector<calibrate::Recording> read_recordings_csv(std::istream& in,
                                                      const std::filesystem::path& file,
                                                      const std::vector<std::string>& setups);

calibrate::RecordedSeries read_series_csv(const std::filesystem::path& path,
                                          const std::string& setup);
calibrate::RecordedSeries read_series_csv(std::istream& in, const std::filesystem::path& path,
                                          const std::string& setup);

// "deg" for angle_of_repose_deg, ...: the unit io/observable_registry.hpp declares for
// a stable or series observable; throws std::out_of_range for any other name.
const std::string& unit_of_observable(const std::string& observable);

// A setup of the study as its recordings are checked against it: the apparatus'
// name and kind ("sandglass", "conical_pile", "rectangular_container").
struct RecordedSetup {
  std::string name;
  std::string kind;
};

// Refuses a recording naming an observable its setup's apparatus kind does not
// measure (io/observable_registry.hpp, "measured by"): a ConfigError
// "<file>:<line>: observable "discharge_time_s" is not measured by setup "pile",
// a conical_pile; a conical_pile measures angle_of_repose_deg, ...". A setup
// missing from `setups` is left to the reader's own check. `given_by`, when not
// empty, says where the value came from ("[raw_recordings.pile]").
void require_measured_by_setup(const calibrate::Recording& recording,
                               const std::filesystem::path& file, std::size_t line,
                               const std::vector<RecordedSetup>& setups,
                               const std::string& given_by = "");
// The same for every recording, at its own line of `file`.
void require_measured_by_setups(const std::vector<calibrate::Recording>& recordings,
                                const std::filesystem::path& file,
                                const std::vector<RecordedSetup>& setups);

}  // namespace demcal::config
