// Particle–wall friction is its own: a sphere on an inclined plane wall slides
// at g (sin(theta) - mu_s,wall cos(theta)) and is held by rolling friction while
// tan(theta) < mu_r,wall, whatever the particle–particle coefficients are (they
// are set far apart here, in both directions, so that using the wrong pair
// would miss the expected acceleration by tens of per cent).
#include "physics_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace demcal::dem {
namespace {

constexpr double kR = 0.5e-3;
constexpr double kG = 9.81;

struct Slide {
  double acceleration_m_s2;  // along the slope, least squares through v(t)
  double distance_m;
};

// The incline of test_incline.cpp: gravity tilted by theta over a floor, here
// a floor of its own material "steel" with the particle–wall coefficients.
Slide slide(double theta_deg, const InteractionParameters& particle_particle,
            const InteractionParameters& particle_wall, const std::string& rolling,
            double duration_s = 0.06) {
  const double th = theta_deg * std::numbers::pi / 180.0;
  auto o = testing::options_in_box({-1, -0.01, -0.001}, {1, 0.01, 0.01},
                                   {kG * std::sin(th), 0, -kG * std::cos(th)});
  o.contact.rolling = rolling;
  o.time_step_fraction_of_rayleigh = 0.1;
  auto s = testing::make_scene(o, particle_particle);
  Material steel = testing::sand();
  steel.name = "steel";
  const int w = s.sim->add_material(steel);
  s.sim->set_interaction(s.material, w, particle_wall);
  s.sim->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), w);
  const double e_star = 1e7 / (2.0 * 0.91);
  const double m = 2650.0 * 4.0 / 3.0 * std::numbers::pi * kR * kR * kR;
  const double overlap =
      std::pow(m * kG * std::cos(th) / (4.0 / 3.0 * e_star * std::sqrt(kR)), 2.0 / 3.0);
  s.sim->add_particle({0, 0, kR - overlap}, kR, s.material);
  const double settle_s = 0.01;
  s.sim->run_until(settle_s);
  const double x0 = s.sim->particles().position_m[0].x;
  double st = 0, sv = 0, stt = 0, stv = 0;
  int count = 0;
  while (s.sim->time_s() < settle_s + duration_s) {
    s.sim->step();
    const double t = s.sim->time_s(), v = s.sim->particles().velocity_m_s[0].x;
    st += t;
    sv += v;
    stt += t * t;
    stv += t * v;
    ++count;
  }
  return {(count * stv - st * sv) / (count * stt - st * st),
          s.sim->particles().position_m[0].x - x0};
}

TEST(WallFriction, SlidesAtTheParticleWallSlidingFriction) {
  const double theta = 60.0;  // tan 60 = 1.73 > 3.5 mu_s for both coefficients: slipping
  const double th = theta * std::numbers::pi / 180.0;
  for (const auto& [mu_pp, mu_pw] : {std::pair{0.05, 0.4}, std::pair{0.45, 0.1}}) {
    const Slide m =
        slide(theta, testing::interaction(0.3, mu_pp), testing::interaction(0.3, mu_pw), "none");
    const double expected = kG * (std::sin(th) - mu_pw * std::cos(th));
    const double wrong = kG * (std::sin(th) - mu_pp * std::cos(th));
    EXPECT_NEAR(m.acceleration_m_s2, expected, 0.01 * expected)
        << "mu_pp " << mu_pp << ", mu_pw " << mu_pw << " (with mu_pp it would be " << wrong << ")";
  }
}

TEST(WallFriction, RollingIsHeldByTheParticleWallRollingFriction) {
  // Held below tan(theta) = mu_r,wall although mu_r,pp is 0; rolls above it
  // although mu_r,pp is far larger.
  const double mu_r_wall = 0.2;
  const double below = std::atan(0.8 * mu_r_wall) * 180.0 / std::numbers::pi;
  const double above = std::atan(1.5 * mu_r_wall) * 180.0 / std::numbers::pi;
  const auto held = slide(below, testing::interaction(0.3, 0.8, 0.0),
                          testing::interaction(0.3, 0.8, mu_r_wall), "epsd", 0.1);
  EXPECT_LT(std::abs(held.distance_m), 0.01 * kR) << "crept " << held.distance_m << " m";
  const auto rolls = slide(above, testing::interaction(0.3, 0.8, 0.9),
                           testing::interaction(0.3, 0.8, mu_r_wall), "epsd", 0.1);
  const double th = above * std::numbers::pi / 180.0;
  const double expected = 5.0 / 7.0 * kG * (std::sin(th) - mu_r_wall * std::cos(th));
  EXPECT_NEAR(rolls.acceleration_m_s2, expected, 0.02 * expected);
}

}  // namespace
}  // namespace demcal::dem
