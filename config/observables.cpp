#include "config/observables.hpp"

#include <cmath>
#include <cstddef>

namespace demcal::config {

const std::vector<std::string>& stable_observable_names() {
  static const std::vector<std::string> names = {"angle_of_repose_deg", "discharge_time_s",
                                                 "mass_flow_rate_kg_s", "bulk_density_kg_m3"};
  return names;
}

namespace {
struct SeriesPoint {
  const char* name;
  double fraction;  // of the final discharged mass
};
constexpr SeriesPoint kSeriesPoints[] = {
    {"discharge_t25_s", 0.25}, {"discharge_t50_s", 0.50}, {"discharge_t75_s", 0.75}};
}  // namespace

const std::vector<std::string>& series_observable_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const SeriesPoint& p : kSeriesPoints) n.emplace_back(p.name);
    return n;
  }();
  return names;
}

const std::vector<std::string>& observable_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n = stable_observable_names();
    for (const auto& s : series_observable_names()) n.push_back(s);
    return n;
  }();
  return names;
}

namespace {
struct ObservableRange {
  const char* name;
  double lo, hi;
  bool lo_open;
  const char* text;
};
// Times up to 1e5 s (a day of discharge is no laboratory test); flow rates up to 1e4 kg/s;
// bulk densities as material densities (up to 3e4 kg/m3).
constexpr ObservableRange kObservableRanges[] = {
    {"angle_of_repose_deg", 0.0, 90.0, false, "a number in [0, 90] (degrees)"},
    {"discharge_time_s", 0.0, 1e5, true, "a number in (0, 1e5] (seconds)"},
    {"mass_flow_rate_kg_s", 0.0, 1e4, false, "a number in [0, 1e4] (kg/s)"},
    {"bulk_density_kg_m3", 0.0, 3e4, true, "a number in (0, 3e4] (kg/m3)"},
    {"discharge_t25_s", 0.0, 1e5, false, "a number in [0, 1e5] (seconds)"},
    {"discharge_t50_s", 0.0, 1e5, false, "a number in [0, 1e5] (seconds)"},
    {"discharge_t75_s", 0.0, 1e5, false, "a number in [0, 1e5] (seconds)"}};

const ObservableRange* range_of(const std::string& observable) {
  for (const ObservableRange& r : kObservableRanges)
    if (observable == r.name) return &r;
  return nullptr;
}
}  // namespace

std::string observable_range_text(const std::string& observable) {
  const ObservableRange* r = range_of(observable);
  return r ? r->text : "a finite number";
}

bool observable_in_range(const std::string& observable, double value) {
  if (!std::isfinite(value)) return false;
  const ObservableRange* r = range_of(observable);
  if (r == nullptr) return true;
  return (r->lo_open ? value > r->lo : value >= r->lo) && value <= r->hi;
}

nlohmann::json series_observables(const nlohmann::json& series, const nlohmann::json& observables) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& name : series_observable_names()) out[name] = nullptr;
  const bool finished = observables.is_object() && observables.contains("discharge_time_s") &&
                        observables["discharge_time_s"].is_number();
  if (!finished || !series.is_object() || !series.contains("discharged_mass")) return out;
  const nlohmann::json& m = series["discharged_mass"];
  if (!m.contains("time_s") || !m.contains("mass_kg")) return out;
  const auto t = m["time_s"].get<std::vector<double>>();
  const auto mass = m["mass_kg"].get<std::vector<double>>();
  if (t.size() != mass.size() || mass.empty() || !(mass.back() > 0.0)) return out;
  for (const SeriesPoint& p : kSeriesPoints) {
    const double target = p.fraction * mass.back();
    for (std::size_t i = 0; i < mass.size(); ++i) {
      if (mass[i] < target) continue;
      // Linear between the samples around the crossing: the series is sampled every few ms.
      double v = t[i];
      if (i > 0 && mass[i] > mass[i - 1])
        v = t[i - 1] + (target - mass[i - 1]) / (mass[i] - mass[i - 1]) * (t[i] - t[i - 1]);
      out[p.name] = v;
      break;
    }
  }
  return out;
}

nlohmann::json with_stable_observables(nlohmann::json observables) {
  if (!observables.is_object()) observables = nlohmann::json::object();
  for (const std::string& name : stable_observable_names())
    if (!observables.contains(name)) observables[name] = nullptr;
  return observables;
}

}  // namespace demcal::config
