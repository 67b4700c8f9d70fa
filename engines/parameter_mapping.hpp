#pragma once
// The one place that states how demcal's contact law maps onto another DEM
// engine's: LAMMPS (pair_style granular, 29Sep2021) and LIGGGHTS 3.8 (pair_style
// gran). A calibrated (mu_s, mu_r) belongs to demcal's contact law; another
// engine reproduces the calibration only when its law is demcal's, term by term.
// Each mapping returns the engine's numbers with the rule that produced each one,
// or a refusal naming what the engine cannot do. Approximations that are not
// refusals (the law matches in what sets the observables, not in every term)
// are listed in the result and in its JSON, which goes into the run record.
//
// LAMMPS (pair granular; the same words for fix wall/gran granular):
//  * normal: "hertz k_n" with k_n = 4/3 E*, not "hertz/material E e nu": the
//    stiffness is stated per pair, so no mixing rule can differ (in this LAMMPS
//    version fix wall/gran mixes hertz/material as E / (2 (1 - nu)) instead of
//    E / (2 (1 - nu^2)); measured: a sphere resting on the wall sits at that
//    overlap).
//  * damping: "damping tsuji limit_damping". LAMMPS's force is
//    F = k_n a delta - alpha sqrt(m* k_n a) v_n with a = sqrt(R* delta); demcal's
//    is the same with alpha = sqrt(5) beta (hertz_normal.hpp), and both keep the
//    total repulsive (limit_damping). The number given to tsuji is not alpha nor
//    the restitution: LAMMPS turns it into alpha by Tsuji's polynomial
//    alpha(c) = 1.2728 - 4.2783 c + ... + 4.8218 c^6, so the input is
//    c = alpha^-1(sqrt(5) beta). Checked by the two-sphere collision
//    (coll_test.in): c = 0.4361 gives e_pair 0.605, e_wall 0.603 for e = 0.60
//    at dt = 5e-6 s (the 0.5 % excess is the time step's).
//  * tangential: "mindlin k_t x mu_s" with k_t = 8 G* (LAMMPS multiplies by a),
//    x = tangential damping / normal damping = 2 sqrt(G*/E*) (demcal damps the
//    tangential spring 8 G* a like the normal one). LAMMPS keeps damping while
//    sliding, demcal idles it: equal at the Coulomb limit, not in transients.
//  * rolling "sds k_roll gamma_roll mu_r": torque R_eff F_roll, |F_roll| <= mu_r F_n,
//    R_eff = R1 R2 / (R1 + R2) (a wall: R_i). demcal "epsd" has the lever R*
//    too, so mu_r carries over unchanged (same limiting torque). Its spring
//    k_r = f S_n (mu_r R*)^2 grows with the overlap; LAMMPS's is constant, so
//    k_roll = f S_n(delta_ref) mu_r^2 at a reference overlap delta_ref =
//    reference_overlap_fraction R* (torque stiffness k_roll R*^2 equal there),
//    and gamma_roll R*^2 = zeta 2 sqrt(k_r I_r) (I_r the reduced inertia about
//    the contact, 7/5 m R^2 per sphere). demcal "sds"
//    (dem/contact/constant_spring_rolling.hpp) is that constant spring itself,
//    frozen at its own rolling_reference_overlap_fraction per pair, with
//    LAMMPS's slider (below): k_roll carries over exactly and no rolling
//    approximation is stated. demcal "cdt" is
//    a constant torque mu_r F_n l_i on each grain (l_i ~ R_i): no LAMMPS
//    counterpart; refused unless
//    allow_rolling_substitute, then sds with the same limiting torque
//    (mu_r_LAMMPS = mu_r l / R_eff: 2 mu_r between equal spheres, mu_r at a wall).
//    The sliders differ: LAMMPS bounds spring + dashpot *together*,
//    |F_roll| <= mu_r F_n, and where the sum would exceed it stores the spring
//    as -(F_crit f^ + gamma_roll v_roll) / k_roll (as its tangential force
//    does), so its dashpot stays on at the limit. demcal's epsd (Ai et al. 2011
//    model C, and LIGGGHTS's epsd) bounds the spring alone and idles the
//    dashpot only once the spring is at the limit: below it, the dashpot adds
//    to the spring without bound, and in an impact (a grain spun up in a few
//    steps) the torque exceeds mu_r R* F_n. That is not a detail: a grain
//    striking a floor obliquely at 1.25 m/s keeps 17-30 % less of its
//    tangential speed under epsd's slider, and the 3D Sandglass's lower pile
//    is about 2 deg steeper (studies/engine-crosscheck/README.md, 2026-12-07);
//    with LAMMPS's slider (demcal "sds") the piles agree within 0.3 deg.
//
//  * adhesion "jkr" (demcal's EDEM-form JKR, dem/contact/jkr_adhesion.hpp):
//    "jkr E_in tsuji_input 0 gamma damping tsuji" with E_in = 2 E*, Poisson
//    ratio 0 (LAMMPS mixes E_in / (2 (1 - nu^2)) for pairs; with nu = 0 the wall
//    fix's own mixing gives the same E*, so both get demcal's E*), gamma the
//    surface energy scaled by f^2 for coarse graining as install_materials does.
//    Equal: the JKR force-overlap curve F = 4 E* a^3 / (3 R*) - 4 sqrt(pi gamma
//    E* a^3), the pull-off force 3 pi gamma R*, the Mindlin spring on the JKR
//    contact radius, the sliding and rolling limits on F_n + 2 F_po (Thornton).
//    Differ (stated in the mapping's approximations): LAMMPS breaks a contact at
//    the force-controlled pull-off point (a = (9 pi gamma R*^2 / (4 E*))^(1/3),
//    overlap -1.44 a_c^2/R*, force -F_po), demcal holds it to the
//    displacement-controlled one (overlap -3 a_c^2/R*, force -5/9 F_po): LAMMPS's
//    hysteresis loop is smaller; LAMMPS damps with sqrt(m* 4/3 E* a_JKR) and also
//    while held apart, demcal with the Hertz a and only at positive overlap;
//    LAMMPS's friction load leaves the normal damping out, demcal's has it; and
//    LAMMPS refuses limit_damping with JKR (the damped force may pull).
//    Walls: a particle_wall surface energy is refused. fix wall/gran granular jkr
//    in 29Sep2021 gives NaN forces as soon as a grain leaves a wall it touched
//    (measured: a 1 mm grain dropped 0.5 mm onto a jkr plane with gamma = 0.05
//    J/m^2 bounces, and the run dies with "Non-numeric atom coords"; held on the
//    wall from the start it rests at the JKR overlap). allow_dry_walls runs the
//    walls as dry hertz instead (stated in the approximations).
//  * air drag (dem/air_drag.hpp): "fix addforce" with atom-style variables that
//    are demcal's law term by term: F = -drag_scale f^3 3 pi mu d_g v
//    (1 + 0.15 Re^0.687) (0.44 Re / 24 above Re = 1000), d_g = 2 r / f,
//    Re = rho_air |v| d_g / mu. LAMMPS evaluates it with the half-step velocity
//    of velocity Verlet (demcal with its own integrator's): equal to O(dt).
//
// Both: wall groups with their own interaction ([interaction.particle_wall.<group>],
// GranularMaterial::particle_wall_by_group) are refused: the decks give every
// wall one material and one wall/gran law.
//
// LIGGGHTS 3.8 (pair_style gran model hertz tangential history rolling_friction ...):
//  * materials are per atom type (type 1 grain, type 2 wall) and mixed by Hertz
//    theory as demcal mixes them: youngsModulus, poissonsRatio carry over.
//  * restitution: LIGGGHTS's damping is demcal's form with
//    beta = ln e / sqrt(ln^2 e + pi^2) (the linear-spring formula), so its
//    coefficientRestitution = exp(-pi beta / sqrt(1 - beta^2)) of demcal's beta
//    (equal to e for restitution_model = "linear_spring_formula"). beta >= 1 is refused.
//    "limitForce on" keeps the normal force repulsive, as demcal does, for
//    pairs and (at the end of each fix wall/gran line) for walls.
//  * tangential history: demcal's (spring 8 G* a, same damping, rescaled at slip),
//    except that while sticking LIGGGHTS leaves spring + dashpot unbounded
//    (demcal bounds the sum at mu_s F_n); stated as an approximation.
//  * rolling cdt: LIGGGHTS's torque is mu_r F_n R* (a wall: the contact radius of
//    i), demcal's mu_r F_n l_i: coefficientRollingFriction = 2 mu_r between equal
//    spheres, mu_r at a wall. epsd: same lever R* and limit, mu_r unchanged; its
//    spring is 2.25 k_n (mu_r R*)^2 on the secant Hertz stiffness 4/3 E* a,
//    demcal's f S_n on the tangent one 2 E* a: equal when f = 1.5 (noted otherwise);
//    coefficientRollingViscousDamping = demcal's rolling_damping_ratio.
//    demcal "sds" (a constant rolling spring) is refused: LIGGGHTS's epsd and
//    epsd2 springs both follow the overlap.

#include "dem/apparatus/granular_material.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace demcal::engines {

enum class Engine { kDemcal, kLammps, kLiggghts };

std::string engine_name(Engine engine);
// "demcal" | "lammps" | "liggghts"; throws std::invalid_argument listing them.
Engine engine_from_name(const std::string& name);

struct MappingOptions {
  // Where LAMMPS's constant rolling stiffness is matched to demcal's
  // overlap-dependent one, as delta / R*. 0.5 % is a loaded contact of a bed
  // a few tens of grains deep at the softened moduli calibrations use.
  double reference_overlap_fraction = 0.005;
  // Map demcal's "cdt" onto LAMMPS's "rolling sds" (same limiting torque,
  // an elastic phase below it) instead of refusing.
  bool allow_rolling_substitute = false;
  // With adhesion "jkr": run the walls dry (hertz) instead of refusing a
  // particle_wall surface energy (LAMMPS 29Sep2021's wall JKR is unusable, see
  // the header); the substitution is listed in the approximations.
  bool allow_dry_walls = false;
};

// One engine parameter and where it came from.
struct MappedParameter {
  std::string pair;         // "particle-particle" | "particle-wall" | "particle"
  std::string engine_name;  // the engine's word
  double value = 0.0;
  std::string rule;  // how it follows from demcal's parameters
};

// The contact law of one pair of materials in LAMMPS's pair granular words.
struct LammpsPairCoefficients {
  double normal_stiffness_pa = 0.0;      // hertz k_n = 4/3 E*
  double tsuji_input = 0.0;              // the number after "hertz k_n"
  double tangential_stiffness_pa = 0.0;  // mindlin k_t = 8 G*
  double tangential_damping_factor = 0.0;
  double sliding_friction = 0.0;
  bool rolling = false;
  double rolling_stiffness_n_m = 0.0;
  double rolling_damping_n_s_m = 0.0;
  double rolling_friction = 0.0;
  // JKR adhesion: the normal model is "jkr" (surface energy as the engine takes
  // it, after coarse graining), without limit_damping (LAMMPS refuses it there).
  bool jkr = false;
  double surface_energy_j_m2 = 0.0;

  // "hertz ... damping tsuji limit_damping tangential mindlin ... [rolling sds ...]", or
  // "jkr 2E* ... 0 gamma damping tsuji tangential mindlin ..." with adhesion.
  std::string granular_words() const;
};

struct LammpsMapping {
  LammpsPairCoefficients particle_particle;
  LammpsPairCoefficients particle_wall;
  double density_kg_m3 = 0.0;
  double representative_diameter_m = 0.0;
  // Air drag, when demcal's material has it: the air and the coarse-graining
  // factor the drag's grain diameter is taken with (dem/air_drag.hpp).
  std::optional<dem::AirProperties> air_drag;
  double coarse_graining_factor = 1.0;
  std::vector<MappedParameter> parameters;
  std::vector<std::string> approximations;
  // The LAMMPS commands of the drag (variables and "fix air_drag all addforce"),
  // empty without air drag.
  std::string air_drag_commands() const;
  nlohmann::json to_json() const;
};

struct LiggghtsPairCoefficients {
  double restitution = 0.0;  // coefficientRestitution (LIGGGHTS's meaning, see above)
  double sliding_friction = 0.0;
  double rolling_friction = 0.0;
  double rolling_damping_ratio = 0.0;  // epsd only
};

struct LiggghtsMapping {
  std::string rolling_model;  // "cdt" | "epsd" | "off"
  double particle_youngs_modulus_pa = 0.0;
  double particle_poisson_ratio = 0.0;
  double wall_youngs_modulus_pa = 0.0;
  double wall_poisson_ratio = 0.0;
  double density_kg_m3 = 0.0;
  LiggghtsPairCoefficients particle_particle;
  LiggghtsPairCoefficients particle_wall;
  std::vector<MappedParameter> parameters;
  std::vector<std::string> approximations;

  // "model hertz tangential history [rolling_friction X]": the words pair_style
  // and fix wall/gran share.
  std::string model_words() const;
  // "limitForce on": the model settings of pair_style and of every fix
  // wall/gran line. A wall line must end with them: LIGGGHTS reads a wall's
  // settings only after its geometry ("primitive ..." or "mesh ..."); placed
  // before it, the next word is refused as unknown.
  std::string settings_words() const;
  // model_words() + " " + settings_words(): pair_style's words.
  std::string pair_style_words() const;
  nlohmann::json to_json() const;
};

// Either the mapping or why there is none.
template <class T>
struct MappingResult {
  std::optional<T> mapping;
  std::string refusal;  // "<engine> cannot ...: <what>" when mapping is empty
  bool ok() const { return mapping.has_value(); }
  // Throws std::runtime_error with the refusal. A temporary result hands its
  // mapping over (no reference into a dying object).
  const T& value() const&;
  T value() &&;
};

// The material with `reduction` applied as install_materials applies it (the
// shear modulus, coarse-grained sizes). The sizes must be set.
MappingResult<LammpsMapping> map_to_lammps(const dem::GranularMaterial& material,
                                           const dem::ModelReduction& reduction,
                                           const MappingOptions& options = {});
MappingResult<LiggghtsMapping> map_to_liggghts(const dem::GranularMaterial& material,
                                               const dem::ModelReduction& reduction,
                                               const MappingOptions& options = {});

// Tsuji's polynomial as LAMMPS evaluates it, and its inverse on [0, 1]
// (alpha(0) = 1.2728 down to alpha(1) ~ 3e-4); throws std::domain_error outside.
double lammps_tsuji_alpha(double input);
double lammps_tsuji_input_for_alpha(double alpha);

}  // namespace demcal::engines
