#pragma once
// Tangential part: Mindlin's no-slip spring S_t = 8 G* a on the accumulated
// tangential displacement, a the contact radius the normal and adhesion parts
// report (Hertz: a = sqrt(R* delta); JKR: its wider adhesive contact), damped
// like the normal direction, and bounded by Coulomb's law |F_t| <= mu_s F_n,
// F_n the friction load the earlier parts set (a dry contact's normal force).
// While sliding, the spring is shortened to sit on the Coulomb limit and the
// damper is idle (as in LIGGGHTS), so the friction force equals mu_s F_n exactly.

#include "dem/contact/contact_state.hpp"
#include "dem/contact/hertz_normal.hpp"
#include "dem/contact/pair_coefficients.hpp"

#include <cmath>

namespace demcal::dem {

struct MindlinTangential {
  static constexpr const char* kName = "mindlin";

  [[gnu::always_inline]] void apply(const ContactKinematics& k, const PairCoefficients& c,
                                    ContactHistory& h, ContactForce& f) const {
    Vec3 xi = rotate_into_tangent_plane(h.tangential_displacement_m, k.normal);
    xi += k.tangential_velocity_m_s * k.dt_s;
    const double stiffness = 8.0 * c.shear_modulus_eff_pa * f.contact_radius_m;
    const Vec3 spring = -stiffness * xi;
    const double limit = c.sliding_friction * f.friction_load_n;
    const double spring2 = norm2(spring);
    // Both branches are computed and one is selected (no `if`: see
    // rotate_into_tangent_plane); a selected value equals the branch's own.
    const double limit2 = limit * limit;
    const bool slides = spring2 > limit2;
    // Sliding: the spring shortened onto the Coulomb limit.
    const double ratio = spring2 > 0.0 ? limit / std::sqrt(spring2 > 0.0 ? spring2 : 1.0) : 0.0;
    // Sticking: spring and damper; the damper must not push the force past
    // the Coulomb limit either.
    const double damping =
        HertzNormal::kDampingScale * c.damping_beta * std::sqrt(stiffness * k.mass_eff_kg);
    const Vec3 ft = spring - damping * k.tangential_velocity_m_s;
    const double ft2 = norm2(ft);
    const double cap = ft2 > limit2 ? limit / std::sqrt(ft2 > limit2 ? ft2 : 1.0) : 1.0;
    const double kept = slides ? ratio : 1.0;
    xi *= kept;
    f.tangential_force_n = slides ? spring * ratio : ft * cap;
    f.elastic_energy_j += slides ? 0.0 : 0.5 * stiffness * norm2(xi);
    h.tangential_displacement_m = xi;
  }
};

// Frictionless contacts (for checks and idealised granular gases).
struct NoTangential {
  static constexpr const char* kName = "none";
  void apply(const ContactKinematics&, const PairCoefficients&, ContactHistory&,
             ContactForce&) const {}
};

}  // namespace demcal::dem
