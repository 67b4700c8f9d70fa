#include "calibrate/report/labels.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <regex>

namespace demcal::calibrate {
namespace {

struct ObservableText {
  const char* key;
  const char* name;
  const char* short_name;
  const char* unit;  // as written after a number
  const char* axis_unit;
};

constexpr std::array<ObservableText, 8> kObservables{{
    {"angle_of_repose_deg", "angle of repose", "AoR", "°", "°"},
    {"discharge_time_s", "discharge time", "time", " s", "s"},
    {"discharge_t25_s", "time to 25 % discharged", "t25", " s", "s"},
    {"discharge_t50_s", "time to 50 % discharged", "t50", " s", "s"},
    {"discharge_t75_s", "time to 75 % discharged", "t75", " s", "s"},
    {"mass_flow_rate_kg_s", "mass flow rate", "flow rate", " kg/s", "kg/s"},
    {"bulk_density_kg_m3", "bulk density", "bulk density", " kg/m³", "kg/m³"},
    {"discharged_mass_kg", "discharged mass", "mass", " kg", "kg"},
}};

const ObservableText* find(const std::string& key) {
  for (const auto& o : kObservables)
    if (key == o.key) return &o;
  return nullptr;
}

}  // namespace

std::string observable_label(const std::string& observable) {
  const auto* o = find(observable);
  return o ? std::string(o->name) + " (" + o->axis_unit + ")" : observable;
}

std::string observable_name(const std::string& observable) {
  const auto* o = find(observable);
  return o ? o->name : observable;
}

std::string observable_short(const std::string& observable) {
  const auto* o = find(observable);
  return o ? o->short_name : observable;
}

std::string observable_unit_suffix(const std::string& observable) {
  const auto* o = find(observable);
  return o ? o->unit : "";
}

std::string parameter_label(const std::string& parameter) {
  if (parameter == "mu_r") return "rolling friction mu_r";
  if (parameter == "mu_s") return "sliding friction mu_s";
  if (parameter == "restitution") return "restitution e";
  if (parameter == "surface_energy") return "surface energy (J/m²)";
  return parameter;
}

std::string humanize_identifiers(std::string text) {
  for (const auto& o : kObservables) {
    const std::string key = o.key, label = observable_label(o.key);
    for (const std::string& form : {"'" + key + "'", key}) {
      for (auto k = text.find(form); k != std::string::npos; k = text.find(form, k + label.size()))
        text.replace(k, form.size(), label);
    }
  }
  return text;
}

std::string humanize_sentence(std::string text) {
  text = humanize_identifiers(std::move(text));
  const auto replace_all = [&](const std::string& from, const std::string& to) {
    for (auto k = text.find(from); k != std::string::npos; k = text.find(from, k + to.size()))
      text.replace(k, from.size(), to);
  };
  replace_all("chi^2", "chi²");
  replace_all("+/-", "±");
  static const std::regex tiny(R"(-?\b[0-9]+(\.[0-9]+)?e-[1-9][0-9]+\b)");
  return std::regex_replace(text, tiny, "0");
}

std::string human_number(double v, int digits, double zero_below) {
  if (!std::isfinite(v)) return "—";
  if (std::abs(v) < zero_below) return "0";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string observable_value(const std::string& observable, double v, int digits) {
  return human_number(v, digits) + observable_unit_suffix(observable);
}

}  // namespace demcal::calibrate
