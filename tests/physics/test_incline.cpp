// A sphere on an incline (gravity tilted by theta over a flat floor): it rolls
// without slipping at (5/7) g sin(theta) while tan(theta) < 3.5 mu_s, and slips
// at g (sin(theta) - mu_s cos(theta)) beyond. Rolling resistance holds it at rest
// while tan(theta) < mu_r and lets it roll at (5/7) g (sin(theta) - mu_r cos(theta)) beyond.
#include "physics_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace demcal::dem {
namespace {

constexpr double kR = 0.5e-3;
constexpr double kG = 9.81;

struct Motion {
  double acceleration_m_s2;  // along the slope, from a least-squares line through v(t)
  double slip_speed_m_s;     // |v - omega x r| at the contact point at the end
  double distance_m;
};

Motion slide_or_roll(double theta_deg, double mu_s, const std::string& rolling, double mu_r,
                     double duration_s = 0.06) {
  const double th = theta_deg * std::numbers::pi / 180.0;
  auto o = testing::options_in_box({-1, -0.01, -0.001}, {1, 0.01, 0.01},
                                   {kG * std::sin(th), 0, -kG * std::cos(th)});
  o.contact.rolling = rolling;
  o.time_step_fraction_of_rayleigh = 0.1;
  auto s = testing::make_scene(o, testing::interaction(0.3, mu_s, mu_r));
  s.sim->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), s.material);
  // Start at the static overlap so no bounce disturbs the measurement.
  const double e_star = 1e7 / (2.0 * 0.91);
  const double m = 2650.0 * 4.0 / 3.0 * std::numbers::pi * kR * kR * kR;
  const double overlap = std::pow(m * kG * std::cos(th) / (4.0 / 3.0 * e_star * std::sqrt(kR)), 2.0 / 3.0);
  s.sim->add_particle({0, 0, kR - overlap}, kR, s.material);
  // Let the tangential spring load up, then fit v(t) over the rest.
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
  const auto& p = s.sim->particles();
  const Vec3 contact_velocity = p.velocity_m_s[0] + cross(p.omega_rad_s[0], Vec3{0, 0, -kR});
  return {(count * stv - st * sv) / (count * stt - st * st), norm(contact_velocity),
          p.position_m[0].x - x0};
}

TEST(Incline, RollsWithoutSlippingBelowTheThreshold) {
  for (double theta : {10.0, 20.0, 40.0}) {  // 3.5 * 0.3 = 1.05 > tan(40 deg) = 0.84
    const auto m = slide_or_roll(theta, 0.3, "none", 0.0);
    const double expected = 5.0 / 7.0 * kG * std::sin(theta * std::numbers::pi / 180.0);
    EXPECT_NEAR(m.acceleration_m_s2, expected, 0.01 * expected) << theta << " deg";
    EXPECT_LT(m.slip_speed_m_s, 1e-3) << theta << " deg";
  }
}

TEST(Incline, SlipsAboveTheThreshold) {
  for (double theta : {50.0, 60.0, 75.0}) {  // tan(50 deg) = 1.19 > 1.05
    const double th = theta * std::numbers::pi / 180.0;
    const auto m = slide_or_roll(theta, 0.3, "none", 0.0);
    const double expected = kG * (std::sin(th) - 0.3 * std::cos(th));
    EXPECT_NEAR(m.acceleration_m_s2, expected, 0.01 * expected) << theta << " deg";
    EXPECT_GT(m.slip_speed_m_s, 0.01) << theta << " deg";
  }
}

class RollingResistanceIncline : public ::testing::TestWithParam<const char*> {};

TEST_P(RollingResistanceIncline, HeldBelowTanThetaEqualsMuRAndRollingAbove) {
  const double mu_r = 0.2;
  const double below = std::atan(0.8 * mu_r) * 180.0 / std::numbers::pi;
  const double above = std::atan(1.5 * mu_r) * 180.0 / std::numbers::pi;
  const auto held = slide_or_roll(below, 0.8, GetParam(), mu_r, 0.1);
  EXPECT_LT(std::abs(held.distance_m), 0.01 * kR) << "crept " << held.distance_m << " m";
  const auto rolls = slide_or_roll(above, 0.8, GetParam(), mu_r, 0.1);
  const double th = above * std::numbers::pi / 180.0;
  const double expected = 5.0 / 7.0 * kG * (std::sin(th) - mu_r * std::cos(th));
  EXPECT_NEAR(rolls.acceleration_m_s2, expected, 0.02 * expected);
}

INSTANTIATE_TEST_SUITE_P(EveryModel, RollingResistanceIncline,
                         ::testing::Values("cdt", "epsd", "sds"));

}  // namespace
}  // namespace demcal::dem
