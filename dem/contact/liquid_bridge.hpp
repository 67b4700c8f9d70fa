#pragma once
// Adhesion part "liquid_bridge": a pendular capillary bridge between wet grains
// (and between a grain and a wall), in the closed form of
//   Willett, Adams, Johnson & Seville (2000), "Capillary bridges between two
//   spherical bodies", Langmuir 16, 9396-9405, eq. for the total force at
//   small contact angle:
//     F(S) = 2 pi R gamma cos(theta) / (1 + 1.05 S~ + 2.5 S~^2),  S~ = S sqrt(R / V),
// S the gap between the surfaces, gamma the liquid's surface tension, theta its
// contact angle, V the bridge's liquid volume and R the Derjaguin radius
// 2 R* = 2 R1 R2 / (R1 + R2) (the grain radius for two equal grains, twice the
// grain radius against a plane: F(0) = 4 pi R gamma cos(theta) there, the
// sphere-plane limit). The bridge ruptures at the gap of
//   Lian, Thornton & Adams (1993), J. Colloid Interface Sci. 161, 138-147:
//     S_c = (1 + theta / 2) V^(1/3)        (theta in radians).
//
// The bridge forms when the surfaces touch (the engine starts contacts there)
// and holds until the gap passes S_c (hysteresis: a dry approach feels nothing,
// as a pendular bridge only forms from the liquid films in contact). While the
// grains overlap the force is F(0), its value at touching. It is attractive and
// added to the normal part's force; the normal part's damping, the friction
// load (the elastic load the solid contact carries) and the tangential and
// rolling parts are left as they are. Viscous forces in the liquid are not
// modelled.
//
// Energy: U(S) = -integral_S^S_c F(s) ds (closed form: arctangents, since
// 1.05^2 < 4 * 2.5), continued by -F(0) delta into overlap, so the energy counted
// is continuous at rupture and drops at each formation (the hysteresis loss).
//
// Parameters, per pair of materials (particle-particle, particle-wall), declared
// below: surface_tension_n_m (gamma; 0 = dry: the pair is left untouched, bit
// for bit), contact_angle_deg (theta, [0, 90)), liquid_bridge_volume_fraction
// (V over the volume of the sphere of radius R, (4/3) pi R^3: the grain's own
// volume between equal grains; Willett's fits cover V / R^3 <= 0.1, hence the
// upper bound 0.02). Coarse graining: a parcel f times a grain's size keeps the
// grain's Bond number F / (m g) ~ gamma R / R^3 with gamma f^2; the volume
// fraction and the angle are dimensionless and stay.

#include "dem/contact/contact_state.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/contact/part_parameter.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace demcal::dem {

namespace liquid_bridge {

inline constexpr int kSurfaceTensionSlot = 0;
inline constexpr int kContactAngleSlot = 1;
inline constexpr int kVolumeFractionSlot = 2;

// The bridge between surfaces of Derjaguin radius R = 2 R*.
struct Bridge {
  double radius_m;       // R
  double gamma_n_m;      // surface tension
  double cos_theta;      // cos(contact angle)
  double theta_rad;
  double volume_m3;      // V
  double rupture_gap_m;  // S_c

  static Bridge of(const PairCoefficients& c, double radius_eff_m) {
    Bridge b;
    b.radius_m = 2.0 * radius_eff_m;
    b.gamma_n_m = c.part_values[kSurfaceTensionSlot];
    b.theta_rad = c.part_values[kContactAngleSlot] * (std::numbers::pi / 180.0);
    b.cos_theta = std::cos(b.theta_rad);
    b.volume_m3 = c.part_values[kVolumeFractionSlot] * (4.0 / 3.0) * std::numbers::pi *
                  b.radius_m * b.radius_m * b.radius_m;
    b.rupture_gap_m = (1.0 + 0.5 * b.theta_rad) * std::cbrt(b.volume_m3);
    return b;
  }
  // F(0) = 2 pi R gamma cos(theta).
  double max_force_n() const {
    return 2.0 * std::numbers::pi * radius_m * gamma_n_m * cos_theta;
  }
  // The attractive force (>= 0) at the gap S (S <= 0: touching or overlapping).
  double force_n(double gap_m) const {
    if (gap_m >= rupture_gap_m) return 0.0;
    const double s = std::max(gap_m, 0.0) * std::sqrt(radius_m / volume_m3);
    return max_force_n() / (1.0 + 1.05 * s + 2.5 * s * s);
  }
  // U(S) <= 0, with -dU/dS the (attractive, so negative) normal force.
  double energy_j(double gap_m) const {
    if (gap_m >= rupture_gap_m) return 0.0;
    const double k = std::sqrt(radius_m / volume_m3);
    const double b = 1.05 * k, c = 2.5 * k * k;
    const double root = std::sqrt(4.0 * c - b * b);
    const auto primitive = [&](double s) { return 2.0 / root * std::atan((2.0 * c * s + b) / root); };
    const double s = std::max(gap_m, 0.0);
    const double bound = -max_force_n() * (primitive(rupture_gap_m) - primitive(s));
    return gap_m < 0.0 ? bound + max_force_n() * gap_m : bound;
  }
};

}  // namespace liquid_bridge

struct LiquidBridge {
  static constexpr const char* kName = "liquid_bridge";
  static constexpr std::array<PartParameter, 3> kParameters = {{
      {.key = "surface_tension_n_m",
       .unit = "N/m",
       .summary = "surface tension gamma of the liquid in the bridges (water: 0.072); 0 = dry pair",
       .what = "the surface tension",
       .default_value = 0.0,
       .lo = 0.0,
       .hi = 1.0,
       .required = true,
       .coarse_graining_exponent = 2.0,
       .slot = liquid_bridge::kSurfaceTensionSlot},
      {.key = "contact_angle_deg",
       .unit = "deg",
       .summary = "contact angle theta of the liquid on the solid (0 = fully wetting)",
       .what = "the contact angle",
       .default_value = 0.0,
       .lo = 0.0,
       .hi = 90.0,
       .hi_open = true,
       .slot = liquid_bridge::kContactAngleSlot},
      {.key = "liquid_bridge_volume_fraction",
       .unit = "1",
       .summary = "liquid volume of one bridge over (4/3) pi R^3, R = 2 R* (the grain's volume "
                  "between equal grains)",
       .what = "the bridge volume",
       .default_value = 1.0e-3,
       .lo = 0.0,
       .hi = 0.02,
       .lo_open = true,
       .slot = liquid_bridge::kVolumeFractionSlot},
  }};

  // Held while gap^3 < S_c^3 = (1 + theta/2)^3 V: no cube root in the loop.
  bool holds(const PairCoefficients& c, double radius_eff_m, double overlap_m) const {
    const double gamma = c.part_values[liquid_bridge::kSurfaceTensionSlot];
    if (gamma == 0.0) return false;
    const double gap = -overlap_m;
    const double theta = c.part_values[liquid_bridge::kContactAngleSlot] * (std::numbers::pi / 180.0);
    const double lengthen = 1.0 + 0.5 * theta;
    const double r = 2.0 * radius_eff_m;
    const double volume = c.part_values[liquid_bridge::kVolumeFractionSlot] * (4.0 / 3.0) *
                          std::numbers::pi * r * r * r;
    return gap * gap * gap < lengthen * lengthen * lengthen * volume;
  }
  double max_separation_m(const PairCoefficients& c, double radius_eff_m) const {
    if (c.part_values[liquid_bridge::kSurfaceTensionSlot] == 0.0) return 0.0;
    return liquid_bridge::Bridge::of(c, radius_eff_m).rupture_gap_m;
  }

  [[gnu::always_inline]] void apply(const ContactKinematics& k, const PairCoefficients& c,
                                    ContactHistory& /*h*/, ContactForce& f) const {
    if (c.part_values[liquid_bridge::kSurfaceTensionSlot] == 0.0) return;
    const liquid_bridge::Bridge b = liquid_bridge::Bridge::of(c, k.radius_eff_m);
    const double gap = -k.overlap_m;
    f.normal_force_n -= b.force_n(gap);
    f.elastic_energy_j += b.energy_j(gap);
  }
};

}  // namespace demcal::dem
