// Walls record the load the particles put on them: a bed at rest weighs on its
// floor, and a moving wall carries its contacts along.
#include "physics_fixtures.hpp"

#include "dem/insertion/inserter.hpp"
#include "dem/wall/cylinder_wall.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace demcal::dem {
namespace {

TEST(WallLoads, FloorCarriesTheWeightOfABedAtRest) {
  auto o = testing::options_in_box({-0.01, -0.01, -0.001}, {0.01, 0.01, 0.05}, {0, 0, -9.81});
  // The spring-dashpot rolling model holds a static bed still; the constant
  // torque model lets a stacked lattice creep for a long time before it settles.
  o.contact.rolling = "epsd";
  auto s = testing::make_scene(o, testing::interaction(0.3, 0.5, 0.1));
  const int floor = s.sim->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), s.material);
  s.sim->add_wall(std::make_unique<CylinderWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, 0.05, 0.008), s.material);
  FillOptions f;
  f.amount.count = 300;
  f.method = "lattice";
  s.sim->add_inserter(make_fill_inserter(make_cylinder_region({0, 0, 0.0005}, 0.0079, 0.03),
                                         make_monodisperse(1e-3), f));
  s.sim->run_until(0.4);
  double weight = 0.0;
  for (double m : s.sim->particles().mass_kg) weight += m * 9.81;
  const Vec3 f_floor = s.sim->wall_loads()[floor].force_n;
  const Vec3 f_side = s.sim->wall_loads()[1].force_n;
  ASSERT_LT(s.sim->rms_speed_m_s(), 1e-3) << "bed not at rest";
  // Side-wall friction (Janssen) carries part of the weight; floor + side carry all of it.
  EXPECT_NEAR(-(f_floor.z + f_side.z), weight, 0.01 * weight);
  EXPECT_LT(-f_floor.z, weight * 1.001);
  EXPECT_GT(-f_floor.z, 0.3 * weight);
  EXPECT_GT(s.sim->wall_loads()[floor].contacts, 20u);
}

TEST(WallLoads, PlaneMovingAtConstantSpeedPushesAParticleAlong) {
  auto o = testing::options_in_box({-0.01, -0.01, -0.01}, {0.05, 0.01, 0.01}, {0, 0, 0});
  auto s = testing::make_scene(o, testing::interaction(0.5, 0.0));
  auto pusher = std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{1, 0, 0});
  WallMotion motion;
  motion.velocity_m_s = {0.1, 0, 0};
  pusher->set_motion(motion);
  const int w = s.sim->add_wall(std::move(pusher), s.material);
  s.sim->add_particle({0.5e-3 + 1e-5, 0, 0}, 0.5e-3, s.material);
  s.sim->run_until(0.1);
  // After the first impact (e = 0.5) the particle leads the wall at 1.5 x its speed.
  EXPECT_NEAR(s.sim->particles().velocity_m_s[0].x, 0.15, 0.003);
  EXPECT_EQ(s.sim->wall_loads()[w].contacts, 0u);
}

TEST(Instability, TooLargeATimeStepStopsTheRunWithAClearError) {
  auto o = testing::options_in_box({-0.01, -0.01, -0.01}, {0.01, 0.01, 0.01}, {0, 0, 0});
  o.time_step_s = 2e-4;  // ~5 Rayleigh times: contacts explode
  auto s = testing::make_scene(o, testing::interaction(0.9, 0.5));
  s.sim->add_particle({-0.49e-3, 0, 0}, 0.5e-3, s.material, {1, 0, 0});
  s.sim->add_particle({0.49e-3, 0, 0}, 0.5e-3, s.material, {-1, 0, 0});
  try {
    s.sim->run_steps(200);
    FAIL() << "expected an InstabilityError";
  } catch (const InstabilityError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("unstable run"), std::string::npos) << what;
    EXPECT_NE(what.find("time step"), std::string::npos) << what;
  }
}

TEST(Instability, AParticleLeavingTheBoxStopsTheRun) {
  auto o = testing::options_in_box({-0.01, -0.01, -0.01}, {0.01, 0.01, 0.01}, {0, 0, -9.81});
  auto s = testing::make_scene(o, testing::interaction(0.5, 0.5));
  s.sim->add_particle({0, 0, 0}, 0.5e-3, s.material);
  try {
    s.sim->run_until(0.2);
    FAIL() << "expected an InstabilityError";
  } catch (const InstabilityError& e) {
    EXPECT_NE(std::string(e.what()).find("left the domain"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace demcal::dem
