// The batched wall-contact evaluation (dem/wall_contact_batch.hpp) against
// the contact law applied to one wall contact at a time, as the engine did
// before (dem/simulation.cpp at f4223a3): the same force, torques, energy and
// history, bit for bit, for every combination of parts, on contacts that
// stick, slide, roll, sit still, and whose centre has passed the wall.
#include "dem/contact/contact_law.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/material.hpp"
#include "dem/wall_contact_batch.hpp"
#include "tests/support/every_contact_law.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace demcal::dem {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const Vec3& a, const Vec3& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

struct WallContact {
  Vec3 normal;
  double distance_m = 0.0;
  double r = 0.0, m = 0.0, im = 0.0, ii = 0.0;
  Vec3 v, w, wall_velocity;
  int coefficient = 0;
  ContactHistory h;
};

struct Outcome {
  Vec3 force_i, torque_i, law_torque_i;
  double energy_j = 0.0;
  ContactHistory history;
};

// The engine's wall-contact arithmetic before batches.
template <class Kernel>
Outcome one_at_a_time(const Kernel& kernel, const WallContact& c, const PairCoefficients& coef,
                      double dt) {
  ContactKinematics k;
  k.normal = c.normal;
  k.overlap_m = c.r - c.distance_m;
  k.radius_eff_m = c.r;
  k.mass_eff_kg = c.m;
  k.lever_i_m = std::max(c.distance_m, 0.0);
  k.inv_mass_i_kg = c.im;
  k.inv_inertia_i_kg_m2 = c.ii;
  k.omega_i_rad_s = c.w;
  k.partner_is_wall = true;
  const Vec3 vc = c.v - c.wall_velocity - k.lever_i_m * cross(c.w, k.normal);
  k.normal_speed_m_s = dot(vc, k.normal);
  k.tangential_velocity_m_s = vc - k.normal_speed_m_s * k.normal;
  k.dt_s = dt;
  ContactHistory h = c.h;
  ContactForce cf;
  kernel(k, coef, h, cf);
  Outcome o;
  o.force_i = cf.normal_force_n * k.normal + cf.tangential_force_n;
  o.torque_i = cf.torque_i_nm - k.lever_i_m * cross(k.normal, cf.tangential_force_n);
  o.law_torque_i = cf.torque_i_nm;
  o.energy_j = cf.elastic_energy_j;
  o.history = h;
  return o;
}

TEST(WallContactBatch, EvaluatesEveryContactAsTheLawDoesOneAtATime) {
  // Two materials; the pair (0, 1) is a wall without rolling friction.
  const std::vector<PairCoefficients> table = testing::two_material_coefficients().table;

  // Overlaps up to 3 % of a radius, a few centres past the wall (distance
  // below zero: no lever arm), spins and histories large enough to slide and
  // roll at the limit, exact zeros for the selects' other sides, and a
  // moving wall.
  std::mt19937_64 rng(20261206);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<WallContact> contacts(203);
  for (std::size_t a = 0; a < contacts.size(); ++a) {
    WallContact& c = contacts[a];
    c.normal = normalized(Vec3{u(rng), u(rng), u(rng)});
    c.r = 1e-3 * (1.5 + 0.5 * u(rng));
    c.distance_m = a % 17 == 0 ? -0.1 * c.r : c.r * (1.0 - 0.015 * (1.0 + u(rng)));
    c.m = 2650.0 * 4.18879 * c.r * c.r * c.r;
    c.im = 1.0 / c.m;
    c.ii = 1.0 / (0.4 * c.m * c.r * c.r);
    c.v = a % 11 == 0 ? Vec3{} : Vec3{0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng)};
    c.w = a % 7 == 0 ? Vec3{} : Vec3{80.0 * u(rng), 80.0 * u(rng), 80.0 * u(rng)};
    // One wall per batch of 64 staged contacts: moving or still, of wall
    // material 0 or 1, so that every coefficient of the table is used.
    const std::size_t wall = a / WallContactBatch::kCapacity;
    c.wall_velocity = wall % 2 == 0 ? Vec3{0.0, 0.0, -0.05} : Vec3{};
    c.coefficient = static_cast<int>(2 * (a % 2) + wall / 2 % 2);
    if (a % 5 != 0) {
      c.h.tangential_displacement_m = {1e-5 * u(rng), 1e-5 * u(rng), 1e-5 * u(rng)};
      c.h.rolling_torque_nm = {1e-6 * u(rng), 1e-6 * u(rng), 1e-6 * u(rng)};
    }
  }
  const double dt = 2e-6;
  // The particles as the engine holds them, in another order than the
  // candidates (particle n - 1 - a is candidate a), and the candidates'
  // histories.
  const std::size_t n = contacts.size();
  std::vector<Vec3> x(n), v(n), w(n);
  std::vector<double> r(n), m(n), im(n), ii(n);
  std::vector<int> mat(n);
  std::vector<ContactHistory> history(n);
  for (std::size_t a = 0; a < n; ++a) {
    const WallContact& c = contacts[a];
    const std::size_t p = n - 1 - a;
    v[p] = c.v;
    w[p] = c.w;
    r[p] = c.r;
    m[p] = c.m;
    im[p] = c.im;
    ii[p] = c.ii;
    mat[p] = static_cast<int>(a % 2);
    history[a] = c.h;
  }
  const ParticleArrays pa{x.data(), v.data(),  w.data(),  r.data(),
                          m.data(), im.data(), ii.data(), mat.data()};

  const int laws =
      testing::for_every_contact_law([&](const ContactLaw& law, const std::string& name) {
        with_contact_kernel(law, [&](const auto& kernel) {
          WallContactBatch batch;
          std::size_t next = 0;
          int mismatches = 0;
          auto check = [&] {
            const WallContact& first = contacts[batch.candidate[0]];
            batch.gather(pa, first.wall_velocity, 2, first.coefficient % 2, history.data());
            evaluate_walls(kernel, batch, table.data(), dt);
            for (int l = 0; l < batch.size; ++l) {
              ASSERT_EQ(batch.candidate[l], next);
              const WallContact& c = contacts[next++];
              const Outcome o =
                  one_at_a_time(kernel, c, table[static_cast<std::size_t>(c.coefficient)], dt);
              const ContactHistory h = batch.history(l);
              const bool same =
                  same_bits(batch.force_on_i(l), o.force_i) &&
                  same_bits(batch.torque_on_i(l), o.torque_i) &&
                  same_bits(batch.law_torque_on_i(l), o.law_torque_i) &&
                  same_bits(batch.energy_j[l], o.energy_j) &&
                  same_bits(h.tangential_displacement_m, o.history.tangential_displacement_m) &&
                  same_bits(h.rolling_torque_nm, o.history.rolling_torque_nm);
              if (!same && mismatches++ == 0)
                ADD_FAILURE() << name << ": wall contact " << next - 1
                              << " differs from the law applied alone (force "
                              << batch.force_on_i(l).x << " against " << o.force_i.x << ")";
            }
            batch.size = 0;
          };
          for (std::size_t a = 0; a < contacts.size(); ++a) {
            const WallContact& c = contacts[a];
            batch.stage(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(n - 1 - a),
                        c.normal, c.distance_m, c.r * c.normal);
            EXPECT_TRUE(same_bits(batch.point(batch.size - 1), c.r * c.normal));
            if (batch.full()) check();
          }
          if (batch.size > 0) check();  // a part-filled last batch
          EXPECT_EQ(next, contacts.size());
          EXPECT_EQ(mismatches, 0) << name;
        });
      });
  EXPECT_GE(laws, 16);
}

}  // namespace
}  // namespace demcal::dem
