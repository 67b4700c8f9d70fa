#include "dem/contact/contact_law.hpp"

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
  return out;
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

}  // namespace

ContactLaw make_contact_law(const ContactLawSpec& spec) {
  ContactLaw law;
  law.normal = pick<NormalPart>("normal", spec.normal);
  law.adhesion = pick<AdhesionPart>("adhesion", spec.adhesion);
  law.tangential = pick<TangentialPart>("tangential", spec.tangential);
  law.rolling = pick<RollingPart>("rolling", spec.rolling);
  if (spec.cdt_own_angular_velocity) {
    auto* cdt = std::get_if<ConstantDirectionalTorque>(&law.rolling);
    if (cdt == nullptr)
      throw std::invalid_argument(
          "contact.cdt_own_angular_velocity applies only to rolling = \"cdt\"");
    cdt->own_angular_velocity = true;
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
