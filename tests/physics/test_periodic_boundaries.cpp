// A cluster straddling a periodic boundary must feel exactly what its unwrapped
// copy feels in a box large enough to hold it whole.
#include "physics_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace demcal::dem {
namespace {

constexpr double kR = 0.5e-3;
constexpr double kL = 0.012;  // periodic length along x: wide enough that the cluster never meets its own image

struct Cluster {
  std::vector<Vec3> position, velocity, omega;
};

// Nine touching spheres around x = 0, i.e. across the boundary of [0, L).
Cluster make_cluster() {
  Cluster c;
  Random rng(3);
  for (int k = 0; k < 9; ++k) {
    c.position.push_back({(k % 3 - 1) * 1.98 * kR + rng.uniform(-2e-6, 2e-6),
                          0.01 + (k / 3 - 1) * 1.98 * kR, 0.01 + rng.uniform(-4e-6, 4e-6)});
    c.velocity.push_back({rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05)});
    c.omega.push_back({rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20)});
  }
  return c;
}

std::unique_ptr<Simulation> build(bool periodic, const Cluster& c) {
  SimulationOptions o = periodic ? testing::options_in_box({0, 0, 0}, {kL, 0.02, 0.02}, {0, 0, 0})
                                 : testing::options_in_box({-0.02, 0, 0}, {0.02, 0.02, 0.02}, {0, 0, 0});
  o.domain.periodic = {periodic, false, false};
  o.contact.rolling = "epsd";
  auto s = testing::make_scene(o, testing::interaction(0.5, 0.5, 0.2));
  for (std::size_t k = 0; k < c.position.size(); ++k) {
    Vec3 p = c.position[k];
    if (periodic && p.x < 0.0) p.x += kL;
    s.sim->add_particle(p, kR, s.material, c.velocity[k], c.omega[k]);
  }
  return std::move(s.sim);
}

TEST(PeriodicBoundaries, ClusterAcrossTheBoundaryFeelsWhatItsUnwrappedCopyFeels) {
  const Cluster c = make_cluster();
  auto wrapped = build(true, c);
  auto open = build(false, c);
  wrapped->time_step_s();
  open->time_step_s();
  ASSERT_GT(open->contact_count(), 6u) << "the cluster should be in contact";
  EXPECT_EQ(wrapped->contact_count(), open->contact_count());
  const auto& fw = wrapped->particles().force_n;
  const auto& fo = open->particles().force_n;
  for (std::size_t k = 0; k < fw.size(); ++k) {
    EXPECT_NEAR(norm(fw[k] - fo[k]), 0.0, 1e-9 * norm(fo[k]) + 1e-15) << "particle " << k;
    EXPECT_NEAR(norm(wrapped->particles().torque_nm[k] - open->particles().torque_nm[k]), 0.0,
                1e-9 * norm(open->particles().torque_nm[k]) + 1e-18);
  }
  // And they keep moving alike, history included, through many re-wraps.
  wrapped->run_steps(1500);
  open->run_steps(1500);
  for (std::size_t k = 0; k < fw.size(); ++k) {
    Vec3 d = wrapped->particles().position_m[k] - open->particles().position_m[k];
    d.x -= kL * std::round(d.x / kL);
    EXPECT_LT(norm(d), 1e-9) << "particle " << k;
  }
}

TEST(PeriodicBoundaries, RefusesASlabThinnerThanTwoCutOffs) {
  auto o = testing::options_in_box({0, 0, 0}, {0.0015, 0.01, 0.01}, {0, 0, 0});
  o.domain.periodic = {true, false, false};
  auto s = testing::make_scene(o, testing::interaction(0.5, 0.5));
  s.sim->add_particle({0.0007, 0.005, 0.005}, kR, s.material);
  EXPECT_THROW(s.sim->time_step_s(), std::runtime_error);
}

}  // namespace
}  // namespace demcal::dem
