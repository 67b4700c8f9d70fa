// A sphere launched rolling on a flat floor decelerates at (5/7) mu_r g under a
// rolling torque mu_r R F_n, so it stops after 7 v0^2 / (10 mu_r g).
#include "physics_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace demcal::dem {
namespace {

constexpr double kR = 0.5e-3;
constexpr double kG = 9.81;

double stopping_distance(const std::string& model, double mu_r, double v0) {
  auto o = testing::options_in_box({-1, -0.01, -0.001}, {1, 0.01, 0.01}, {0, 0, -kG});
  o.contact.rolling = model;
  o.time_step_fraction_of_rayleigh = 0.1;
  auto s = testing::make_scene(o, testing::interaction(0.3, 0.8, mu_r));
  s.sim->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), s.material);
  const double e_star = 1e7 / (2.0 * 0.91);
  const double m = 2650.0 * 4.0 / 3.0 * std::numbers::pi * kR * kR * kR;
  const double overlap = std::pow(m * kG / (4.0 / 3.0 * e_star * std::sqrt(kR)), 2.0 / 3.0);
  // Rolling without slipping from the start: v = omega x r at the contact.
  s.sim->add_particle({0, 0, kR - overlap}, kR, s.material, {v0, 0, 0}, {0, v0 / kR, 0});
  const double t_stop = v0 / (5.0 / 7.0 * mu_r * kG);
  s.sim->run_until(1.5 * t_stop);
  EXPECT_LT(std::abs(s.sim->particles().velocity_m_s[0].x), 1e-3 * v0) << "still moving";
  return s.sim->particles().position_m[0].x;
}

class RollingStop : public ::testing::TestWithParam<const char*> {};

TEST_P(RollingStop, StopsAtTheAnalyticDistance) {
  for (double mu_r : {0.05, 0.2}) {
    const double v0 = 0.1;
    const double expected = 7.0 * v0 * v0 / (10.0 * mu_r * kG);
    EXPECT_NEAR(stopping_distance(GetParam(), mu_r, v0), expected, 0.02 * expected)
        << GetParam() << " mu_r = " << mu_r;
  }
}

INSTANTIATE_TEST_SUITE_P(EveryModel, RollingStop, ::testing::Values("cdt", "epsd", "sds"));

}  // namespace
}  // namespace demcal::dem
