#include "config/observables.hpp"

#include "io/observable_registry.hpp"

#include <cmath>
#include <cstddef>

namespace demcal::config {

// Views of the one registry (io/observable_registry.hpp): no observable is declared here.

const std::vector<std::string>& stable_observable_names() {
  static const std::vector<std::string> names =
      io::observable_names_of_kind(io::ObservableKind::stable);
  return names;
}

namespace {
// The fraction of the final discharged mass each series observable is read at.
struct SeriesPoint {
  const char* name;
  double fraction;
};
constexpr SeriesPoint kSeriesPoints[] = {
    {"discharge_t25_s", 0.25}, {"discharge_t50_s", 0.50}, {"discharge_t75_s", 0.75}};
}  // namespace

const std::vector<std::string>& series_observable_names() {
  static const std::vector<std::string> names =
      io::observable_names_of_kind(io::ObservableKind::series);
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

std::string observable_range_text(const std::string& observable) {
  const io::ObservableInfo* o = io::find_observable(observable);
  return o ? std::string(o->range_text) : "a finite number";
}

bool observable_in_range(const std::string& observable, double value) {
  if (!std::isfinite(value)) return false;
  const io::ObservableInfo* o = io::find_observable(observable);
  if (o == nullptr) return true;
  return (o->lo_open ? value > o->lo : value >= o->lo) && value <= o->hi;
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
