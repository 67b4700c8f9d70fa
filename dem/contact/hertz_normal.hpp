#pragma once
// Normal part: Hertz elastic force with the viscous damping of the Hertz–Mindlin
// (no slip) model as commercial DEM codes formulate it:
//   F_n = 4/3 E* sqrt(R*) delta^{3/2} - 2 sqrt(5/6) beta sqrt(S_n m*) v_n,
//   S_n = 2 E* sqrt(R* delta).
// The total is kept repulsive: a dry contact cannot pull. A contact held at
// negative overlap (by an adhesion part) gets nothing from this part.

#include "dem/contact/contact_state.hpp"
#include "dem/contact/pair_coefficients.hpp"

#include <algorithm>
#include <cmath>

namespace demcal::dem {

struct HertzNormal {
  static constexpr const char* kName = "hertz";

  [[gnu::always_inline]] void apply(const ContactKinematics& k, const PairCoefficients& c,
                                    ContactHistory& /*h*/, ContactForce& f) const {
    const double root = std::sqrt(k.radius_eff_m * std::max(k.overlap_m, 0.0));  // contact radius
    const double stiffness = 2.0 * c.youngs_modulus_eff_pa * root;  // S_n
    const double elastic = (2.0 / 3.0) * stiffness * k.overlap_m;
    const double damping = kDampingScale * c.damping_beta * std::sqrt(stiffness * k.mass_eff_kg);
    f.normal_force_n = std::max(0.0, elastic - damping * k.normal_speed_m_s);
    f.normal_stiffness_n_m = stiffness;
    f.contact_radius_m = root;
    f.friction_load_n = f.normal_force_n;
    f.elastic_energy_j += 0.4 * elastic * k.overlap_m;
  }

  static constexpr double kDampingScale = 1.8257418583505538;  // 2 sqrt(5/6)
};

}  // namespace demcal::dem
