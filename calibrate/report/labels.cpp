#include "calibrate/report/labels.hpp"

#include "io/observable_registry.hpp"

#include <cmath>
#include <cstdio>
#include <regex>

namespace demcal::calibrate {
namespace {

// The labels are the registry's (io/observable_registry.hpp): no observable is named here.
const io::ObservableInfo* find(const std::string& key) { return io::find_observable(key); }

}  // namespace

std::string observable_label(const std::string& observable) {
  const auto* o = find(observable);
  return o ? std::string(o->label) + " (" + std::string(o->display_unit) + ")" : observable;
}

std::string observable_name(const std::string& observable) {
  const auto* o = find(observable);
  return o ? std::string(o->label) : observable;
}

std::string observable_short(const std::string& observable) {
  const auto* o = find(observable);
  return o ? std::string(o->short_label) : observable;
}

std::string observable_unit_suffix(const std::string& observable) {
  const auto* o = find(observable);
  return o ? io::value_suffix(*o) : "";
}

std::string parameter_label(const std::string& parameter) {
  if (parameter == "mu_r") return "rolling friction mu_r";
  if (parameter == "mu_s") return "sliding friction mu_s";
  if (parameter == "restitution") return "restitution e";
  if (parameter == "surface_energy") return "surface energy (J/m²)";
  return parameter;
}

std::string humanize_identifiers(std::string text) {
  for (const auto& o : io::observable_registry()) {
    const std::string key(o.name), label = observable_label(key);
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
