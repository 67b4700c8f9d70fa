#pragma once
// Particle–wall contacts evaluated in batches, as dem/contact_batch.hpp does
// for particle pairs: the wall loop finds the contacts of one wall (the
// nearest point on the wall is a virtual call per candidate), stages each
// with its contact point, and a full batch is evaluated in one loop the
// compiler vectorises. Before (issue 13), every wall contact ran the contact
// law one at a time: about a tenth of the quick Sandglass's time, for about a
// tenth of its contacts.
//
// Each contact's arithmetic is the same sequence of IEEE operations as the
// one-contact loop it replaces, and the caller adds the results in the order
// the contacts were found, so a run repeats bit for bit.

#include "dem/contact/contact_state.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/contact_batch.hpp"
#include "dem/vec3.hpp"
#include "dem/vector_clones.hpp"

#include <algorithm>
#include <cstdint>

namespace demcal::dem {

// Aligned to a cache line, like ContactBatch: one per thread, side by side.
struct alignas(64) WallContactBatch {
  static constexpr int kCapacity = 64;

  int size = 0;
  // In, written when a contact is staged.
  std::uint32_t candidate[kCapacity];                     // index in the wall's candidate list
  std::uint32_t i[kCapacity];                             // the particle
  double n_x[kCapacity], n_y[kCapacity], n_z[kCapacity];  // unit normal, wall towards i
  double distance_m[kCapacity];  // centre of i to the wall (< radius while touching)
  double p_x[kCapacity], p_y[kCapacity], p_z[kCapacity];  // the contact point on the wall
  // In: what the law needs of i, and i's velocity relative to the wall.
  double r_i[kCapacity], m_i[kCapacity], im_i[kCapacity], ii_i[kCapacity];
  double dv_x[kCapacity], dv_y[kCapacity], dv_z[kCapacity];  // v_i - the wall's velocity
  double w_x[kCapacity], w_y[kCapacity], w_z[kCapacity];
  std::int32_t coefficient[kCapacity];  // index in the materials x materials table
  // In and out: the contact's history.
  double xi_x[kCapacity], xi_y[kCapacity], xi_z[kCapacity];
  double mr_x[kCapacity], mr_y[kCapacity], mr_z[kCapacity];
  // Out: the force on i, the torque on i (the law's own and the tangential
  // force's), the law's own torque alone (the wall's load needs it), energy.
  double f_x[kCapacity], f_y[kCapacity], f_z[kCapacity];
  double t_x[kCapacity], t_y[kCapacity], t_z[kCapacity];
  double tl_x[kCapacity], tl_y[kCapacity], tl_z[kCapacity];
  double energy_j[kCapacity];

  bool full() const { return size == kCapacity; }

  void stage(std::uint32_t c, std::uint32_t particle, const Vec3& normal, double distance,
             const Vec3& point) {
    const int l = size++;
    candidate[l] = c;
    i[l] = particle;
    n_x[l] = normal.x;
    n_y[l] = normal.y;
    n_z[l] = normal.z;
    distance_m[l] = distance;
    p_x[l] = point.x;
    p_y[l] = point.y;
    p_z[l] = point.z;
  }

  // Copies, for every staged contact, what the law needs of its particle,
  // the particle's velocity relative to the wall, and the contact's history
  // (indexed by candidate). Run before evaluate_walls().
  void gather(const ParticleArrays& pa, const Vec3& wall_velocity, int materials, int wall_material,
              const ContactHistory* history) {
    for (int l = 0; l < size; ++l) {
      const std::uint32_t p = i[l];
      r_i[l] = pa.radius_m[p];
      m_i[l] = pa.mass_kg[p];
      im_i[l] = pa.inv_mass_kg[p];
      ii_i[l] = pa.inv_inertia_kg_m2[p];
      const Vec3 dv = pa.velocity_m_s[p] - wall_velocity;
      dv_x[l] = dv.x;
      dv_y[l] = dv.y;
      dv_z[l] = dv.z;
      const Vec3 w = pa.omega_rad_s[p];
      w_x[l] = w.x;
      w_y[l] = w.y;
      w_z[l] = w.z;
      coefficient[l] = pa.material[p] * materials + wall_material;
      set_history(l, history[candidate[l]]);
    }
  }

  ContactHistory history(int l) const {
    ContactHistory h;
    h.tangential_displacement_m = {xi_x[l], xi_y[l], xi_z[l]};
    h.rolling_torque_nm = {mr_x[l], mr_y[l], mr_z[l]};
    return h;
  }
  void set_history(int l, const ContactHistory& h) {
    xi_x[l] = h.tangential_displacement_m.x;
    xi_y[l] = h.tangential_displacement_m.y;
    xi_z[l] = h.tangential_displacement_m.z;
    mr_x[l] = h.rolling_torque_nm.x;
    mr_y[l] = h.rolling_torque_nm.y;
    mr_z[l] = h.rolling_torque_nm.z;
  }
  Vec3 point(int l) const { return {p_x[l], p_y[l], p_z[l]}; }
  Vec3 force_on_i(int l) const { return {f_x[l], f_y[l], f_z[l]}; }
  Vec3 torque_on_i(int l) const { return {t_x[l], t_y[l], t_z[l]}; }
  Vec3 law_torque_on_i(int l) const { return {tl_x[l], tl_y[l], tl_z[l]}; }
};

// The contact law over every staged wall contact. The wall does not move with
// the contact and does not turn: its mass, inertia and lever arm are zero, and
// the contact's effective radius and mass are the particle's.
template <class Kernel>
DEMCAL_VECTOR_CLONES void evaluate_walls(const Kernel& kernel, WallContactBatch& b,
                                         const PairCoefficients* __restrict coefficients,
                                         double dt_s) {
  const int count = b.size;
  for (int l = 0; l < count; ++l) {
    const Vec3 w{b.w_x[l], b.w_y[l], b.w_z[l]};
    ContactKinematics k;
    k.normal = {b.n_x[l], b.n_y[l], b.n_z[l]};
    k.overlap_m = b.r_i[l] - b.distance_m[l];
    k.radius_eff_m = b.r_i[l];
    k.mass_eff_kg = b.m_i[l];
    k.lever_i_m = std::max(b.distance_m[l], 0.0);
    k.inv_mass_i_kg = b.im_i[l];
    k.inv_inertia_i_kg_m2 = b.ii_i[l];
    k.omega_i_rad_s = w;
    k.partner_is_wall = true;
    const Vec3 vc = Vec3{b.dv_x[l], b.dv_y[l], b.dv_z[l]} - k.lever_i_m * cross(w, k.normal);
    k.normal_speed_m_s = dot(vc, k.normal);
    k.tangential_velocity_m_s = vc - k.normal_speed_m_s * k.normal;
    k.dt_s = dt_s;
    ContactHistory h = b.history(l);
    ContactForce cf;
    kernel(k, coefficients[b.coefficient[l]], h, cf);
    b.set_history(l, h);
    const Vec3 fi = cf.normal_force_n * k.normal + cf.tangential_force_n;
    const Vec3 ti = cf.torque_i_nm - k.lever_i_m * cross(k.normal, cf.tangential_force_n);
    b.f_x[l] = fi.x;
    b.f_y[l] = fi.y;
    b.f_z[l] = fi.z;
    b.t_x[l] = ti.x;
    b.t_y[l] = ti.y;
    b.t_z[l] = ti.z;
    b.tl_x[l] = cf.torque_i_nm.x;
    b.tl_y[l] = cf.torque_i_nm.y;
    b.tl_z[l] = cf.torque_i_nm.z;
    b.energy_j[l] = cf.elastic_energy_j;
  }
}

}  // namespace demcal::dem
