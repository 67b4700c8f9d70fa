#include "engines/parameter_mapping.hpp"

#include "engines/deck.hpp"

#include "dem/contact/constant_spring_rolling.hpp"
#include "dem/contact/jkr_adhesion.hpp"
#include "dem/contact/pair_coefficients.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace demcal::engines {
namespace {

std::string num(double v) { return deck_number(v); }

struct Resolved {
  dem::Material particle;
  dem::Material wall;
  dem::PairCoefficients pp;
  dem::PairCoefficients pw;
  double diameter_m = 0.0;
  double mass_kg = 0.0;
};

// The refusals both engines share (LAMMPS maps JKR adhesion and air drag, see
// the header; LIGGGHTS does not), then the pair coefficients as the engine
// would resolve them (install_materials' reduction applied).
std::string common_refusal(const std::string& engine, const dem::GranularMaterial& m,
                           bool maps_jkr_and_drag) {
  if (m.contact.normal != "hertz")
    return engine + " cannot use demcal's normal part \"" + m.contact.normal + "\"";
  if (m.contact.adhesion != "none" && !(maps_jkr_and_drag && m.contact.adhesion == "jkr"))
    return engine + " cannot reproduce demcal's adhesion \"" + m.contact.adhesion + "\" (" +
           (m.contact.adhesion == "jkr"
                ? std::string("EDEM-form JKR with demcal's hysteresis and friction load")
                : std::string("demcal's own adhesion part, with its rupture rule")) +
           "); no mapping is stated" +
           (maps_jkr_and_drag ? std::string(" (LAMMPS maps adhesion = \"jkr\" only)")
                              : std::string());
  if (m.contact.adhesion == "none" &&
      (m.particle_particle.surface_energy_j_m2 > 0.0 || m.particle_wall.surface_energy_j_m2 > 0.0))
    return engine + " cannot reproduce a surface energy without demcal's adhesion part";
  if (m.air_drag && !maps_jkr_and_drag)
    return engine + " cannot reproduce demcal's air drag (dem/air_drag.hpp); run without it";
  if (!m.sizes) return engine + ": the material has no size distribution";
  // The decks give every wall one material (atom type 2, one wall/gran law).
  if (!m.particle_wall_by_group.empty())
    return engine + " deck cannot give the wall group \"" +
           m.particle_wall_by_group.begin()->first +
           "\" its own interaction ([interaction.particle_wall." +
           m.particle_wall_by_group.begin()->first +
           "]): demcal's decks give every wall the one particle_wall law";
  return "";
}

Resolved resolve(const dem::GranularMaterial& m, const dem::ModelReduction& r) {
  Resolved out;
  out.particle = m.particle;
  if (r.shear_modulus_pa > 0.0) {
    out.particle.shear_modulus_pa = r.shear_modulus_pa;
    out.particle.youngs_modulus_pa = 0.0;
  }
  out.wall = m.wall;
  out.pp = dem::resolve_pair(out.particle, out.particle, m.particle_particle, m.restitution_model);
  out.pw = dem::resolve_pair(out.particle, out.wall, m.particle_wall, m.restitution_model);
  const auto sizes = dem::scaled_sizes(m.sizes, r.coarse_graining_factor);
  out.diameter_m = dem::mean_diameter_m(*sizes);
  out.mass_kg = m.particle.density_kg_m3 * std::numbers::pi / 6.0 * std::pow(out.diameter_m, 3);
  return out;
}

}  // namespace

std::string engine_name(Engine engine) {
  switch (engine) {
    case Engine::kDemcal:
      return "demcal";
    case Engine::kLammps:
      return "lammps";
    case Engine::kLiggghts:
      return "liggghts";
  }
  return "unknown";
}

Engine engine_from_name(const std::string& name) {
  if (name == "demcal") return Engine::kDemcal;
  if (name == "lammps") return Engine::kLammps;
  if (name == "liggghts") return Engine::kLiggghts;
  throw std::invalid_argument("unknown engine \"" + name +
                              "\"; expected one of \"demcal\", \"lammps\", \"liggghts\"");
}

template <class T>
const T& MappingResult<T>::value() const& {
  if (!mapping) throw std::runtime_error(refusal);
  return *mapping;
}
template <class T>
T MappingResult<T>::value() && {
  if (!mapping) throw std::runtime_error(refusal);
  return std::move(*mapping);
}
template struct MappingResult<LammpsMapping>;
template struct MappingResult<LiggghtsMapping>;

double lammps_tsuji_alpha(double c) {
  if (!(c >= 0.0 && c <= 1.0)) throw std::domain_error("tsuji input must lie in [0, 1]");
  // LAMMPS's coefficients (pair_granular.cpp, coeff()), Horner form.
  return 1.2728 +
         c * (-4.2783 + c * (11.087 + c * (-22.348 + c * (27.467 + c * (-18.022 + c * 4.8218)))));
}

double lammps_tsuji_input_for_alpha(double alpha) {
  const double lo_alpha = lammps_tsuji_alpha(1.0), hi_alpha = lammps_tsuji_alpha(0.0);
  if (!(alpha >= lo_alpha && alpha <= hi_alpha)) {
    std::ostringstream s;
    s << "damping alpha " << alpha << " lies outside what LAMMPS's tsuji damping reaches ["
      << lo_alpha << ", " << hi_alpha << "]";
    throw std::domain_error(s.str());
  }
  // alpha(c) decreases monotonically on [0, 1] (checked in the tests).
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    (lammps_tsuji_alpha(mid) > alpha ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

std::string LammpsPairCoefficients::granular_words() const {
  // jkr takes a Young's modulus and a Poisson ratio and mixes them as
  // E / (2 (1 - nu^2)); with nu = 0, E = 2 E* = 1.5 k_n gives back E*.
  std::string s = jkr ? "jkr " + num(1.5 * normal_stiffness_pa) + " " + num(tsuji_input) + " 0 " +
                            num(surface_energy_j_m2) + " damping tsuji tangential mindlin "
                      : "hertz " + num(normal_stiffness_pa) + " " + num(tsuji_input) +
                            " damping tsuji limit_damping tangential mindlin ";
  s += num(tangential_stiffness_pa) + " " + num(tangential_damping_factor) + " " +
       num(sliding_friction);
  if (rolling)
    s += " rolling sds " + num(rolling_stiffness_n_m) + " " + num(rolling_damping_n_s_m) + " " +
         num(rolling_friction);
  return s;
}

namespace {

nlohmann::json parameters_json(const std::vector<MappedParameter>& ps) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& p : ps)
    a.push_back(
        {{"pair", p.pair}, {"engine_name", p.engine_name}, {"value", p.value}, {"rule", p.rule}});
  return a;
}

}  // namespace

std::string LammpsMapping::air_drag_commands() const {
  if (!air_drag) return "";
  const dem::AirProperties& a = *air_drag;
  const double f = coarse_graining_factor;
  // demcal's F = -drag_scale f^3 3 pi mu d_g v K(Re), d_g = 2 r / f:
  // the prefactor per unit radius is drag_scale f^2 6 pi mu.
  std::ostringstream s;
  s << "# air drag (dem/air_drag.hpp): Schiller-Naumann on the grain of diameter 2 r / f\n"
    << "compute         drag_radius all property/atom radius\n"
    << "variable        drag_speed atom sqrt(vx*vx+vy*vy+vz*vz)\n"
    << "variable        drag_re atom "
    << num(a.density_kg_m3 * 2.0 / (f * a.dynamic_viscosity_pa_s))
    << "*c_drag_radius*v_drag_speed\n"
    << "variable        drag_k atom (v_drag_re<1000)*(1+0.15*v_drag_re^0.687)+(v_drag_re>=1000)*"
    << num(0.44 / 24.0) << "*v_drag_re\n"
    << "variable        drag_c atom "
    << num(-a.drag_scale * f * f * 6.0 * std::numbers::pi * a.dynamic_viscosity_pa_s)
    << "*c_drag_radius*v_drag_k\n"
    << "variable        drag_fx atom v_drag_c*vx\n"
    << "variable        drag_fy atom v_drag_c*vy\n"
    << "variable        drag_fz atom v_drag_c*vz\n"
    << "fix             air_drag all addforce v_drag_fx v_drag_fy v_drag_fz\n";
  return s.str();
}

nlohmann::json LammpsMapping::to_json() const {
  nlohmann::json j = {
      {"engine", "lammps"},
      {"engine_version_mapped", "LAMMPS 29Sep2021 (Debian 12), pair_style granular"},
      {"representative_diameter_m", representative_diameter_m},
      {"density_kg_m3", density_kg_m3},
      {"pair_coeff", particle_particle.granular_words()},
      {"wall_coeff", particle_wall.granular_words()},
      {"parameters", parameters_json(parameters)},
      {"approximations", approximations}};
  // Absent without drag: the records of dry, still-air decks stay as they were.
  if (air_drag)
    j["air_drag"] = {{"density_kg_m3", air_drag->density_kg_m3},
                     {"dynamic_viscosity_pa_s", air_drag->dynamic_viscosity_pa_s},
                     {"drag_scale", air_drag->drag_scale},
                     {"coarse_graining_factor", coarse_graining_factor},
                     {"fix", "addforce with atom-style variables (air_drag_commands)"}};
  return j;
}

std::string LiggghtsMapping::model_words() const {
  std::string s = "model hertz tangential history";
  if (rolling_model != "off") s += " rolling_friction " + rolling_model;
  return s;
}

std::string LiggghtsMapping::pair_style_words() const {
  return model_words() + " " + settings_words();
}

std::string LiggghtsMapping::settings_words() const { return "limitForce on"; }

nlohmann::json LiggghtsMapping::to_json() const {
  return {{"engine", "liggghts"},
          {"engine_version_mapped", "LIGGGHTS-PUBLIC 3.8, pair_style gran"},
          {"pair_style", "gran " + pair_style_words()},
          {"density_kg_m3", density_kg_m3},
          {"parameters", parameters_json(parameters)},
          {"approximations", approximations}};
}

MappingResult<LammpsMapping> map_to_lammps(const dem::GranularMaterial& m,
                                           const dem::ModelReduction& reduction,
                                           const MappingOptions& options) {
  MappingResult<LammpsMapping> result;
  if (auto why = common_refusal("LAMMPS", m, true); !why.empty()) {
    result.refusal = why;
    return result;
  }
  if (m.contact.tangential != "mindlin" && m.contact.tangential != "none") {
    result.refusal =
        "LAMMPS: no mapping for demcal's tangential part \"" + m.contact.tangential + "\"";
    return result;
  }
  if (m.contact.rolling == "cdt" && m.contact.cdt_own_angular_velocity) {
    result.refusal =
        "LAMMPS cannot oppose each grain's own angular velocity (cdt_own_angular_velocity, "
        "EDEM's original type A); its rolling sds acts on the relative rolling";
    return result;
  }
  if (m.contact.rolling == "cdt" && !options.allow_rolling_substitute) {
    result.refusal =
        "LAMMPS has no constant directional torque (demcal rolling \"cdt\"); its rolling sds is "
        "the spring-dashpot-slider demcal calls \"sds\". Calibrate with rolling = \"sds\" (or "
        "\"epsd\"), or allow the substitute (same limiting torque: mu_r x 2 between equal spheres)";
    return result;
  }
  const Resolved r = resolve(m, reduction);
  LammpsMapping map;
  map.density_kg_m3 = r.particle.density_kg_m3;
  map.representative_diameter_m = r.diameter_m;
  const double radius = 0.5 * r.diameter_m;

  auto one = [&](const dem::PairCoefficients& c, const dem::InteractionParameters& p,
                 const std::string& pair, bool wall) -> std::optional<LammpsPairCoefficients> {
    LammpsPairCoefficients l;
    const double reff = wall ? radius : 0.5 * radius;
    l.normal_stiffness_pa = 4.0 / 3.0 * c.youngs_modulus_eff_pa;
    const double alpha = std::sqrt(5.0) * c.damping_beta;
    try {
      l.tsuji_input = lammps_tsuji_input_for_alpha(alpha);
    } catch (const std::domain_error& e) {
      result.refusal = "LAMMPS cannot damp the " + pair + " contact as demcal does (restitution " +
                       num(p.restitution) + "): " + e.what();
      return std::nullopt;
    }
    l.tangential_stiffness_pa = 8.0 * c.shear_modulus_eff_pa;
    l.tangential_damping_factor = 2.0 * std::sqrt(c.shear_modulus_eff_pa / c.youngs_modulus_eff_pa);
    l.sliding_friction = m.contact.tangential == "none" ? 0.0 : c.sliding_friction;
    map.parameters.push_back({pair, "hertz k_n", l.normal_stiffness_pa, "4/3 E*"});
    map.parameters.push_back(
        {pair, "tsuji input", l.tsuji_input,
         "Tsuji polynomial^-1(sqrt(5) beta), beta = demcal damping for e = " + num(p.restitution)});
    map.parameters.push_back({pair, "mindlin k_t", l.tangential_stiffness_pa, "8 G*"});
    map.parameters.push_back(
        {pair, "mindlin x_gamma_t", l.tangential_damping_factor, "2 sqrt(G*/E*)"});
    map.parameters.push_back({pair, "mindlin mu_s", l.sliding_friction, "demcal mu_s"});
    if (m.contact.adhesion == "jkr" && wall && p.surface_energy_j_m2 > 0.0 &&
        !options.allow_dry_walls) {
      result.refusal =
          "LAMMPS cannot give the walls JKR adhesion "
          "(interaction.particle_wall.surface_energy_j_m2 "
          "= " +
          num(p.surface_energy_j_m2) +
          "): fix wall/gran granular jkr in LAMMPS 29Sep2021 gives NaN forces when a grain leaves "
          "a wall it touched. Set it to 0, or allow dry walls (MappingOptions::allow_dry_walls)";
      return std::nullopt;
    }
    // Walls stay hertz (dry: refused above, or allowed); a pair with gamma = 0
    // too (LAMMPS's JKR at zero surface energy divides 0 by 0 at a = 0).
    if (m.contact.adhesion == "jkr" && !wall && p.surface_energy_j_m2 > 0.0) {
      l.jkr = true;
      // The part's own coarse-graining rule (gamma f^2), as install_materials applies it.
      l.surface_energy_j_m2 = dem::JkrAdhesion::kParameters[0].coarse_grained(
          p.surface_energy_j_m2, reduction.coarse_graining_factor);
      map.parameters.push_back({pair, "jkr E", 1.5 * l.normal_stiffness_pa,
                                "2 E* with Poisson ratio 0 (LAMMPS mixes E / (2 (1 - nu^2)))"});
      map.parameters.push_back(
          {pair, "jkr gamma", l.surface_energy_j_m2,
           "demcal surface_energy_j_m2 x f^2, f = " + num(reduction.coarse_graining_factor)});
    }
    if (m.contact.rolling != "none" && c.rolling_friction > 0.0) {
      l.rolling = true;
      const bool cdt = m.contact.rolling == "cdt";
      const bool sds = m.contact.rolling == "sds";
      // cdt's torque on a grain is mu_r F_n l, l ~ R_i; sds's is mu_r' F_n R_eff.
      l.rolling_friction = cdt ? c.rolling_friction * radius / reff : c.rolling_friction;
      const double f = cdt ? 2.25 : c.rolling_stiffness_factor;
      const double zeta = cdt ? 0.3 : c.rolling_damping_ratio;
      // demcal's sds is LAMMPS's constant spring at its own reference overlap;
      // epsd's overlap-dependent spring is matched at the option's.
      const double overlap_fraction =
          sds ? c.part_values[dem::constant_spring_rolling::kReferenceOverlapSlot]
              : options.reference_overlap_fraction;
      const double overlap = overlap_fraction * reff;
      const double sn = 2.0 * c.youngs_modulus_eff_pa * std::sqrt(reff * overlap);
      l.rolling_stiffness_n_m = f * sn * l.rolling_friction * l.rolling_friction;
      // Reduced inertia about the contact (Ai et al. 2011): 7/5 m R^2 per sphere.
      const double inertia = 1.4 * r.mass_kg * radius * radius;
      const double reduced = wall ? inertia : 0.5 * inertia;
      const double torque_stiffness = l.rolling_stiffness_n_m * reff * reff;
      l.rolling_damping_n_s_m = zeta * 2.0 * std::sqrt(torque_stiffness * reduced) / (reff * reff);
      map.parameters.push_back(
          {pair, "sds mu_r", l.rolling_friction,
           cdt ? "demcal cdt mu_r x l / R_eff (substitute: same limiting torque)"
               : "demcal " + m.contact.rolling + " mu_r (same lever R*)"});
      map.parameters.push_back({pair, "sds k_roll", l.rolling_stiffness_n_m,
                                std::string(sds ? "demcal sds's constant spring (exact): " : "") +
                                    "f S_n(delta_ref) mu_r^2, delta_ref = " +
                                    num(overlap_fraction) + " R*, f = " + num(f)});
      map.parameters.push_back({pair, "sds gamma_roll", l.rolling_damping_n_s_m,
                                "zeta 2 sqrt(k_roll R*^2 I_r) / R*^2, zeta = " + num(zeta)});
    }
    return l;
  };
  auto pp = one(r.pp, m.particle_particle, "particle-particle", false);
  if (!pp) return result;
  auto pw = one(r.pw, m.particle_wall, "particle-wall", true);
  if (!pw) return result;
  map.particle_particle = *pp;
  map.particle_wall = *pw;
  map.parameters.push_back({"particle", "density", map.density_kg_m3, "demcal density"});
  if (m.contact.adhesion == "jkr")
    map.approximations.push_back(
        "JKR: LAMMPS breaks a contact at the force-controlled pull-off point (overlap -1.44 "
        "a_c^2/R*, force -3 pi gamma R*), demcal at the displacement-controlled one (-3 a_c^2/R*, "
        "-5/9 of it); LAMMPS damps with the JKR contact radius and also while held apart, "
        "without limit_damping; its friction load leaves the damping out");
  if (m.contact.adhesion == "jkr" && m.particle_wall.surface_energy_j_m2 > 0.0)
    map.approximations.push_back(
        "walls dry (hertz): demcal's particle_wall surface energy " +
        num(m.particle_wall.surface_energy_j_m2) +
        " J/m^2 is left out (allow_dry_walls; LAMMPS 29Sep2021's wall JKR is unusable)");
  if (m.air_drag) {
    map.air_drag = m.air_drag;
    map.coarse_graining_factor = reduction.coarse_graining_factor;
    map.parameters.push_back({"particle", "air drag 3 pi mu_air",
                              3.0 * std::numbers::pi * m.air_drag->dynamic_viscosity_pa_s,
                              "demcal air.dynamic_viscosity_pa_s (Stokes prefactor)"});
    map.parameters.push_back({"particle", "air drag rho_air", m.air_drag->density_kg_m3,
                              "demcal air.density_kg_m3 (Reynolds number)"});
    map.parameters.push_back(
        {"particle", "air drag scale",
         m.air_drag->drag_scale * std::pow(reduction.coarse_graining_factor, 3),
         "demcal air.drag_scale x f^3 (grain diameter 2 r / f)"});
    map.approximations.push_back(
        "air drag evaluated by fix addforce with LAMMPS's half-step velocity (demcal: its "
        "integrator's velocity at force time): equal to O(dt)");
  }
  map.approximations.push_back(
      "tangential damping stays on while sliding in LAMMPS (demcal idles it at the Coulomb limit)");
  if (m.contact.rolling == "epsd")
    map.approximations.push_back(
        "rolling spring constant in LAMMPS, overlap-dependent in demcal: equal at delta = " +
        num(options.reference_overlap_fraction) + " R*; the limiting torque is exact");
  // LAMMPS's sds slider bounds spring + dashpot together and stores the spring
  // as -(F_crit f^ + gamma_roll v_roll) / k_roll (pair_granular.cpp and
  // fix_wall_gran.cpp, 29Sep2021), as for its tangential force. demcal's "sds"
  // is that slider; its epsd (Ai et al. model C, as LIGGGHTS) bounds the spring
  // alone, so its dashpot adds to the torque past the limit in impacts: the 3D
  // Sandglass's lower pile is about 2 deg steeper (studies/engine-crosscheck).
  if ((map.particle_particle.rolling || map.particle_wall.rolling) && m.contact.rolling == "epsd")
    map.approximations.push_back(
        "rolling slider: LAMMPS's sds bounds spring + dashpot together at mu_r R* F_n and keeps "
        "the dashpot on there (its spring history set to -(F_crit + gamma_roll v_roll) / "
        "k_roll); demcal epsd bounds the spring alone, so its dashpot can exceed the limit in "
        "impacts (LAMMPS's piles come out flatter; calibrate with rolling = \"sds\" for "
        "LAMMPS)");
  if (m.contact.rolling == "cdt")
    map.approximations.push_back(
        "demcal cdt (constant torque) run as LAMMPS sds with the same limiting torque (R_eff from "
        "the mean diameter " +
        num(r.diameter_m) + " m; unequal grains differ)");
  if (m.sizes->min_diameter_m() != m.sizes->max_diameter_m())
    map.approximations.push_back(
        "rolling stiffness, damping and cdt lever computed for the mean diameter; LAMMPS applies "
        "them to every size");
  result.mapping = std::move(map);
  return result;
}

MappingResult<LiggghtsMapping> map_to_liggghts(const dem::GranularMaterial& m,
                                               const dem::ModelReduction& reduction,
                                               const MappingOptions& /*options*/) {
  MappingResult<LiggghtsMapping> result;
  if (auto why = common_refusal("LIGGGHTS", m, false); !why.empty()) {
    result.refusal = why;
    return result;
  }
  if (m.contact.tangential != "mindlin") {
    result.refusal = "LIGGGHTS: no mapping for demcal's tangential part \"" + m.contact.tangential +
                     "\" (use mindlin with sliding_friction 0)";
    return result;
  }
  if (m.contact.rolling == "sds") {
    result.refusal =
        "LIGGGHTS 3.8 has no constant rolling spring (demcal rolling \"sds\"): its epsd and "
        "epsd2 springs follow the overlap. Calibrate with rolling = \"epsd\" for LIGGGHTS";
    return result;
  }
  if (m.contact.rolling == "cdt" && m.contact.cdt_own_angular_velocity) {
    result.refusal =
        "LIGGGHTS cdt opposes the relative angular velocity, not each grain's own "
        "(cdt_own_angular_velocity)";
    return result;
  }
  const Resolved r = resolve(m, reduction);
  LiggghtsMapping map;
  map.rolling_model = m.contact.rolling == "none" ? "off" : m.contact.rolling;
  map.particle_youngs_modulus_pa = r.particle.youngs_modulus();
  map.particle_poisson_ratio = r.particle.poisson_ratio;
  map.wall_youngs_modulus_pa = r.wall.youngs_modulus();
  map.wall_poisson_ratio = r.wall.poisson_ratio;
  map.density_kg_m3 = r.particle.density_kg_m3;
  map.parameters.push_back({"particle", "youngsModulus 1", map.particle_youngs_modulus_pa,
                            "demcal E (after the modulus reduction)"});
  map.parameters.push_back(
      {"particle", "poissonsRatio 1", map.particle_poisson_ratio, "demcal nu"});
  map.parameters.push_back(
      {"particle-wall", "youngsModulus 2", map.wall_youngs_modulus_pa, "demcal wall E"});
  map.parameters.push_back(
      {"particle-wall", "poissonsRatio 2", map.wall_poisson_ratio, "demcal wall nu"});

  auto one = [&](const dem::PairCoefficients& c, const dem::InteractionParameters& p,
                 const std::string& pair, bool wall) -> std::optional<LiggghtsPairCoefficients> {
    LiggghtsPairCoefficients l;
    const double beta = c.damping_beta;
    if (!(beta < 1.0)) {
      result.refusal = "LIGGGHTS cannot damp the " + pair +
                       " contact as demcal does (restitution " + num(p.restitution) + ", beta " +
                       num(beta) + " >= 1 has no coefficientRestitution)";
      return std::nullopt;
    }
    l.restitution = std::exp(-std::numbers::pi * beta / std::sqrt(1.0 - beta * beta));
    l.sliding_friction = c.sliding_friction;
    // cdt: LIGGGHTS's lever is R* (R/2 between equal spheres), demcal's l ~ R.
    l.rolling_friction =
        m.contact.rolling == "cdt" && !wall ? 2.0 * c.rolling_friction : c.rolling_friction;
    l.rolling_damping_ratio = c.rolling_damping_ratio;
    map.parameters.push_back(
        {pair, "coefficientRestitution", l.restitution,
         "exp(-pi beta / sqrt(1 - beta^2)), beta = demcal damping for e = " + num(p.restitution)});
    map.parameters.push_back({pair, "coefficientFriction", l.sliding_friction, "demcal mu_s"});
    if (map.rolling_model != "off") {
      map.parameters.push_back({pair, "coefficientRollingFriction", l.rolling_friction,
                                map.rolling_model == "cdt"
                                    ? (wall ? "demcal mu_r (lever R_i both)"
                                            : "2 demcal mu_r (lever R* vs demcal's R_i)")
                                    : "demcal mu_r (same lever R*)"});
      if (map.rolling_model == "epsd")
        map.parameters.push_back({pair, "coefficientRollingViscousDamping", l.rolling_damping_ratio,
                                  "demcal rolling_damping_ratio"});
    }
    return l;
  };
  auto pp = one(r.pp, m.particle_particle, "particle-particle", false);
  if (!pp) return result;
  auto pw = one(r.pw, m.particle_wall, "particle-wall", true);
  if (!pw) return result;
  map.particle_particle = *pp;
  map.particle_wall = *pw;
  if (map.rolling_model == "epsd" && (m.particle_particle.rolling_stiffness_factor != 1.5 ||
                                      m.particle_wall.rolling_stiffness_factor != 1.5))
    map.approximations.push_back(
        "LIGGGHTS epsd's rolling spring is 2.25 x secant Hertz stiffness = demcal's factor 1.5 on "
        "the tangent one; demcal's factor " +
        num(m.particle_particle.rolling_stiffness_factor) +
        " is stiffer; the limiting torque is exact");
  // LIGGGHTS 3.8's tangential_model_history.h (its last change is the 3.8.0
  // release): while sticking, spring + dashpot is not bounded by mu_s F_n.
  // Measured: two grains in a sliding oblique impact (1.0 m/s across) leave
  // spinning 709 rad/s on LIGGGHTS, 788 on demcal and 711 on demcal with the
  // cap removed (bench/logs/2026-12-07_lammps-pile-gap/impact/).
  map.approximations.push_back(
      "LIGGGHTS's tangential dashpot adds to the spring without the Coulomb bound while sticking "
      "(demcal bounds spring + dashpot at mu_s F_n): its dashpot damps a contact's elastic "
      "spring-back more, so grains leave a sliding impact with up to 10 % less spin");
  if (map.rolling_model == "cdt") {
    map.approximations.push_back(
        "LIGGGHTS cdt has no cap at the torque that stops the relative rolling in one step "
        "(demcal's has): grains at rest may chatter");
    if (m.sizes->min_diameter_m() != m.sizes->max_diameter_m())
      map.approximations.push_back(
          "cdt lever mapped for equal spheres (2 mu_r); unequal grains differ");
  }
  result.mapping = std::move(map);
  return result;
}

}  // namespace demcal::engines
