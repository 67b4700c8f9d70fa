#pragma once
// Adhesion part "jkr": Johnson–Kendall–Roberts adhesion in the form EDEM
// documents, gamma being the surface energy of each surface (the work of
// adhesion is 2 gamma), E* and R* the pair's effective modulus and radius:
//   contact radius a from the overlap:  delta = a^2 / R* - 2 sqrt(pi gamma a / E*)
//   normal force:                       F_JKR = 4 E* a^3 / (3 R*) - 4 sqrt(pi gamma E* a^3)
//   pull-off force:                     F_po  = 3 pi gamma R*  (the largest tension)
//
// How it combines with the normal part. The Hertz part has already set its
// damped elastic force; this part adds F_JKR(delta) - F_Hertz(delta), F_Hertz
// being the undamped Hertz force at the same overlap (0 at negative overlap).
// At rest the force is F_JKR exactly; the damping is the Hertz part's, unchanged
// (active while delta > 0, as in EDEM's Hertz–Mindlin with JKR); gamma = 0 leaves
// the dry law untouched, bit for bit.
//
// Range (hysteresis). A contact forms only when the surfaces touch (the force
// then jumps to -8/9 F_po) and is held at negative overlap until the separation
// passes the JKR critical distance
//   delta_c = -3 a_c^2 / R*,  a_c^3 = pi gamma R*^2 / (4 E*),
// that is -(3/4) (4 pi^2 gamma^2 R* / E*^2)^(1/3), where the contact becomes
// unstable under imposed displacement (d delta / d a = 0; Johnson, Contact
// Mechanics, 5.5); there it breaks, and a new contact forms only when the
// surfaces touch again. EDEM's critical gap lies 0.4 % short of this one.
// holds() and max_separation_m() declare this range to the engine's contact
// loop (ContactKernel in contact_law.hpp), which refuses a Verlet skin that
// does not cover max_separation_m.
//
// What it hands the later parts:
//  - contact radius: the JKR a, so the Mindlin spring is 8 G* a on the real,
//    adhesive contact (Thornton & Yin 1991) and stays stiff while held;
//  - normal stiffness 2 E* a (the epsd rolling spring scales with it);
//  - friction load F_n + 2 F_po (>= 0): the sliding criterion Thornton (1991)
//    derived for adhesive elastic spheres, which LAMMPS's pair granular JKR uses
//    too. A contact held at zero or tensile load still resists sliding and
//    rolling (a negative load would flip the Coulomb and rolling limits), the
//    bound is continuous through delta = 0, and gamma -> 0 gives back F_n;
//  - elastic energy: the integral of F_JKR over the overlap from delta_c, so
//    the energy counted is continuous at breakage and drops at each formation
//    by the hysteresis loss; energy balances stay non-increasing.
//
// Coarse graining: a parcel f times a grain's size keeps the grain's Bond
// number F_po / (m g), which goes as gamma R / R^3, when gamma is scaled by f^2
// (install_materials in dem/apparatus/granular_material.cpp applies it).

#include "dem/contact/contact_state.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/contact/part_parameter.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace demcal::dem {

// The JKR relations for one pair, in the scaled variables that keep them
// polynomial: A = a / a_c and D = delta R* / a_c^2, so that D = A^2 - 4 sqrt(A)
// (the contact breaks at A = 1, D = -3) and F = (pi gamma R* / 3) (A^3 - 6 A^1.5).
struct JkrContact {
  double contact_radius_m = 0.0;  // a
  double force_n = 0.0;           // F_JKR, positive repulsive
  double energy_j = 0.0;          // integral of F_JKR over the overlap from delta_c
  double hertz_force_n = 0.0;     // the undamped Hertz force at this overlap
  double hertz_energy_j = 0.0;    // and its elastic energy, 0.4 F delta
};

namespace jkr {

// sqrt(A) >= 1 on the stable branch for D >= -3: the largest root of the quartic
// s^4 - 4 s - D = 0, by Ferrari's method. Its resolvent cubic m^3 + D m - 2 = 0
// has one real root for D > -3; Cardano's form u + v would cancel for large D
// (u ~ -v), so there m is taken as 2 / (u^2 - uv + v^2), uv = -D/3.
inline double root_of_overlap(double d) {
  const double disc = std::sqrt(std::max(0.0, 1.0 + d * d * d / 27.0));
  const double u = std::cbrt(1.0 + disc);
  const double v = std::cbrt(1.0 - disc);
  const double m = d >= 0.0 ? 2.0 / (u * u + v * v + d / 3.0) : u + v;
  const double r = std::sqrt(2.0 * m);
  return 0.5 * (r + std::sqrt(std::max(0.0, 8.0 / r - r * r)));
}

// a_c^3 = pi gamma R*^2 / (4 E*): the contact radius where the contact breaks.
inline double critical_radius_cubed_m3(double youngs_modulus_eff_pa, double surface_energy_j_m2,
                                       double radius_eff_m) {
  return std::numbers::pi * surface_energy_j_m2 * radius_eff_m * radius_eff_m /
         (4.0 * youngs_modulus_eff_pa);
}

// The state of a contact at `overlap_m` (clamped to delta_c); gamma > 0.
inline JkrContact contact(double youngs_modulus_eff_pa, double surface_energy_j_m2,
                          double radius_eff_m, double overlap_m) {
  const double ac =
      std::cbrt(critical_radius_cubed_m3(youngs_modulus_eff_pa, surface_energy_j_m2, radius_eff_m));
  const double unit_m = ac * ac / radius_eff_m;  // overlap per unit of D
  const double d = std::max(overlap_m / unit_m, -3.0);
  const double s = root_of_overlap(d);
  const double a = s * s;  // A
  const double s3 = s * s * s;
  const double force_unit = std::numbers::pi * surface_energy_j_m2 * radius_eff_m / 3.0;
  const double energy_unit = force_unit * unit_m;
  const double dp = std::max(d, 0.0);
  const double dp15 = dp * std::sqrt(dp);
  JkrContact c;
  c.contact_radius_m = a * ac;
  c.force_n = force_unit * (s3 * s3 - 6.0 * s3);
  // The integral of (A^3 - 6 A^1.5) dD with dD = (2 A - 2 / sqrt(A)) dA, from A = 1.
  c.energy_j = energy_unit * (0.4 * a * a * a * a * a - 4.0 * a * a * s3 + 6.0 * a * a - 2.4);
  c.hertz_force_n = force_unit * dp15;
  c.hertz_energy_j = energy_unit * 0.4 * dp15 * dp;
  return c;
}

// -delta_c = 3 a_c^2 / R*: how far apart a touching contact is held.
inline double critical_separation_m(double youngs_modulus_eff_pa, double surface_energy_j_m2,
                                    double radius_eff_m) {
  const double ac =
      std::cbrt(critical_radius_cubed_m3(youngs_modulus_eff_pa, surface_energy_j_m2, radius_eff_m));
  return 3.0 * ac * ac / radius_eff_m;
}

}  // namespace jkr

struct JkrAdhesion {
  static constexpr const char* kName = "jkr";
  // gamma keeps its named field (older code and tests read it); coarse
  // graining: f^2 (see the top of this file).
  static constexpr std::array<PartParameter, 1> kParameters = {{
      {.key = "surface_energy_j_m2",
       .unit = "J/m^2",
       .summary = "JKR surface energy gamma of each surface (pull-off force 3 pi gamma R*)",
       .what = "the surface energy",
       .default_value = 0.0,
       .lo = 0.0,
       .required = true,
       .coarse_graining_exponent = 2.0,
       .legacy_field = &InteractionParameters::surface_energy_j_m2},
  }};

  // Whether a contact that touched is still held at this (negative) overlap:
  // -delta < 3 a_c^2 / R*, compared in cubes, (-delta)^3 < (27 pi^2 / 16)
  // (gamma / E*)^2 R*, so the loop needs no cube root to decide.
  bool holds(const PairCoefficients& c, double radius_eff_m, double overlap_m) const {
    const double gap = -overlap_m;
    const double ratio = c.surface_energy_j_m2 / c.youngs_modulus_eff_pa;
    return gap * gap * gap < kHoldFactor * ratio * ratio * radius_eff_m;
  }
  double max_separation_m(const PairCoefficients& c, double radius_eff_m) const {
    if (c.surface_energy_j_m2 == 0.0) return 0.0;
    return jkr::critical_separation_m(c.youngs_modulus_eff_pa, c.surface_energy_j_m2, radius_eff_m);
  }

  [[gnu::always_inline]] void apply(const ContactKinematics& k, const PairCoefficients& c,
                                    ContactHistory& /*h*/, ContactForce& f) const {
    if (c.surface_energy_j_m2 == 0.0) return;
    const JkrContact j =
        jkr::contact(c.youngs_modulus_eff_pa, c.surface_energy_j_m2, k.radius_eff_m, k.overlap_m);
    f.normal_force_n += j.force_n - j.hertz_force_n;
    f.contact_radius_m = j.contact_radius_m;
    f.normal_stiffness_n_m = 2.0 * c.youngs_modulus_eff_pa * j.contact_radius_m;
    const double pull_off = 3.0 * std::numbers::pi * c.surface_energy_j_m2 * k.radius_eff_m;
    f.friction_load_n = std::max(0.0, f.normal_force_n + 2.0 * pull_off);
    f.elastic_energy_j += j.energy_j - j.hertz_energy_j;
  }

  static constexpr double kHoldFactor = 27.0 * std::numbers::pi * std::numbers::pi / 16.0;
};

}  // namespace demcal::dem
