#pragma once
// The observables demcal measures, by name: what a design table, a recording,
// a surrogate or a run record may name, and the physical range every reader
// holds a value of one to (an AoR of 200 deg, a negative time are refused).
// Views of the one registry, io/observable_registry.hpp, where every observable,
// its unit, labels, range and the apparatus that measure it are declared.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace demcal::config {

// The registry's stable observables (angle_of_repose_deg, discharge_time_s, ...):
// the names a campaign reads from every apparatus run (every design table has them).
const std::vector<std::string>& stable_observable_names();
// The registry's series observables, discharge_t25_s, discharge_t50_s, discharge_t75_s
// (config/observables.cpp holds the fraction each is read at): the m(t) series in three numbers --
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

}  // namespace demcal::config
