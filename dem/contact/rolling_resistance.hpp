#pragma once
// Rolling parts. Rolling resistance stands in for the shape of real grains
// (Derakhshani et al. 2015 and most calibration work use it so). Which angular
// velocity the torque opposes, and which lever arm multiplies mu_r, differs
// between codes; each part states its choice. The load F_n is the contact's
// friction load (ContactForce::friction_load_n): the normal force of a dry
// contact, never negative, so an adhesive contact under tension still resists
// rolling instead of being pushed to roll by a negative limit.

#include "dem/contact/contact_state.hpp"
#include "dem/contact/pair_coefficients.hpp"

#include <algorithm>
#include <cmath>

namespace demcal::dem {

// The relative rolling angular velocity: omega_i - omega_j without its
// component along the normal (that is twisting, not rolling). It vanishes when
// two touching grains turn together as one rigid body, so a pile at rest feels
// no spurious torque, and it does not depend on the observer's frame.
inline Vec3 relative_rolling_velocity(const ContactKinematics& k) {
  const Vec3 w = k.omega_i_rad_s - k.omega_j_rad_s;
  return w - dot(w, k.normal) * k.normal;
}

// Constant directional torque (EDEM's "type A", LIGGGHTS's "cdt"): a torque of
// magnitude mu_r * F_n * l on each particle, l being the distance from its centre
// to the contact point (EDEM's lever arm), opposing the relative rolling angular
// velocity. The torque is capped at what stops the relative rolling within one
// step, so a grain at rest does not chatter between directions.
//
// Without branches (see rotate_into_tangent_plane in contact_state.hpp): a
// contact with no load, no rolling friction or no rolling gets a torque scaled
// by zero, which leaves the sums as they were.
struct ConstantDirectionalTorque {
  static constexpr const char* kName = "cdt";

  [[gnu::always_inline]] void apply(const ContactKinematics& k, const PairCoefficients& c,
                                    ContactHistory& /*h*/, ContactForce& f) const {
    const double moment = c.rolling_friction * f.friction_load_n;  // per unit lever arm
    const Vec3 w = relative_rolling_velocity(k);
    const double wn = norm(w);
    const bool on = moment != 0.0 && wn != 0.0;
    // Change of w in one step per unit of `scale` (torque per lever arm); the
    // cap keeps the step from reversing w.
    const double compliance =
        (k.lever_i_m * k.inv_inertia_i_kg_m2 + k.lever_j_m * k.inv_inertia_j_kg_m2) * k.dt_s;
    const double scale = on ? std::min(moment, wn / std::max(compliance, 1e-300)) : 0.0;
    const Vec3 dir = w / (on ? wn : 1.0);
    f.torque_i_nm -= dir * (scale * k.lever_i_m);
    f.torque_j_nm += dir * (scale * k.lever_j_m);
  }
};

// EDEM's original constant directional torque: each particle's torque opposes
// its own angular velocity (without its component along the normal), at the
// cost of torques on grains that roll together without relative motion. Kept
// to reproduce EDEM figures; chosen by contact.cdt_own_angular_velocity with
// rolling = "cdt", hence the same name. A part of its own, not a flag of the
// one above: a flag read in the contact loop is a branch there, and a branch
// keeps the loop from being vectorised.
struct ConstantDirectionalTorqueOwnOmega {
  static constexpr const char* kName = "cdt";

  [[gnu::always_inline]] void apply(const ContactKinematics& k, const PairCoefficients& c,
                                    ContactHistory& /*h*/, ContactForce& f) const {
    const double moment = c.rolling_friction * f.friction_load_n;  // per unit lever arm
    if (moment == 0.0) return;
    auto own = [&](const Vec3& omega, double lever, double inv_inertia, Vec3& torque) {
      const Vec3 w = omega - dot(omega, k.normal) * k.normal;
      const double wn = norm(w);
      if (wn == 0.0 || inv_inertia == 0.0) return;
      const double cap = wn / (inv_inertia * k.dt_s);
      torque -= w / wn * std::min(moment * lever, cap);
    };
    own(k.omega_i_rad_s, k.lever_i_m, k.inv_inertia_i_kg_m2, f.torque_i_nm);
    own(k.omega_j_rad_s, k.lever_j_m, k.inv_inertia_j_kg_m2, f.torque_j_nm);
  }
};

// The rolling dashpot's coefficient (N m s/rad): the stated fraction of the
// critical damping of the rolling spring on the reduced moment of inertia
// about the contact point (Ai et al. 2011, eq. 16); a wall (no rotational
// inertia) adds nothing.
[[gnu::always_inline]] inline double rolling_dashpot_n_m_s(const ContactKinematics& k,
                                                           const PairCoefficients& c,
                                                           double stiffness_nm_rad) {
  const double ii = 1.0 / k.inv_inertia_i_kg_m2 + k.lever_i_m * k.lever_i_m / k.inv_mass_i_kg;
  double inv_ir = 1.0 / ii;
  const bool j_turns = k.inv_inertia_j_kg_m2 > 0.0;
  const double inv_inertia_j = j_turns ? k.inv_inertia_j_kg_m2 : 1.0;
  const double inv_mass_j = j_turns ? k.inv_mass_j_kg : 1.0;
  const double inv_ir_j = 1.0 / (1.0 / inv_inertia_j + k.lever_j_m * k.lever_j_m / inv_mass_j);
  inv_ir += j_turns ? inv_ir_j : 0.0;
  return c.rolling_damping_ratio * 2.0 * std::sqrt(stiffness_nm_rad / inv_ir);
}

// The spring–dashpot–slider of "epsd" (Iwashita & Oda 1998; Ai, Chen, Rotter &
// Ooi 2011, model C, as LIGGGHTS's epsd): a rolling spring of the given
// stiffness (N m/rad) on the relative rolling rotation, a dashpot at a
// fraction of its critical damping, and a plastic limit on the *spring*,
// |M_spring| <= arm F_n, arm = mu_r R*, at which the dashpot is idle. Below
// that limit the dashpot adds to the spring unbounded, so in an impact (a fast
// spin-up) the torque may exceed arm F_n. LAMMPS's sds slider bounds spring
// and dashpot together instead ("sds", constant_spring_rolling.hpp).
//
// Without branches (see rotate_into_tangent_plane in contact_state.hpp): both
// the sliding and the sticking torque are computed and one is selected. With
// mu_r = 0 the arm and the stiffness are 0, the spring stays at zero and so
// does the torque: no special case is needed.
[[gnu::always_inline]] inline void apply_rolling_spring_dashpot_slider(
    const ContactKinematics& k, const PairCoefficients& c, double arm_m, double stiffness_nm_rad,
    ContactHistory& h, ContactForce& f) {
  const Vec3 w = relative_rolling_velocity(k);
  Vec3 spring =
      rotate_into_tangent_plane(h.rolling_torque_nm, k.normal) - stiffness_nm_rad * k.dt_s * w;
  const double limit = arm_m * f.friction_load_n;
  const double s2 = norm2(spring);
  const bool slides = s2 > limit * limit;
  const double damping = rolling_dashpot_n_m_s(k, c, stiffness_nm_rad);
  const Vec3 sticking = spring - damping * w;
  const bool stores = stiffness_nm_rad > 0.0;
  const double energy = stores ? 0.5 * norm2(spring) / (stores ? stiffness_nm_rad : 1.0) : 0.0;
  // Sliding: the spring shortened onto the plastic limit, the dashpot idle.
  spring *= slides ? limit / std::sqrt(slides ? s2 : 1.0) : 1.0;
  const Vec3 torque = slides ? spring : sticking;
  f.elastic_energy_j += slides ? 0.0 : energy;
  h.rolling_torque_nm = spring;
  f.torque_i_nm += torque;
  f.torque_j_nm -= torque;
}

// Elastic–plastic spring–dashpot rolling resistance (Ai et al. 2011, model C)
// with the spring of Iwashita & Oda: k_r = factor * k_n * (mu_r R*)^2, k_n the
// normal part's tangent stiffness at this overlap, so the spring stiffens as
// the contact is loaded (LIGGGHTS's "epsd" does the same). The lever arm is R*,
// as in Ai et al. and LAMMPS's "rolling sds": the same mu_r means the same
// limiting torque there. A spring that does not follow the overlap is "sds"
// (dem/contact/constant_spring_rolling.hpp).
struct ElasticPlasticSpringDashpot {
  static constexpr const char* kName = "epsd";

  [[gnu::always_inline]] void apply(const ContactKinematics& k, const PairCoefficients& c,
                                    ContactHistory& h, ContactForce& f) const {
    const double arm = c.rolling_friction * k.radius_eff_m;
    const double stiffness = c.rolling_stiffness_factor * f.normal_stiffness_n_m * arm * arm;
    apply_rolling_spring_dashpot_slider(k, c, arm, stiffness, h, f);
  }
};

struct NoRolling {
  static constexpr const char* kName = "none";
  void apply(const ContactKinematics&, const PairCoefficients&, ContactHistory&,
             ContactForce&) const {}
};

}  // namespace demcal::dem
