// The batched contact evaluation (dem/contact_batch.hpp) against the contact
// law applied one contact at a time, as the engine did before batches: the
// same forces, torques, energies and histories, bit for bit, for every
// combination of parts, on contacts that stick, slide, roll and sit still.
// The batch loop is vectorised (and compiled for several instruction sets);
// a part or a compiler flag that made the vector form round differently
// would change runs, and fails here first.
#include "dem/contact/contact_law.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/contact_batch.hpp"
#include "dem/material.hpp"
#include "tests/support/every_contact_law.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace demcal::dem {
namespace {

struct Outcome {
  Vec3 force_i, torque_i, torque_j;
  double energy_j = 0.0;
  ContactHistory history;
};

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const Vec3& a, const Vec3& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

// The engine's pair arithmetic before batches (dem/simulation.cpp at 8f3ad42).
template <class Kernel>
Outcome one_at_a_time(const Kernel& kernel, const ParticleArrays& pa, std::uint32_t i,
                      std::uint32_t j, const Vec3& d, const PairCoefficients& c, ContactHistory h,
                      double dt) {
  const double ri = pa.radius_m[i], rj = pa.radius_m[j], rsum = ri + rj;
  const double dist = std::sqrt(norm2(d));
  const Vec3 wi = pa.omega_rad_s[i], wj = pa.omega_rad_s[j];
  ContactKinematics k;
  k.normal = d / dist;
  k.overlap_m = rsum - dist;
  k.radius_eff_m = ri * rj / rsum;
  k.mass_eff_kg = pa.mass_kg[i] * pa.mass_kg[j] / (pa.mass_kg[i] + pa.mass_kg[j]);
  k.lever_i_m = ri - 0.5 * k.overlap_m;
  k.lever_j_m = rj - 0.5 * k.overlap_m;
  k.inv_mass_i_kg = pa.inv_mass_kg[i];
  k.inv_mass_j_kg = pa.inv_mass_kg[j];
  k.inv_inertia_i_kg_m2 = pa.inv_inertia_kg_m2[i];
  k.inv_inertia_j_kg_m2 = pa.inv_inertia_kg_m2[j];
  k.omega_i_rad_s = wi;
  k.omega_j_rad_s = wj;
  const Vec3 vc = pa.velocity_m_s[i] - pa.velocity_m_s[j] -
                  cross(k.lever_i_m * wi + k.lever_j_m * wj, k.normal);
  k.normal_speed_m_s = dot(vc, k.normal);
  k.tangential_velocity_m_s = vc - k.normal_speed_m_s * k.normal;
  k.dt_s = dt;
  ContactForce cf;
  kernel(k, c, h, cf);
  Outcome o;
  o.force_i = cf.normal_force_n * k.normal + cf.tangential_force_n;
  const Vec3 nxft = cross(k.normal, cf.tangential_force_n);
  o.torque_i = cf.torque_i_nm - k.lever_i_m * nxft;
  o.torque_j = cf.torque_j_nm - k.lever_j_m * nxft;
  o.energy_j = cf.elastic_energy_j;
  o.history = h;
  return o;
}

TEST(ContactBatch, EvaluatesEveryContactAsTheLawDoesOneAtATime) {
  // Two materials, so that the coefficient table is looked up per pair.
  const testing::CoefficientTable coefficients = testing::two_material_coefficients();
  const int nm = coefficients.materials;
  const std::vector<PairCoefficients>& table = coefficients.table;

  // Particles and contacts: overlaps up to 2 % of a radius, spins and
  // histories large enough for sliding and rolling at the limit, and a few
  // exact zeros (no spin, no history) for the selects' other sides.
  std::mt19937_64 rng(20261205);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::size_t n = 300;
  std::vector<Vec3> v(n), w(n);
  std::vector<double> r(n), m(n), im(n), ii(n);
  std::vector<int> mat(n);
  for (std::size_t a = 0; a < n; ++a) {
    r[a] = 1e-3 * (1.5 + 0.5 * u(rng));
    m[a] = 2650.0 * 4.18879 * r[a] * r[a] * r[a];
    im[a] = 1.0 / m[a];
    ii[a] = 1.0 / (0.4 * m[a] * r[a] * r[a]);
    v[a] = {0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng)};
    w[a] = a % 7 == 0 ? Vec3{} : Vec3{80.0 * u(rng), 80.0 * u(rng), 80.0 * u(rng)};
    mat[a] = static_cast<int>(a % 2);
  }
  struct Pair {
    std::uint32_t i, j;
    Vec3 d;
    ContactHistory h;
  };
  std::vector<Pair> pairs;
  for (std::uint32_t a = 0; a + 1 < n; ++a) {
    const std::uint32_t b = a + 1 + static_cast<std::uint32_t>(a % 3);
    if (b >= n) break;
    Vec3 dir{u(rng), u(rng), u(rng)};
    dir = normalized(dir);
    const double overlap = (r[a] + r[b]) * 0.01 * (1.0 + u(rng));
    Pair pr{a, b, dir * (r[a] + r[b] - overlap), ContactHistory{}};
    if (a % 5 != 0) {
      pr.h.tangential_displacement_m = {1e-5 * u(rng), 1e-5 * u(rng), 1e-5 * u(rng)};
      pr.h.rolling_torque_nm = {1e-6 * u(rng), 1e-6 * u(rng), 1e-6 * u(rng)};
    }
    pairs.push_back(pr);
  }
  // The histories as the neighbour list holds them: a pair that did not touch
  // at the last step keeps whatever its entry held (here a spring stretched
  // far out), and the batch must start it from rest.
  std::vector<ContactHistory> listed(pairs.size());
  std::vector<std::uint8_t> touched(pairs.size());
  std::vector<std::uint32_t> partner(pairs.size());
  std::vector<std::uint8_t> code(pairs.size());
  // The batch computes each separation from the positions and the partner's
  // periodic image, as the pair loop does. Each particle is the partner of at
  // most one pair, and of a lower one: the positions are laid out along the
  // pairs so that each pair is separated by its d through its image (the
  // separation recomputed from them may differ from d in the last bits; the
  // law applied alone gets the recomputed one).
  std::array<Vec3, 27> shift_table{};
  for (int c = 0; c < 27; ++c)
    shift_table[static_cast<std::size_t>(c)] = {0.05 * (c % 3 - 1), 0.05 * (c / 3 % 3 - 1),
                                                0.05 * (c / 9 - 1)};
  std::vector<Vec3> x(n);
  std::vector<bool> placed(n, false);
  for (std::size_t q = 0; q < pairs.size(); ++q) {
    Pair& pr = pairs[q];
    code[q] = static_cast<std::uint8_t>(q % 27);
    const Vec3 shift = shift_table[code[q]];
    if (!placed[pr.i]) x[pr.i] = {0.01 * u(rng), 0.01 * u(rng), 0.01 * u(rng)};
    placed[pr.i] = true;
    ASSERT_FALSE(placed[pr.j]) << "particle " << pr.j << " is the partner of two pairs";
    x[pr.j] = x[pr.i] - pr.d - shift;
    placed[pr.j] = true;
    pr.d = x[pr.i] - (x[pr.j] + shift);
  }
  for (std::size_t q = 0; q < pairs.size(); ++q) {
    partner[q] = static_cast<std::uint32_t>(pairs[q].j);
    touched[q] = pairs[q].i % 5 != 0 ? 1 : 0;
    listed[q] = pairs[q].h;
    if (!touched[q]) {
      listed[q].tangential_displacement_m = {1.0, -2.0, 3.0};
      listed[q].rolling_torque_nm = {-4.0, 5.0, -6.0};
    }
  }
  const ParticleArrays pa{x.data(), v.data(),  w.data(),  r.data(),
                          m.data(), im.data(), ii.data(), mat.data()};
  const ListedPairs list{partner.data(), code.data(), shift_table.data(), listed.data()};
  const double dt = 2e-6;

  const int laws =
      testing::for_every_contact_law([&](const ContactLaw& law, const std::string& name) {
        with_contact_kernel(law, [&](const auto& kernel) {
          ContactBatch batch;
          std::size_t next = 0;
          int mismatches = 0;
          auto check = [&] {
            batch.gather(pa, list, nm);
            evaluate(kernel, batch, table.data(), dt);
            for (int l = 0; l < batch.size; ++l) {
              const Pair& pr = pairs[next++];
              const Outcome o = one_at_a_time(
                  kernel, pa, pr.i, pr.j, pr.d,
                  table[static_cast<std::size_t>(mat[pr.i] * nm + mat[pr.j])], pr.h, dt);
              const ContactHistory h = batch.history(l);
              const bool same =
                  same_bits(batch.force_on_i(l), o.force_i) &&
                  same_bits(batch.torque_on_i(l), o.torque_i) &&
                  same_bits(batch.torque_on_j(l), o.torque_j) &&
                  same_bits(batch.energy_j[l], o.energy_j) &&
                  same_bits(h.tangential_displacement_m, o.history.tangential_displacement_m) &&
                  same_bits(h.rolling_torque_nm, o.history.rolling_torque_nm);
              if (!same && mismatches++ == 0)
                ADD_FAILURE() << name << ": contact " << next - 1
                              << " differs from the law applied alone (force "
                              << batch.force_on_i(l).x << " against " << o.force_i.x << ")";
            }
            batch.size = 0;
          };
          for (std::size_t q = 0; q < pairs.size(); ++q) {
            const Pair& pr = pairs[q];
            // Staged as the pair loop does, with a parted pair between
            // every two contacts: it is written but not taken.
            batch.stage(batch.size, pr.i, static_cast<std::uint32_t>(q), touched[q] != 0);
            batch.size += 1;
            if (batch.full()) check();
            batch.stage(batch.size, pr.j, 0, true);
          }
          check();  // a part-filled last batch
          EXPECT_EQ(next, pairs.size());
          EXPECT_EQ(mismatches, 0) << name;
        });
      });
  EXPECT_GE(laws, 16);
}

}  // namespace
}  // namespace demcal::dem
