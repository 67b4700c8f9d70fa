#include "dem/verlet_kicks.hpp"

#include "dem/vector_clones.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace demcal::dem {

namespace {

// The body of kick_and_drift(), with or without the displacement test (there
// is no build to compare with before the first one). Inlined into each
// instruction-set version of its caller.
template <bool kCompare>
inline __attribute__((always_inline)) bool kick_and_drift_loop(
    const KickArrays& a, const Vec3* __restrict force_n, const Vec3* __restrict torque_nm,
    const Vec3* __restrict position_at_build_m, double max_move_m, std::size_t begin,
    std::size_t end, double dt_s) {
  Vec3* __restrict x = a.position_m;
  Vec3* __restrict v = a.velocity_m_s;
  Vec3* __restrict w = a.omega_rad_s;
  const double* __restrict im = a.inv_mass_kg;
  const double* __restrict ii = a.inv_inertia_kg_m2;
  const double h = 0.5 * dt_s;
  const double max_move2 = max_move_m * max_move_m;
  // A flag, not the largest displacement: a maximum over doubles is a
  // reduction GCC will not vectorise (NaN), an "or" of comparisons it will.
  // A NaN position moves no farther than any other here, as with std::max;
  // the stability check reports it at the end of the step.
  int moved_beyond = 0;
  for (std::size_t i = begin; i < end; ++i) {
    const double hm = h * im[i], hi = h * ii[i];
    const Vec3 f = force_n[i], t = torque_nm[i];
    const double dvx = hm * f.x, dvy = hm * f.y, dvz = hm * f.z;
    const double xx = x[i].x + dt_s * (v[i].x + dvx);
    const double xy = x[i].y + dt_s * (v[i].y + dvy);
    const double xz = x[i].z + dt_s * (v[i].z + dvz);
    x[i].x = xx;
    x[i].y = xy;
    x[i].z = xz;
    v[i].x += 2.0 * dvx;
    v[i].y += 2.0 * dvy;
    v[i].z += 2.0 * dvz;
    w[i].x += 2.0 * (hi * t.x);
    w[i].y += 2.0 * (hi * t.y);
    w[i].z += 2.0 * (hi * t.z);
    if constexpr (kCompare) {
      const double dx = xx - position_at_build_m[i].x;
      const double dy = xy - position_at_build_m[i].y;
      const double dz = xz - position_at_build_m[i].z;
      moved_beyond |= static_cast<int>(dx * dx + dy * dy + dz * dz > max_move2);
    }
  }
  return moved_beyond != 0;
}

}  // namespace

DEMCAL_VECTOR_CLONES bool kick_and_drift(const KickArrays& a, const Vec3* force_n,
                                         const Vec3* torque_nm, const Vec3* position_at_build_m,
                                         double max_move_m, std::size_t begin, std::size_t end,
                                         double dt_s) {
  if (position_at_build_m == nullptr)
    return kick_and_drift_loop<false>(a, force_n, torque_nm, nullptr, max_move_m, begin, end, dt_s);
  return kick_and_drift_loop<true>(a, force_n, torque_nm, position_at_build_m, max_move_m, begin,
                                   end, dt_s);
}

DEMCAL_VECTOR_CLONES std::size_t correct_and_check(
    const KickArrays& a, const Vec3* __restrict force_n, const Vec3* __restrict force_before_n,
    const Vec3* __restrict torque_nm, const Vec3* __restrict torque_before_nm, std::size_t begin,
    std::size_t end, double dt_s, const StabilityBounds& bounds, std::size_t none) {
  const Vec3* __restrict x = a.position_m;
  Vec3* __restrict v = a.velocity_m_s;
  Vec3* __restrict w = a.omega_rad_s;
  const double* __restrict im = a.inv_mass_kg;
  const double* __restrict ii = a.inv_inertia_kg_m2;
  const double h = 0.5 * dt_s;
  const Vec3 lo = bounds.lower_m, hi = bounds.upper_m;
  const double vmax2 = bounds.max_speed2_m2_s2;
  std::size_t first_bad = none;
  for (std::size_t i = begin; i < end; ++i) {
    const double hm = h * im[i], hii = h * ii[i];
    const double vx = v[i].x + hm * (force_n[i].x - force_before_n[i].x);
    const double vy = v[i].y + hm * (force_n[i].y - force_before_n[i].y);
    const double vz = v[i].z + hm * (force_n[i].z - force_before_n[i].z);
    v[i].x = vx;
    v[i].y = vy;
    v[i].z = vz;
    w[i].x += hii * (torque_nm[i].x - torque_before_nm[i].x);
    w[i].y += hii * (torque_nm[i].y - torque_before_nm[i].y);
    w[i].z += hii * (torque_nm[i].z - torque_before_nm[i].z);
    // Each comparison is false for NaN; the bounds are finite, so a position
    // inside them is finite, and a speed within vmax is finite unless vmax
    // itself is infinite (then the component tests catch it).
    // The tests are combined as integers: "&" on bools is what the loop
    // needs (no branch), but clang warns about it.
    const double px = x[i].x, py = x[i].y, pz = x[i].z;
    const int inside = int{lo.x <= px} & int{px <= hi.x} & int{lo.y <= py} & int{py <= hi.y} &
                       int{lo.z <= pz} & int{pz <= hi.z};
    const double ax = std::abs(vx), ay = std::abs(vy), az = std::abs(vz);
    const int finite_v = int{ax <= DBL_MAX} & int{ay <= DBL_MAX} & int{az <= DBL_MAX};
    const int ok = inside & finite_v & int{vx * vx + vy * vy + vz * vz <= vmax2};
    first_bad = std::min(first_bad, ok ? none : i);
  }
  return first_bad;
}

}  // namespace demcal::dem
