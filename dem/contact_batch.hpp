#pragma once
// Particle–particle contacts evaluated in batches, so that the compiler
// vectorises the contact law across contacts (issue 13).
//
// The pair loop (dem/pair_scan.hpp) tests distances one pair at a time and
// appends each contact to a batch without a branch (stage, then take); a full
// batch is evaluated in three passes:
//   0. gather(): each contact's partner and separation (recomputed as the
//      distance test computed them), the particle data and the history are
//      copied into the batch;
//   1. evaluate(): one loop over the batch's contacts with no branch, reading
//      and writing only the batch's own arrays (structure of arrays) and the
//      pair coefficients. GCC vectorises it when every part of the law is
//      written without branches (Hertz, Mindlin, the rolling parts: see
//      rotate_into_tangent_plane in contact/contact_state.hpp). A part with
//      branches (JKR, the liquid bridge) is still correct: the same loop
//      then runs one contact at a time.
//   2. the caller adds the forces to the particles in the order the contacts
//      were found, exactly as a one-pair-at-a-time loop would.
// Each contact's arithmetic is the same sequence of IEEE operations in either
// form (no fused multiply–add: the engine is built with -ffp-contract=off),
// so a batched run repeats the unbatched one bit for bit, on any x86-64.
//
// evaluate() is compiled for three instruction sets (dem/vector_clones.hpp),
// so one portable binary runs 8, 4 or 2 contacts per instruction.

#include "dem/contact/contact_state.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/vec3.hpp"
#include "dem/vector_clones.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace demcal::dem {

// The particle data a batch copies, as raw arrays (indexed by particle).
struct ParticleArrays {
  const Vec3* position_m;
  const Vec3* velocity_m_s;
  const Vec3* omega_rad_s;
  const double* radius_m;
  const double* mass_kg;
  const double* inv_mass_kg;
  const double* inv_inertia_kg_m2;
  const int* material;
};

// The neighbour list's arrays a batch reads, indexed by pair
// (dem/neighbor_list.hpp).
struct ListedPairs {
  const std::uint32_t* partner;
  const std::uint8_t* shift_code;  // the partner's periodic image: an index in shift_table
  const Vec3* shift_table;
  const ContactHistory* history;
};

// Aligned to a cache line: each thread has its own batch, and batches side by
// side in a vector must not share a line (a shared line bounced between the
// cores at every pair: false sharing).
struct alignas(64) ContactBatch {
  static constexpr int kCapacity = 64;

  int size = 0;
  // In: the pair. The pair loop writes every listed pair, touching or not,
  // so it writes as little as it can; gather() looks up the rest.
  std::int32_t i[kCapacity];      // read back when the forces are added
  std::uint32_t pair[kCapacity];  // index in the neighbour list
  // In: set by gather(). The separation is computed again, by the same
  // operations as the distance test, so it is the same to the last bit.
  std::int32_t j[kCapacity];
  double dx[kCapacity], dy[kCapacity], dz[kCapacity];  // x_i - (x_j + image shift)
  // In: what the law needs of i and j, copied here by gather() (evaluate()
  // then reads only contiguous arrays; GCC 12 would not vectorise it with
  // gathers from the particle arrays).
  double r_i[kCapacity], r_j[kCapacity];
  double m_i[kCapacity], m_j[kCapacity];
  double im_i[kCapacity], im_j[kCapacity];                   // inverse masses
  double ii_i[kCapacity], ii_j[kCapacity];                   // inverse moments of inertia
  double dv_x[kCapacity], dv_y[kCapacity], dv_z[kCapacity];  // v_i - v_j
  double wi_x[kCapacity], wi_y[kCapacity], wi_z[kCapacity];
  double wj_x[kCapacity], wj_y[kCapacity], wj_z[kCapacity];
  std::int32_t coefficient[kCapacity];  // index in the materials x materials table
  // In and out: the contact's history (tangential spring, rolling torque).
  double xi_x[kCapacity], xi_y[kCapacity], xi_z[kCapacity];
  double mr_x[kCapacity], mr_y[kCapacity], mr_z[kCapacity];
  // Out: force on i (j gets its negative), torques on i and j, stored energy.
  double f_x[kCapacity], f_y[kCapacity], f_z[kCapacity];
  double ti_x[kCapacity], ti_y[kCapacity], ti_z[kCapacity];
  double tj_x[kCapacity], tj_y[kCapacity], tj_z[kCapacity];
  double energy_j[kCapacity];

  // Whether the pair of each slot touched at the last step: a pair that did
  // not starts from a spring at rest, whatever its list entry still holds
  // (the pair loop does not clear a parted pair's history).
  std::uint8_t was_touching[kCapacity];

  bool full() const { return size == kCapacity; }

  // Writes a pair into slot l (the next free one) without taking it: the pair
  // loop writes every pair it tests and takes only those in contact (its
  // count of taken slots += touching), so the contact test is not a branch
  // the processor must guess. The loop keeps that count in a register and
  // sets `size` before a flush.
  void stage(int l, std::uint32_t pi, std::uint32_t p, bool touched_before) {
    i[l] = static_cast<std::int32_t>(pi);
    pair[l] = p;
    was_touching[l] = touched_before ? 1 : 0;
  }

  // Copies, for every taken contact, its partner and separation, what the
  // law needs of i and j, and the contact's history. Run before evaluate():
  // a loop over contacts only, so its loads are not behind the contact test.
  void gather(const ParticleArrays& pa, const ListedPairs& list, int materials) {
    for (int l = 0; l < size; ++l) {
      const std::uint32_t p = pair[l];
      const auto pi = static_cast<std::size_t>(i[l]);
      const auto pj = static_cast<std::size_t>(list.partner[p]);
      j[l] = static_cast<std::int32_t>(pj);
      const Vec3 d = pa.position_m[pi] - (pa.position_m[pj] + list.shift_table[list.shift_code[p]]);
      dx[l] = d.x;
      dy[l] = d.y;
      dz[l] = d.z;
      r_i[l] = pa.radius_m[pi];
      r_j[l] = pa.radius_m[pj];
      m_i[l] = pa.mass_kg[pi];
      m_j[l] = pa.mass_kg[pj];
      im_i[l] = pa.inv_mass_kg[pi];
      im_j[l] = pa.inv_mass_kg[pj];
      ii_i[l] = pa.inv_inertia_kg_m2[pi];
      ii_j[l] = pa.inv_inertia_kg_m2[pj];
      const Vec3 dv = pa.velocity_m_s[pi] - pa.velocity_m_s[pj];
      dv_x[l] = dv.x;
      dv_y[l] = dv.y;
      dv_z[l] = dv.z;
      const Vec3 wi = pa.omega_rad_s[pi], wj = pa.omega_rad_s[pj];
      wi_x[l] = wi.x;
      wi_y[l] = wi.y;
      wi_z[l] = wi.z;
      wj_x[l] = wj.x;
      wj_y[l] = wj.y;
      wj_z[l] = wj.z;
      coefficient[l] = pa.material[pi] * materials + pa.material[pj];
      const ContactHistory& h = list.history[p];
      const bool kept = was_touching[l] != 0;
      xi_x[l] = kept ? h.tangential_displacement_m.x : 0.0;
      xi_y[l] = kept ? h.tangential_displacement_m.y : 0.0;
      xi_z[l] = kept ? h.tangential_displacement_m.z : 0.0;
      mr_x[l] = kept ? h.rolling_torque_nm.x : 0.0;
      mr_y[l] = kept ? h.rolling_torque_nm.y : 0.0;
      mr_z[l] = kept ? h.rolling_torque_nm.z : 0.0;
    }
  }

  ContactHistory history(int l) const {
    ContactHistory h;
    h.tangential_displacement_m = {xi_x[l], xi_y[l], xi_z[l]};
    h.rolling_torque_nm = {mr_x[l], mr_y[l], mr_z[l]};
    return h;
  }
  Vec3 force_on_i(int l) const { return {f_x[l], f_y[l], f_z[l]}; }
  Vec3 torque_on_i(int l) const { return {ti_x[l], ti_y[l], ti_z[l]}; }
  Vec3 torque_on_j(int l) const { return {tj_x[l], tj_y[l], tj_z[l]}; }
};

// Pass 1: the contact law over every contact of the batch. coefficients is
// the dense materials x materials table.
template <class Kernel>
DEMCAL_VECTOR_CLONES void evaluate(const Kernel& kernel, ContactBatch& b,
                                   const PairCoefficients* __restrict coefficients, double dt_s) {
  const int count = b.size;
  for (int l = 0; l < count; ++l) {
    const double ri = b.r_i[l], rj = b.r_j[l];
    const double rsum = ri + rj;
    const Vec3 d{b.dx[l], b.dy[l], b.dz[l]};
    const double dist = std::sqrt(norm2(d));  // as the distance test computed it
    const Vec3 wi{b.wi_x[l], b.wi_y[l], b.wi_z[l]};
    const Vec3 wj{b.wj_x[l], b.wj_y[l], b.wj_z[l]};
    ContactKinematics k;
    k.normal = d / dist;
    k.overlap_m = rsum - dist;
    k.radius_eff_m = ri * rj / rsum;
    k.mass_eff_kg = b.m_i[l] * b.m_j[l] / (b.m_i[l] + b.m_j[l]);
    k.lever_i_m = ri - 0.5 * k.overlap_m;
    k.lever_j_m = rj - 0.5 * k.overlap_m;
    k.inv_mass_i_kg = b.im_i[l];
    k.inv_mass_j_kg = b.im_j[l];
    k.inv_inertia_i_kg_m2 = b.ii_i[l];
    k.inv_inertia_j_kg_m2 = b.ii_j[l];
    k.omega_i_rad_s = wi;
    k.omega_j_rad_s = wj;
    const Vec3 vc = Vec3{b.dv_x[l], b.dv_y[l], b.dv_z[l]} -
                    cross(k.lever_i_m * wi + k.lever_j_m * wj, k.normal);
    k.normal_speed_m_s = dot(vc, k.normal);
    k.tangential_velocity_m_s = vc - k.normal_speed_m_s * k.normal;
    k.dt_s = dt_s;
    ContactHistory h;
    h.tangential_displacement_m = {b.xi_x[l], b.xi_y[l], b.xi_z[l]};
    h.rolling_torque_nm = {b.mr_x[l], b.mr_y[l], b.mr_z[l]};
    ContactForce cf;
    kernel(k, coefficients[b.coefficient[l]], h, cf);
    b.xi_x[l] = h.tangential_displacement_m.x;
    b.xi_y[l] = h.tangential_displacement_m.y;
    b.xi_z[l] = h.tangential_displacement_m.z;
    b.mr_x[l] = h.rolling_torque_nm.x;
    b.mr_y[l] = h.rolling_torque_nm.y;
    b.mr_z[l] = h.rolling_torque_nm.z;
    const Vec3 fi = cf.normal_force_n * k.normal + cf.tangential_force_n;
    const Vec3 nxft = cross(k.normal, cf.tangential_force_n);
    const Vec3 ti = cf.torque_i_nm - k.lever_i_m * nxft;
    const Vec3 tj = cf.torque_j_nm - k.lever_j_m * nxft;
    b.f_x[l] = fi.x;
    b.f_y[l] = fi.y;
    b.f_z[l] = fi.z;
    b.ti_x[l] = ti.x;
    b.ti_y[l] = ti.y;
    b.ti_z[l] = ti.z;
    b.tj_x[l] = tj.x;
    b.tj_y[l] = tj.y;
    b.tj_z[l] = tj.z;
    b.energy_j[l] = cf.elastic_energy_j;
  }
}

}  // namespace demcal::dem
