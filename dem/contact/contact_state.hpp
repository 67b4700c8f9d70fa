#pragma once
// What the engine hands to the parts of a contact law, and what they hand back.
// One contact is particle i against a partner j, which is another particle or a
// wall. The engine fills ContactKinematics; the parts fill ContactForce in role
// order (normal, adhesion, tangential, rolling), each reading what the earlier
// roles wrote. ContactHistory persists across steps while the contact lasts.
// A contact starts when the surfaces touch; it ends when they part, unless a
// part holds it beyond touching (adhesion: see ContactKernel in contact_law.hpp),
// so parts must accept overlap_m <= 0 for a contact that is held.

#include "dem/vec3.hpp"

namespace demcal::dem {

struct ContactKinematics {
  Vec3 normal;                  // unit, from the partner towards particle i
  double overlap_m = 0.0;       // > 0 when the surfaces interpenetrate; < 0 only while held
  double radius_eff_m = 0.0;    // R* = Ri Rj / (Ri + Rj); Ri against a wall
  double mass_eff_kg = 0.0;     // m* = mi mj / (mi + mj); mi against a wall
  double lever_i_m = 0.0;       // centre of i to the contact point
  double lever_j_m = 0.0;       // centre of j to the contact point (0 for a wall)
  double inv_mass_i_kg = 0.0;
  double inv_mass_j_kg = 0.0;        // 0 for a wall
  double inv_inertia_i_kg_m2 = 0.0;  // 1 / moment of inertia about the centre
  double inv_inertia_j_kg_m2 = 0.0;  // 0 for a wall
  double normal_speed_m_s = 0.0;       // (v_c . n): negative while approaching
  Vec3 tangential_velocity_m_s;        // relative sliding velocity at the contact point
  Vec3 omega_i_rad_s;
  Vec3 omega_j_rad_s;
  bool partner_is_wall = false;
  double dt_s = 0.0;
};

struct ContactHistory {
  Vec3 tangential_displacement_m;  // Mindlin spring elongation, kept in the tangent plane
  Vec3 rolling_torque_nm;          // elastic–plastic rolling spring torque on i
};

struct ContactForce {
  double normal_force_n = 0.0;       // along the normal, positive pushes i away from j
  double normal_stiffness_n_m = 0.0; // tangent stiffness dF/d(overlap), for parts that scale with it
  double contact_radius_m = 0.0;     // radius of the contact area (Hertz: sqrt(R* delta)); the
                                     // tangential spring scales with it
  // The load that bounds sliding (mu_s) and rolling (mu_r) friction; >= 0.
  // Equal to normal_force_n for a dry contact; an adhesion part raises it,
  // since a contact held by adhesion resists sliding under zero or tensile load.
  double friction_load_n = 0.0;
  Vec3 tangential_force_n;           // on i, at the contact point
  Vec3 torque_i_nm;                  // extra torque on i (rolling resistance)
  Vec3 torque_j_nm;                  // extra torque on j
  double elastic_energy_j = 0.0;     // stored elastic energy (energy checks)
};

// Keeps a history vector in the current tangent plane without changing its
// length: the contact rotates, the spring rotates with it. A zero vector, or
// one along the normal, becomes zero.
//
// Written without branches (selects only), like every part's apply(): the
// engine runs the parts over batches of contacts in a loop the compiler
// vectorises, and an `if` that leaves early keeps it from doing so
// (dem/simulation.cpp, "contact batches"). The select is taken before the
// division, so no lane divides by zero.
[[gnu::always_inline]] inline Vec3 rotate_into_tangent_plane(const Vec3& v, const Vec3& n) {
  const double len2 = norm2(v);
  const Vec3 projected = v - dot(v, n) * n;
  const double plen2 = norm2(projected);
  const bool keep = plen2 > 0.0;
  const double scale = keep ? std::sqrt(len2 / (keep ? plen2 : 1.0)) : 0.0;
  return projected * scale;
}

}  // namespace demcal::dem
