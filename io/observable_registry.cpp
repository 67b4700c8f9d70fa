#include "io/observable_registry.hpp"

#include <algorithm>

namespace demcal::io {
namespace {

using K = ObservableKind;

// The declarations. Times up to 1e5 s (a day of discharge is no laboratory test);
// flow rates up to 1e4 kg/s; bulk densities as material densities (up to 3e4 kg/m3).
//
// bulk_density_kg_m3 is declared measured by every kind: a poured heap's bulk density
// (its mass over the volume under its surface) is a laboratory measurement, and the
// analytic evaluator (study/analytic_evaluator.hpp) gives it for every apparatus. The
// DEM's conical pile and rectangular container do not compute it yet; their runs
// leave it null, so a recording of it for them is refused later, by `demcal fit` (no run
// measured it) or `demcal calibrate` (no surrogate for it).
// {name, unit, label, short label, display unit, lo, hi, lo open, range text, kind, measured by}
// clang-format off
const std::vector<ObservableInfo>& declarations() {
  static const std::vector<ObservableInfo> all = {
      {"angle_of_repose_deg", "deg", "angle of repose", "AoR", "°", 0.0, 90.0, false,
       "a number in [0, 90] (degrees)", K::stable,
       {"sandglass", "conical_pile", "rectangular_container"}},
      {"discharge_time_s", "s", "discharge time", "time", "s", 0.0, 1e5, true,
       "a number in (0, 1e5] (seconds)", K::stable, {"sandglass"}},
      {"mass_flow_rate_kg_s", "kg/s", "mass flow rate", "flow rate", "kg/s", 0.0, 1e4, false,
       "a number in [0, 1e4] (kg/s)", K::stable, {"sandglass"}},
      {"bulk_density_kg_m3", "kg/m3", "bulk density", "bulk density", "kg/m³", 0.0, 3e4, true,
       "a number in (0, 3e4] (kg/m3)", K::stable,
       {"sandglass", "conical_pile", "rectangular_container"}},
      // The m(t) series in three numbers: the time from the orifice's opening until 25,
      // 50 and 75 % of the mass that finally passed had passed (config/observables.hpp).
      {"discharge_t25_s", "s", "time to 25 % discharged", "t25", "s", 0.0, 1e5, false,
       "a number in [0, 1e5] (seconds)", K::series, {"sandglass"}},
      {"discharge_t50_s", "s", "time to 50 % discharged", "t50", "s", 0.0, 1e5, false,
       "a number in [0, 1e5] (seconds)", K::series, {"sandglass"}},
      {"discharge_t75_s", "s", "time to 75 % discharged", "t75", "s", 0.0, 1e5, false,
       "a number in [0, 1e5] (seconds)", K::series, {"sandglass"}},
      // Written beside the angle of repose by the pile rules (dem/measure/angle_of_repose).
      {"angle_of_repose_uncertainty_deg", "deg", "angle of repose uncertainty", "AoR sd", "°",
       0.0, 90.0, false, "a number in [0, 90] (degrees)", K::auxiliary,
       {"sandglass", "conical_pile", "rectangular_container"}},
      {"pile_height_m", "m", "pile height", "height", "m", 0.0, 1e2, false,
       "a number in [0, 1e2] (m)", K::auxiliary, {"conical_pile"}},
      {"pile_base_diameter_m", "m", "pile base diameter", "base diameter", "m", 0.0, 1e2, false,
       "a number in [0, 1e2] (m)", K::auxiliary, {"conical_pile"}},
      // The sandglass's m(t) (time_s,discharged_mass_kg).
      {"discharged_mass_kg", "kg", "discharged mass", "mass", "kg", 0.0, 1e4, false,
       "a number in [0, 1e4] (kg)", K::trace, {"sandglass"}},
  };
  return all;
}
// clang-format on

}  // namespace

std::string_view to_string(ObservableKind kind) {
  switch (kind) {
    case K::stable:
      return "stable";
    case K::series:
      return "series";
    case K::auxiliary:
      return "auxiliary";
    case K::trace:
      return "trace";
  }
  return "?";
}

const std::vector<std::string>& apparatus_kinds() {
  static const std::vector<std::string> kinds = {"sandglass", "conical_pile",
                                                 "rectangular_container"};
  return kinds;
}

const std::vector<ObservableInfo>& observable_registry() { return declarations(); }

const ObservableInfo* find_observable(std::string_view name) {
  for (const ObservableInfo& o : declarations())
    if (o.name == name) return &o;
  return nullptr;
}

std::vector<std::string> observable_names_of_kind(ObservableKind kind) {
  std::vector<std::string> names;
  for (const ObservableInfo& o : declarations())
    if (o.kind == kind) names.emplace_back(o.name);
  return names;
}

bool measures(std::string_view apparatus_kind, std::string_view observable) {
  const ObservableInfo* o = find_observable(observable);
  return o != nullptr && std::find(o->measured_by.begin(), o->measured_by.end(), apparatus_kind) !=
                             o->measured_by.end();
}

std::vector<std::string> recordable_observables(std::string_view apparatus_kind) {
  std::vector<std::string> names;
  for (const ObservableInfo& o : declarations())
    if ((o.kind == K::stable || o.kind == K::series) && measures(apparatus_kind, o.name))
      names.emplace_back(o.name);
  return names;
}

std::string value_suffix(const ObservableInfo& observable) {
  std::string suffix = observable.display_unit == "°" ? "" : " ";
  suffix.append(observable.display_unit);
  return suffix;
}

std::string observable_registry_table() {
  std::string out = "name | kind | unit | label | short | range | measured by\n";
  for (const ObservableInfo& o : declarations()) {
    std::string by;
    for (std::string_view k : o.measured_by) {
      if (!by.empty()) by += ", ";
      by.append(k);
    }
    out += std::string(o.name) + " | " + std::string(to_string(o.kind)) + " | " +
           std::string(o.unit) + " | " + std::string(o.label) + " | " + std::string(o.short_label) +
           " | " + std::string(o.range_text) + " | " + by + "\n";
  }
  return out;
}

}  // namespace demcal::io
