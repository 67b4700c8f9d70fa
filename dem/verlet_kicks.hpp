#pragma once
// The two particle loops of a velocity-Verlet step (dem/simulation.cpp), as
// free functions the compiler vectorises and compiles for several instruction
// sets (dem/vector_clones.hpp). Each loop is a plain pass over arrays, with no
// branch and no call: the stability check, once a chain of branches per
// particle, is a set of comparisons and a running minimum of the first
// particle that failed them (issue 13: the two loops were 11 % of a run).
//
// The arithmetic is the same sequence of IEEE operations as the scalar loop
// per particle, so the results do not depend on which version runs.

#include "dem/vec3.hpp"

#include <cstddef>

namespace demcal::dem {

// The state the kicks update, as raw arrays indexed by particle.
struct KickArrays {
  Vec3* position_m;
  Vec3* velocity_m_s;
  Vec3* omega_rad_s;
  const double* inv_mass_kg;
  const double* inv_inertia_kg_m2;
};

// The first half of a step for particles [begin, end): with the force and
// torque of the last step, v and w are predicted a full step ahead (v += dt
// f/m) and x drifts with the half-step velocity (x += dt (v + dt/2 f/m)).
// Returns whether some particle is now farther than max_move_m from where it
// was at the last neighbour build (false when position_at_build_m is null: no
// build to compare with).
bool kick_and_drift(const KickArrays& a, const Vec3* force_n, const Vec3* torque_nm,
                    const Vec3* position_at_build_m, double max_move_m, std::size_t begin,
                    std::size_t end, double dt_s);

// Where a particle may be and how fast it may go. Along a periodic axis the
// bounds are -/+ the largest double, which leaves only the finiteness test.
struct StabilityBounds {
  Vec3 lower_m;
  Vec3 upper_m;
  double max_speed2_m2_s2 = 0.0;  // the square of the largest speed allowed
};

// The second half for particles [begin, end): the prediction of
// kick_and_drift() is corrected by half a step of the change in force and
// torque (v += dt/2 (f - f_before)/m). Then each particle is checked: finite
// position and velocity, inside the bounds, no faster than allowed. Returns
// the first particle that fails, or `none` when every one passes.
std::size_t correct_and_check(const KickArrays& a, const Vec3* force_n, const Vec3* force_before_n,
                              const Vec3* torque_nm, const Vec3* torque_before_nm,
                              std::size_t begin, std::size_t end, double dt_s,
                              const StabilityBounds& bounds, std::size_t none);

}  // namespace demcal::dem
