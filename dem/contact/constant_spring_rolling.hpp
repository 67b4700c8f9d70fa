#pragma once
// Rolling part "sds": LAMMPS's `pair_style granular ... rolling sds`, the
// spring-dashpot-slider with a spring that does not follow the overlap.
// LAMMPS takes a constant k_roll (N/m) on the rolling displacement R* theta, a
// torque stiffness k_roll R*^2; this part sets that constant from the same
// numbers as epsd, frozen at a reference overlap delta_ref = x R*:
//   k_r = factor * S_n(delta_ref) * (mu_r R*)^2,  S_n(delta_ref) = 2 E* R* sqrt(x),
// so the two springs agree at delta_ref (x = 0.005 by default, the overlap
// demcal's LAMMPS mapping has always matched epsd at). The lever R*, the limit
// mu_r R* F_n and the dashpot's coefficient are epsd's.
//
// The slider is LAMMPS's, not epsd's (pair_granular.cpp and fix_wall_gran.cpp,
// 29Sep2021): the limit bounds spring and dashpot *together*,
// |M_spring + M_dashpot| <= mu_r R* F_n, and where the sum would exceed it the
// torque is the capped sum and the spring is stored as the capped sum minus
// the dashpot (LAMMPS: xi = -(F_crit f^ + gamma_roll v_roll) / k_roll), so the
// dashpot stays on at the limit. epsd (Ai et al. 2011, model C, as LIGGGHTS)
// bounds the spring alone and lets the dashpot add to it below the limit: in
// an impact, when a grain is spun up in a few steps, its torque exceeds
// mu_r R* F_n. Measured (studies/engine-crosscheck/README.md, 2026-12-07): one
// grain striking a floor obliquely at 1.25 m/s keeps 17-30 % less of its
// tangential speed with epsd's slider than with LAMMPS's, and the 3D
// Sandglass's lower pile is about 2 deg steeper; with this slider demcal's and
// LAMMPS's runs agree. A calibration meant for LAMMPS is made with this part.
//
// Where it differs from LAMMPS still: the spring does not see adhesion (a JKR
// contact's stiffer contact), and LAMMPS applies one k_roll and gamma_roll to
// every grain size (stated in the LAMMPS mapping), where this part computes
// them per pair.
#include "dem/contact/contact_state.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/contact/part_parameter.hpp"
#include "dem/contact/rolling_resistance.hpp"

#include <array>
#include <cmath>

namespace demcal::dem {

namespace constant_spring_rolling {
inline constexpr int kReferenceOverlapSlot = 3;
}  // namespace constant_spring_rolling

struct ConstantSpringDashpot {
  static constexpr const char* kName = "sds";
  static constexpr std::array<PartParameter, 1> kParameters = {{
      {.key = "rolling_reference_overlap_fraction",
       .unit = "1",
       .summary = "overlap delta_ref / R* at which the constant rolling spring equals epsd's "
                  "(k_r = factor 2 E* R* sqrt(x) (mu_r R*)^2)",
       .what = "the reference overlap",
       .default_value = 0.005,
       .lo = 0.0,
       .hi = 0.1,
       .lo_open = true,
       .slot = constant_spring_rolling::kReferenceOverlapSlot},
  }};

  // The torque stiffness (N m/rad) of a pair: a constant of the pair and R*.
  static double stiffness_nm_rad(const PairCoefficients& c, double radius_eff_m) {
    const double arm = c.rolling_friction * radius_eff_m;
    const double reference_normal_stiffness =
        2.0 * c.youngs_modulus_eff_pa * radius_eff_m *
        std::sqrt(c.part_values[constant_spring_rolling::kReferenceOverlapSlot]);
    return c.rolling_stiffness_factor * reference_normal_stiffness * arm * arm;
  }

  // Without branches, as every part (rotate_into_tangent_plane in
  // contact_state.hpp). With mu_r = 0 the stiffness, the dashpot and the limit
  // are 0: the torque and the spring stay at zero.
  [[gnu::always_inline]] void apply(const ContactKinematics& k, const PairCoefficients& c,
                                    ContactHistory& h, ContactForce& f) const {
    const double stiffness = stiffness_nm_rad(c, k.radius_eff_m);
    const Vec3 w = relative_rolling_velocity(k);
    const Vec3 spring =
        rotate_into_tangent_plane(h.rolling_torque_nm, k.normal) - stiffness * k.dt_s * w;
    const Vec3 dashpot = -rolling_dashpot_n_m_s(k, c, stiffness) * w;
    const Vec3 sum = spring + dashpot;
    const double limit = c.rolling_friction * k.radius_eff_m * f.friction_load_n;
    const double sum2 = norm2(sum);
    const bool slides = sum2 > limit * limit;
    const Vec3 torque = sum * (slides ? limit / std::sqrt(slides ? sum2 : 1.0) : 1.0);
    const bool stores = stiffness > 0.0;
    f.elastic_energy_j +=
        slides ? 0.0 : (stores ? 0.5 * norm2(spring) / (stores ? stiffness : 1.0) : 0.0);
    h.rolling_torque_nm = slides ? torque - dashpot : spring;
    f.torque_i_nm += torque;
    f.torque_j_nm -= torque;
  }
};

}  // namespace demcal::dem
