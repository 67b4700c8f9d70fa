#include "engines/material_card.hpp"

#include "dem/contact/pair_coefficients.hpp"
#include "engines/deck.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace demcal::engines {
namespace {

std::string n(double v) { return deck_number(v); }

double* field(dem::GranularMaterial& m, const std::string& name) {
  const auto dot = name.find('.');
  if (dot == std::string::npos) return nullptr;
  const std::string group = name.substr(0, dot), f = name.substr(dot + 1);
  if (group == "particle_particle" || group == "particle_wall") {
    auto& p = group == "particle_particle" ? m.particle_particle : m.particle_wall;
    if (f == "restitution") return &p.restitution;
    if (f == "sliding_friction") return &p.sliding_friction;
    if (f == "rolling_friction") return &p.rolling_friction;
    if (f == "rolling_stiffness_factor") return &p.rolling_stiffness_factor;
    if (f == "rolling_damping_ratio") return &p.rolling_damping_ratio;
    if (f == "surface_energy_j_m2") return &p.surface_energy_j_m2;
  }
  if (group == "particle") {
    if (f == "density_kg_m3") return &m.particle.density_kg_m3;
    if (f == "youngs_modulus_pa") return &m.particle.youngs_modulus_pa;
    if (f == "shear_modulus_pa") return &m.particle.shear_modulus_pa;
    if (f == "poisson_ratio") return &m.particle.poisson_ratio;
  }
  return nullptr;
}

std::string describe_contact(const dem::GranularMaterial& m) {
  std::string s = "normal " + m.contact.normal + ", adhesion " + m.contact.adhesion +
                  ", tangential " + m.contact.tangential + ", rolling " + m.contact.rolling;
  if (m.contact.cdt_own_angular_velocity) s += " (own angular velocity)";
  s += m.restitution_model == dem::RestitutionModel::kExact ? ", restitution exact"
                                                            : ", restitution linear_spring_formula";
  return s;
}

// The engine parameters a calibrated parameter moves, at the two interval
// ends: the mapping run again with the parameter at each end.
template <class MapFn>
std::string interval_through_mapping(const MaterialCardInput& in, const CalibratedParameter& c,
                                     MapFn map) {
  if (!std::isfinite(c.lower_95) || !std::isfinite(c.upper_95)) return "";
  dem::GranularMaterial lo = in.material, hi = in.material;
  set_material_parameter(lo, c.name, c.lower_95);
  set_material_parameter(hi, c.name, c.upper_95);
  const auto at = map(in.material), a = map(lo), b = map(hi);
  if (!at || !a || !b) return " (the interval end is outside what the engine can express)";
  std::string s;
  for (std::size_t i = 0; i < at->size() && i < a->size() && i < b->size(); ++i) {
    const auto& p0 = (*at)[i];
    const auto& pa = (*a)[i];
    const auto& pb = (*b)[i];
    if (pa.value == p0.value && pb.value == p0.value) continue;
    s +=
        "\n#       -> " + p0.pair + " " + p0.engine_name + " " + n(pa.value) + " .. " + n(pb.value);
  }
  return s;
}

// `target` names the engine the card is for; the warning is written unless the
// calibration ran on it (calibrated_on_target).
std::string header(const MaterialCardInput& in, const std::string& target,
                   bool calibrated_on_target, const std::string& target_words,
                   const std::vector<std::string>& approximations,
                   const std::function<std::string(const CalibratedParameter&)>& mapped_interval,
                   const std::string& comment = "# ") {
  const auto& p = in.provenance;
  std::ostringstream s;
  s << comment << "demcal material card for " << target_words << "\n";
  if (!p.study.empty()) s << comment << "study: " << p.study << "\n";
  s << comment << "calibrated on: " << engine_name(p.calibrated_engine)
    << (p.calibrated_engine_version.empty() ? "" : " " + p.calibrated_engine_version) << "\n"
    << comment << "contact model calibrated: "
    << (p.contact_model.empty() ? describe_contact(in.material) : p.contact_model) << "\n";
  if (!calibrated_on_target)
    s << comment << "WARNING: calibrated on " << engine_name(p.calibrated_engine)
      << ", written for " << target
      << ": the values are mapped term by term (engines/parameter_mapping.hpp), not calibrated in "
      << target << "; check one calibration observable in " << target
      << " before relying on them\n";
  s << comment << "reductions: coarse graining factor " << n(in.reduction.coarse_graining_factor);
  if (in.reduction.coarse_graining_factor != 1.0)
    s << " (parcels of " << n(in.reduction.coarse_graining_factor)
      << " x the grain diameter; surface energy x factor^2)";
  s << "; shear modulus "
    << (in.reduction.shear_modulus_pa > 0.0 ? n(in.reduction.shear_modulus_pa) + " Pa (reduced)"
                                            : std::string("as the material's"))
    << "\n";
  if (!in.calibrated.empty()) {
    s << comment << "calibrated values (95 % intervals):\n";
    for (const auto& c : in.calibrated) {
      s << comment << "  " << c.name << " = " << n(c.value);
      if (std::isfinite(c.lower_95) && std::isfinite(c.upper_95))
        s << "  [" << n(c.lower_95) << ", " << n(c.upper_95) << "]";
      else
        s << "  (fixed)";
      s << mapped_interval(c) << "\n";
    }
  }
  for (const auto& a : approximations) s << comment << "approximation: " << a << "\n";
  return s.str();
}

CardResult lammps_card(const MaterialCardInput& in, const MappingOptions& opt) {
  const auto r = map_to_lammps(in.material, in.reduction, opt);
  if (!r.ok()) return {std::nullopt, r.refusal};
  const auto& m = *r.mapping;
  auto map = [&](const dem::GranularMaterial& g) -> std::optional<std::vector<MappedParameter>> {
    const auto x = map_to_lammps(g, in.reduction, opt);
    if (!x.ok()) return std::nullopt;
    return x.mapping->parameters;
  };
  std::ostringstream s;
  s << header(in, "LAMMPS", in.provenance.calibrated_engine == Engine::kLammps,
              "LAMMPS (pair_style granular, 29Sep2021)", m.approximations,
              [&](const CalibratedParameter& c) { return interval_through_mapping(in, c, map); })
    << "# representative (volume-mean) diameter " << n(m.representative_diameter_m)
    << " m: the rolling stiffness and damping are stated for it\n"
    << "#\n# particles: atom_style sphere, SI units; set the density of every grain type to\n"
    << "variable        demcal_density equal " << n(m.density_kg_m3) << "\n"
    << "pair_style      granular\n"
    << "pair_coeff      * * " << m.particle_particle.granular_words() << "\n"
    << "# particle-wall: fix ID all wall/gran granular ${demcal_wall} <wallstyle args>\n"
    << "#            or fix ID all wall/gran/region granular ${demcal_wall} region <ID>\n"
    << "variable        demcal_wall string \"" << m.particle_wall.granular_words() << "\"\n";
  return {s.str(), ""};
}

CardResult liggghts_card(const MaterialCardInput& in, const MappingOptions& opt) {
  const auto r = map_to_liggghts(in.material, in.reduction, opt);
  if (!r.ok()) return {std::nullopt, r.refusal};
  const auto& m = *r.mapping;
  auto map = [&](const dem::GranularMaterial& g) -> std::optional<std::vector<MappedParameter>> {
    const auto x = map_to_liggghts(g, in.reduction, opt);
    if (!x.ok()) return std::nullopt;
    return x.mapping->parameters;
  };
  const auto& pp = m.particle_particle;
  const auto& pw = m.particle_wall;
  auto pair2 = [](double a, double b) { return n(a) + " " + n(b) + " " + n(b) + " " + n(b); };
  std::ostringstream s;
  s << header(in, "LIGGGHTS", in.provenance.calibrated_engine == Engine::kLiggghts,
              "LIGGGHTS 3.8 (pair_style gran)", m.approximations,
              [&](const CalibratedParameter& c) { return interval_through_mapping(in, c, map); })
    << "#\n# atom type 1: the grains (density " << n(m.density_kg_m3)
    << " kg/m3), atom type 2: the walls (meshes and primitives: type 2)\n"
    << "# (the wall-wall entry 2 2 is never used; it repeats the particle-wall value)\n"
    << (std::max(m.particle_youngs_modulus_pa, m.wall_youngs_modulus_pa) > 1e9
            ? "hard_particles  yes  # a modulus above 1 GPa (LIGGGHTS refuses it otherwise)\n"
            : "")
    << "fix             m1 all property/global youngsModulus peratomtype "
    << n(m.particle_youngs_modulus_pa) << " " << n(m.wall_youngs_modulus_pa) << "\n"
    << "fix             m2 all property/global poissonsRatio peratomtype "
    << n(m.particle_poisson_ratio) << " " << n(m.wall_poisson_ratio) << "\n"
    << "fix             m3 all property/global coefficientRestitution peratomtypepair 2 "
    << pair2(pp.restitution, pw.restitution) << "\n"
    << "fix             m4 all property/global coefficientFriction peratomtypepair 2 "
    << pair2(pp.sliding_friction, pw.sliding_friction) << "\n";
  if (m.rolling_model != "off")
    s << "fix             m5 all property/global coefficientRollingFriction peratomtypepair 2 "
      << pair2(pp.rolling_friction, pw.rolling_friction) << "\n";
  if (m.rolling_model == "epsd")
    s << "fix             m6 all property/global coefficientRollingViscousDamping peratomtypepair "
         "2 "
      << pair2(pp.rolling_damping_ratio, pw.rolling_damping_ratio) << "\n";
  s << "pair_style      gran " << m.pair_style_words() << "\n"
    << "pair_coeff      * *\n"
    << "# walls: fix ID all wall/gran " << m.model_words() << " primitive type 2 <args> "
    << m.settings_words() << "\n"
    << "#     or fix ID all wall/gran " << m.model_words() << " mesh n_meshes <n> meshes <IDs> "
    << m.settings_words() << "\n";
  return {s.str(), ""};
}

// EDEM's Hertz-Mindlin (no slip): restitution through the linear-spring
// formula (as LIGGGHTS), friction as demcal's, rolling friction type A (CDT)
// with the lever to the contact point and each grain's own angular velocity.
CardResult edem_card(const MaterialCardInput& in, const MappingOptions& opt) {
  const auto& mat = in.material;
  if (mat.contact.rolling == "epsd" || mat.contact.rolling == "sds")
    return {std::nullopt,
            "EDEM's standard rolling friction is the constant directional torque (type A); "
            "demcal's \"" +
                mat.contact.rolling +
                "\" (elastic-plastic spring-dashpot) has no standard EDEM counterpart"};
  // LIGGGHTS's mapping gives the restitution EDEM needs (same formula), but
  // its cdt lever is R*: EDEM's is the distance to the contact, as demcal's.
  const auto r = map_to_liggghts(mat, in.reduction, opt);
  if (!r.ok()) return {std::nullopt, "EDEM: " + r.refusal.substr(r.refusal.find(' ') + 1)};
  const auto& m = *r.mapping;
  dem::Material particle = mat.particle;
  if (in.reduction.shear_modulus_pa > 0.0) {
    particle.shear_modulus_pa = in.reduction.shear_modulus_pa;
    particle.youngs_modulus_pa = 0.0;
  }
  // LIGGGHTS's own approximations (its cdt, its walls) are not EDEM's.
  std::vector<std::string> approx = {
      "restitution: EDEM derives its damping from e by the linear-spring formula, as LIGGGHTS; "
      "the value below gives demcal's damping"};
  if (mat.contact.rolling == "cdt" && !mat.contact.cdt_own_angular_velocity)
    approx.push_back(
        "EDEM's type A opposes each grain's own angular velocity; demcal's cdt (as calibrated) the "
        "relative rolling");
  // EDEM is never the engine a demcal calibration ran on: always warned.
  const std::string text =
      header(in, "EDEM", false, "EDEM (Hertz-Mindlin no slip, rolling friction type A)", approx,
             [](const CalibratedParameter&) { return std::string(); });
  std::ostringstream c;
  c << "section,parameter,value,lower_95,upper_95,unit\n";
  auto find = [&](const std::string& name) -> const CalibratedParameter* {
    for (const auto& p : in.calibrated)
      if (p.name == name) return &p;
    return nullptr;
  };
  auto row = [&](const std::string& section, const std::string& param, double v,
                 const std::string& demcal_name, const std::string& unit, double scale = 1.0) {
    c << section << "," << param << "," << n(v * scale) << ",";
    const auto* p = find(demcal_name);
    if (p && std::isfinite(p->lower_95) && std::isfinite(p->upper_95))
      c << n(p->lower_95 * scale) << "," << n(p->upper_95 * scale);
    else
      c << ",";
    c << "," << unit << "\n";
  };
  const double gp = particle.shear_modulus();
  row("particle", "Poisson's ratio", particle.poisson_ratio, "particle.poisson_ratio", "-");
  row("particle", "Shear modulus", gp, "particle.shear_modulus_pa", "Pa");
  row("particle", "Density", particle.density_kg_m3, "particle.density_kg_m3", "kg/m3");
  row("geometry", "Poisson's ratio", mat.wall.poisson_ratio, "", "-");
  row("geometry", "Shear modulus", mat.wall.shear_modulus(), "", "Pa");
  row("geometry", "Density", mat.wall.density_kg_m3, "", "kg/m3");
  // Restitution: the interval ends are not carried through the damping map here.
  c << "particle-particle,Coefficient of restitution," << n(m.particle_particle.restitution)
    << ",,,-\n";
  row("particle-particle", "Coefficient of static friction", mat.particle_particle.sliding_friction,
      "particle_particle.sliding_friction", "-");
  row("particle-particle", "Coefficient of rolling friction",
      mat.particle_particle.rolling_friction, "particle_particle.rolling_friction", "-");
  c << "particle-geometry,Coefficient of restitution," << n(m.particle_wall.restitution)
    << ",,,-\n";
  row("particle-geometry", "Coefficient of static friction", mat.particle_wall.sliding_friction,
      "particle_wall.sliding_friction", "-");
  row("particle-geometry", "Coefficient of rolling friction", mat.particle_wall.rolling_friction,
      "particle_wall.rolling_friction", "-");
  return {text + c.str(), ""};
}

CardResult json_card(const MaterialCardInput& in, const MappingOptions& opt) {
  const auto& mat = in.material;
  nlohmann::json j;
  j["format"] = "demcal-material-card";
  j["format_version"] = 1;
  j["study"] = in.provenance.study;
  j["calibrated_on"] = {
      {"engine", engine_name(in.provenance.calibrated_engine)},
      {"version", in.provenance.calibrated_engine_version},
      {"contact_model",
       in.provenance.contact_model.empty() ? describe_contact(mat) : in.provenance.contact_model}};
  j["reductions"] = {{"coarse_graining_factor", in.reduction.coarse_graining_factor},
                     {"shear_modulus_pa", in.reduction.shear_modulus_pa}};
  j["warning"] =
      in.provenance.calibrated_engine == Engine::kDemcal
          ? nlohmann::json()
          : nlohmann::json("calibrated on " + engine_name(in.provenance.calibrated_engine) +
                           "; the demcal parameters below are that engine's, mapped");
  auto inter = [](const dem::InteractionParameters& p) {
    return nlohmann::json{{"restitution", p.restitution},
                          {"sliding_friction", p.sliding_friction},
                          {"rolling_friction", p.rolling_friction},
                          {"rolling_stiffness_factor", p.rolling_stiffness_factor},
                          {"rolling_damping_ratio", p.rolling_damping_ratio},
                          {"surface_energy_j_m2", p.surface_energy_j_m2}};
  };
  auto material_json = [](const dem::Material& m) {
    return nlohmann::json{{"name", m.name},
                          {"density_kg_m3", m.density_kg_m3},
                          {"youngs_modulus_pa", m.youngs_modulus()},
                          {"shear_modulus_pa", m.shear_modulus()},
                          {"poisson_ratio", m.poisson_ratio}};
  };
  j["demcal"] = {{"contact",
                  {{"normal", mat.contact.normal},
                   {"adhesion", mat.contact.adhesion},
                   {"tangential", mat.contact.tangential},
                   {"rolling", mat.contact.rolling},
                   {"cdt_own_angular_velocity", mat.contact.cdt_own_angular_velocity}}},
                 {"particle", material_json(mat.particle)},
                 {"wall", material_json(mat.wall)},
                 {"particle_particle", inter(mat.particle_particle)},
                 {"particle_wall", inter(mat.particle_wall)}};
  j["calibrated"] = nlohmann::json::array();
  for (const auto& c : in.calibrated) {
    auto num_or_null = [](double v) {
      return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
    };
    j["calibrated"].push_back({{"name", c.name},
                               {"value", num_or_null(c.value)},
                               {"lower_95", num_or_null(c.lower_95)},
                               {"upper_95", num_or_null(c.upper_95)}});
  }
  const auto l = map_to_lammps(mat, in.reduction, opt);
  j["engines"]["lammps"] = l.ok() ? l.mapping->to_json() : nlohmann::json{{"refused", l.refusal}};
  const auto g = map_to_liggghts(mat, in.reduction, opt);
  j["engines"]["liggghts"] = g.ok() ? g.mapping->to_json() : nlohmann::json{{"refused", g.refusal}};
  return {j.dump(2) + "\n", ""};
}

}  // namespace

CardFormat card_format_from_name(const std::string& name) {
  if (name == "lammps") return CardFormat::kLammps;
  if (name == "liggghts") return CardFormat::kLiggghts;
  if (name == "edem-csv") return CardFormat::kEdemCsv;
  if (name == "json") return CardFormat::kJson;
  throw std::invalid_argument(
      "unknown card format \"" + name +
      "\"; expected one of \"lammps\", \"liggghts\", \"edem-csv\", \"json\"");
}

std::string card_format_name(CardFormat f) {
  switch (f) {
    case CardFormat::kLammps:
      return "lammps";
    case CardFormat::kLiggghts:
      return "liggghts";
    case CardFormat::kEdemCsv:
      return "edem-csv";
    case CardFormat::kJson:
      return "json";
  }
  return "unknown";
}

void set_material_parameter(dem::GranularMaterial& m, const std::string& name, double value) {
  double* f = field(m, name);
  if (f == nullptr)
    throw std::invalid_argument(
        "unknown material parameter \"" + name +
        "\"; expected particle_particle.<f> or particle_wall.<f> (restitution, sliding_friction, "
        "rolling_friction, rolling_stiffness_factor, rolling_damping_ratio, surface_energy_j_m2) "
        "or "
        "particle.<f> (density_kg_m3, youngs_modulus_pa, shear_modulus_pa, poisson_ratio)");
  *f = value;
  // A modulus given replaces the other, as a config gives only one.
  if (name == "particle.youngs_modulus_pa") m.particle.shear_modulus_pa = 0.0;
  if (name == "particle.shear_modulus_pa") m.particle.youngs_modulus_pa = 0.0;
}

double material_parameter(const dem::GranularMaterial& m, const std::string& name) {
  dem::GranularMaterial copy = m;
  double* f = field(copy, name);
  if (f == nullptr) throw std::invalid_argument("unknown material parameter \"" + name + "\"");
  return *f;
}

CardResult write_material_card(const MaterialCardInput& in, CardFormat format,
                               const MappingOptions& mapping) {
  for (const auto& c : in.calibrated) material_parameter(in.material, c.name);  // names valid
  switch (format) {
    case CardFormat::kLammps:
      return lammps_card(in, mapping);
    case CardFormat::kLiggghts:
      return liggghts_card(in, mapping);
    case CardFormat::kEdemCsv:
      return edem_card(in, mapping);
    case CardFormat::kJson:
      return json_card(in, mapping);
  }
  return {std::nullopt, "unknown card format"};
}

}  // namespace demcal::engines
