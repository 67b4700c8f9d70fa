// The force loop split over a team: each chunk adds what it computes for its
// own particles straight into the particle arrays and what it computes for
// partners beyond its range into a buffer, and the buffers are summed in
// afterwards (dem/simulation.cpp, compute_contact_forces). Whatever the team's
// size, every contact must be counted once: the forces and torques equal the
// one-thread loop's up to rounding. The teams are made much larger than the
// machine's cores so that the chunks are a few dozen particles and a chunk's
// partners reach over the whole next chunk and beyond (a particle then gets
// buffered contributions from two or more earlier chunks), the case a
// two-thread run never exercises.
#include "physics_fixtures.hpp"

#include "dem/random.hpp"
#include "dem/wall/plane_wall.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace demcal::dem {
namespace {

constexpr double kRadius = 0.5e-3;

// A jittered lattice at 1.9 radii: every sphere overlaps its lattice
// neighbours, the lowest layer the floor; random velocities and spins give
// every part of the law (normal, tangential, rolling) something to do.
std::unique_ptr<Simulation> compressed_bed(int threads) {
  const double spacing = 1.9 * kRadius;
  const int nx = 8, ny = 8, nz = 6;
  auto o =
      testing::options_in_box({0, 0, -0.001}, {nx * spacing, ny * spacing, 0.02}, {0, 0, -9.81});
  o.domain.periodic = {true, true, false};
  o.contact.rolling = "epsd";
  o.threads = threads;
  o.particle_order = ParticleOrder::kSpatial;
  auto s = testing::make_scene(o, testing::interaction(0.6, 0.5, 0.1));
  s.sim->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), s.material);
  Random rng(7);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Vec3 x{(i + 0.5) * spacing + rng.uniform(-0.02, 0.02) * kRadius,
                     (j + 0.5) * spacing + rng.uniform(-0.02, 0.02) * kRadius,
                     0.9 * kRadius + k * spacing};
        const Vec3 v{rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05)};
        const Vec3 w{rng.uniform(-50.0, 50.0), rng.uniform(-50.0, 50.0), rng.uniform(-50.0, 50.0)};
        s.sim->add_particle(x, kRadius, s.material, v, w);
      }
  return std::move(s.sim);
}

struct ForcesById {
  std::map<std::int64_t, Vec3> force_n, torque_nm;
  double largest_force_n = 0.0, largest_torque_nm = 0.0;
  std::size_t contacts = 0;
};

ForcesById forces_after(int threads, int steps) {
  auto sim = compressed_bed(threads);
  sim->run_steps(steps);
  ForcesById out;
  const Particles& p = sim->particles();
  for (std::size_t i = 0; i < p.size(); ++i) {
    out.force_n[p.id[i]] = p.force_n[i];
    out.torque_nm[p.id[i]] = p.torque_nm[i];
    out.largest_force_n = std::max(out.largest_force_n, norm(p.force_n[i]));
    out.largest_torque_nm = std::max(out.largest_torque_nm, norm(p.torque_nm[i]));
  }
  out.contacts = sim->contact_count();
  return out;
}

TEST(TeamForceSum, EveryTeamSizeGivesTheOneThreadForces) {
  // Two steps: the forces of the second are computed at positions that one
  // step of team-dependent rounding moved by about 1e-16 m, far below what a
  // contact counted twice or lost would change.
  const ForcesById one = forces_after(1, 2);
  ASSERT_EQ(one.force_n.size(), 384u);
  ASSERT_GT(one.contacts, 1000u) << "the bed should be compressed";
  ASSERT_GT(one.largest_force_n, 0.0);
  ASSERT_GT(one.largest_torque_nm, 0.0);
  for (int threads : {2, 3, 5, 16}) {
    const ForcesById team = forces_after(threads, 2);
    EXPECT_EQ(team.contacts, one.contacts) << threads << " threads";
    ASSERT_EQ(team.force_n.size(), one.force_n.size());
    double worst_f = 0.0, worst_t = 0.0;
    for (const auto& [id, f] : one.force_n) {
      worst_f = std::max(worst_f, norm(team.force_n.at(id) - f));
      worst_t = std::max(worst_t, norm(team.torque_nm.at(id) - one.torque_nm.at(id)));
    }
    // Measured when written: at most 2e-15 of the largest force and torque.
    EXPECT_LT(worst_f, 1e-9 * one.largest_force_n) << threads << " threads";
    EXPECT_LT(worst_t, 1e-9 * one.largest_torque_nm) << threads << " threads";
  }
}

}  // namespace
}  // namespace demcal::dem
