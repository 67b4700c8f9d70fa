#include "dem/contact/contact_law.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>

namespace demcal::dem {
namespace {

template <class Variant, std::size_t I = 0>
bool assign_by_name(Variant& v, const std::string& name) {
  if constexpr (I < std::variant_size_v<Variant>) {
    using Part = std::variant_alternative_t<I, Variant>;
    if (name == Part::kName) {
      v = Part{};
      return true;
    }
    return assign_by_name<Variant, I + 1>(v, name);
  } else {
    return false;
  }
}

template <class Variant>
std::vector<std::string> names_of() {
  std::vector<std::string> out;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (out.emplace_back(std::variant_alternative_t<I, Variant>::kName), ...);
  }(std::make_index_sequence<std::variant_size_v<Variant>>{});
  // Two parts may share a name (one chosen by an option); list it once.
  std::vector<std::string> unique;
  for (const std::string& n : out)
    if (std::find(unique.begin(), unique.end(), n) == unique.end()) unique.push_back(n);
  return unique;
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "\"" : ", \"") + n + "\"";
  return s;
}

template <class Variant>
Variant pick(const std::string& role, const std::string& name) {
  Variant v;
  if (!assign_by_name(v, name))
    throw std::invalid_argument("contact." + role + ": unknown part \"" + name +
                                "\"; expected one of " + join(names_of<Variant>()));
  return v;
}

template <class Variant>
const char* name_of(const Variant& v) {
  return std::visit([](const auto& p) { return std::decay_t<decltype(p)>::kName; }, v);
}

template <class Part>
concept DeclaresParameters = requires { Part::kParameters; };

template <class Part>
void collect_part_parameters(const std::string& role, std::vector<RegisteredPartParameter>& out) {
  if constexpr (DeclaresParameters<Part>)
    for (const PartParameter& p : Part::kParameters) out.push_back({role, Part::kName, p});
}

// Plain function templates, not a templated lambda with a fold of lambdas:
// clang 14 (Debian 12's, which builds the fuzz harnesses) crashes on the latter.
template <class Variant, std::size_t... I>
void collect_parameters_of(const std::string& role, std::vector<RegisteredPartParameter>& out,
                           std::index_sequence<I...>) {
  (collect_part_parameters<std::variant_alternative_t<I, Variant>>(role, out), ...);
}

template <class Variant>
void collect_parameters(const std::string& role, std::vector<RegisteredPartParameter>& out) {
  collect_parameters_of<Variant>(role, out, std::make_index_sequence<std::variant_size_v<Variant>>{});
}

std::vector<RegisteredPartParameter> collect_all_parameters() {
  std::vector<RegisteredPartParameter> all;
  collect_parameters<NormalPart>("normal", all);
  collect_parameters<AdhesionPart>("adhesion", all);
  collect_parameters<TangentialPart>("tangential", all);
  collect_parameters<RollingPart>("rolling", all);
  std::set<int> slots;
  std::set<std::string> keys;
  for (const RegisteredPartParameter& r : all) {
    const PartParameter& p = r.parameter;
    const std::string who = "contact part \"" + r.part + "\", parameter " + p.key + ": ";
    if (!keys.insert(p.key).second) throw std::logic_error(who + "another part declares this key");
    if (p.legacy_field != nullptr) continue;
    if (p.slot < 0 || p.slot >= static_cast<int>(kPartValueSlots))
      throw std::logic_error(who + "slot " + std::to_string(p.slot) + " outside PartValues");
    if (!slots.insert(p.slot).second)
      throw std::logic_error(who + "slot " + std::to_string(p.slot) + " is taken by another part");
    if (!p.accepts(p.default_value)) throw std::logic_error(who + "default outside its range");
  }
  return all;
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

const std::vector<RegisteredPartParameter>& registered_part_parameters() {
  static const std::vector<RegisteredPartParameter> all = collect_all_parameters();
  return all;
}

const PartValues& default_part_values() {
  static const PartValues values = [] {
    PartValues v{};
    for (const RegisteredPartParameter& r : registered_part_parameters())
      if (r.parameter.legacy_field == nullptr)
        v[static_cast<std::size_t>(r.parameter.slot)] = r.parameter.default_value;
    return v;
  }();
  return values;
}

std::string part_parameter_range_text(const PartParameter& p) {
  const bool has_lo = std::isfinite(p.lo), has_hi = std::isfinite(p.hi);
  if (has_lo && has_hi)
    return std::string(p.lo_open ? "(" : "[") + number_text(p.lo) + ", " + number_text(p.hi) +
           (p.hi_open ? ")" : "]");
  if (has_lo) return std::string(p.lo_open ? "> " : ">= ") + number_text(p.lo);
  if (has_hi) return std::string(p.hi_open ? "< " : "<= ") + number_text(p.hi);
  return "any number";
}

const std::vector<std::string>& contact_roles() {
  static const std::vector<std::string> roles = {"normal", "adhesion", "tangential", "rolling"};
  return roles;
}

ContactLaw make_contact_law(const ContactLawSpec& spec) {
  ContactLaw law;
  law.normal = pick<NormalPart>("normal", spec.normal);
  law.adhesion = pick<AdhesionPart>("adhesion", spec.adhesion);
  law.tangential = pick<TangentialPart>("tangential", spec.tangential);
  law.rolling = pick<RollingPart>("rolling", spec.rolling);
  if (spec.cdt_own_angular_velocity) {
    if (!std::holds_alternative<ConstantDirectionalTorque>(law.rolling))
      throw std::invalid_argument(
          "contact.cdt_own_angular_velocity applies only to rolling = \"cdt\"");
    law.rolling = ConstantDirectionalTorqueOwnOmega{};
  }
  return law;
}

std::vector<std::string> known_part_names(const std::string& role) {
  if (role == "normal") return names_of<NormalPart>();
  if (role == "adhesion") return names_of<AdhesionPart>();
  if (role == "tangential") return names_of<TangentialPart>();
  if (role == "rolling") return names_of<RollingPart>();
  throw std::invalid_argument("unknown contact role \"" + role + "\"");
}

std::string ContactLaw::describe() const {
  return std::string("normal=") + name_of(normal) + " adhesion=" + name_of(adhesion) +
         " tangential=" + name_of(tangential) + " rolling=" + name_of(rolling);
}

}  // namespace demcal::dem
