// Without damping and friction, contact forces are conservative: total energy
// (kinetic, gravitational, elastic) must not drift in a dense bouncing bed.
#include "physics_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

namespace demcal::dem {
namespace {

TEST(EnergyConservation, DenseElasticBedKeepsItsEnergyOver1e5Steps) {
  // A bed of 360 spheres, 6 x 6 x 10 in a box periodic in x and y (so the periodic
  // contacts are exercised too) over a floor, each with a random velocity.
  constexpr double r = 0.5e-3;
  constexpr int per_side = 6;
  const double spacing = 2.02 * r;
  const double side = per_side * spacing;
  auto o = testing::options_in_box({0, 0, -0.001}, {side, side, 0.05}, {0, 0, -9.81});
  o.domain.periodic = {true, true, false};
  o.contact.tangential = "none";
  o.contact.rolling = "none";
  o.time_step_fraction_of_rayleigh = 0.05;
  auto s = testing::make_scene(o, testing::interaction(1.0, 0.0));
  s.sim->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), s.material);
  Random rng(7);
  for (int iz = 0; iz < 10; ++iz)
    for (int iy = 0; iy < per_side; ++iy)
      for (int ix = 0; ix < per_side; ++ix) {
        const Vec3 pos{(ix + 0.5) * spacing, (iy + 0.5) * spacing, r * 1.01 + iz * spacing};
        const Vec3 vel{rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05)};
        s.sim->add_particle(pos, r, s.material, vel);
      }
  // Energy with the floor as the zero of potential energy.
  auto total = [&] {
    const EnergyBudget e = s.sim->energy();
    return e.total_j();
  };
  s.sim->time_step_s();
  const double e0 = total();
  double worst = 0.0;
  std::size_t max_contacts = 0;
  for (int k = 0; k < 100; ++k) {
    s.sim->run_steps(1000);
    worst = std::max(worst, std::abs(total() - e0));
    max_contacts = std::max(max_contacts, s.sim->contact_count());
  }
  // Potential energy is measured from z = 0; the reference is the bed's energy above it.
  EXPECT_GT(max_contacts, 120u) << "the bed should be dense: a contact per three particles at least";
  EXPECT_EQ(s.sim->step_count(), 100000);
  EXPECT_LT(worst / std::abs(e0), 1e-4) << "e0 = " << e0;
  std::cout << "relative energy drift " << worst / std::abs(e0) << ", up to " << max_contacts
            << " contacts\n";
}

}  // namespace
}  // namespace demcal::dem
