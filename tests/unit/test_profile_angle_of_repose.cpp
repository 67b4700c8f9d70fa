// The angle of repose read from a measured surface profile h(s) (a laboratory's
// laser line) with the slice rules: exact on an analytic heap, robust to
// missing readings and to reading noise, the same angle as the particle
// measurement when the profile is the particles' own surface, and refusals
// that say what is wrong.
#include "dem/measure/angle_of_repose.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

namespace demcal::dem {
namespace {

constexpr double kD = 1e-3;  // grain diameter, m

// A symmetric heap: crest height h0 at s = 0, flanks at `angle_deg`, flat floor beyond.
double heap(double s, double h0, double angle_deg) {
  const double t = std::tan(angle_deg * std::numbers::pi / 180.0);
  return std::max(0.0, h0 - t * std::abs(s));
}

TEST(ProfileAngleOfRepose, ReadsTheSlopeOfAnAnalyticHeap) {
  for (const double angle : {25.0, 32.0, 41.57}) {
    std::vector<double> s, h;
    for (double x = -0.06; x <= 0.06; x += 1e-4) {
      s.push_back(x);
      h.push_back(heap(x, 0.02, angle));
    }
    const AngleOfRepose r = measure_profile_angle_of_repose(s, h, kD);
    EXPECT_EQ(r.valid_sides, 2);
    // Each bin's height is its highest reading, fitted where it was read: on a
    // straight flank that is exactly on the line.
    EXPECT_NEAR(r.mean_deg, angle, 0.05) << angle;
    EXPECT_NEAR(r.crest_height_m, 0.02, 2e-4);
    EXPECT_EQ(r.particles_used, 0u);
  }
}

TEST(ProfileAngleOfRepose, NoisyReadingsAndGapsOverSeeds) {
  // Reading noise of a tenth of a grain and 20 % of the readings missing:
  // the angle stays within its stated uncertainty's reach over 10 seeds.
  int within = 0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.1 * kD);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> s, h;
    for (double x = -0.06; x <= 0.06; x += 2e-4) {
      s.push_back(x);
      h.push_back(u(rng) < 0.2 ? std::numeric_limits<double>::quiet_NaN()
                               : heap(x, 0.02, 35.0) + noise(rng));
    }
    const AngleOfRepose r = measure_profile_angle_of_repose(s, h, kD);
    ASSERT_EQ(r.valid_sides, 2);
    if (std::abs(r.mean_deg - 35.0) <= 3.0 * r.uncertainty_deg + 0.2) ++within;
  }
  EXPECT_GE(within, 9);
}

TEST(ProfileAngleOfRepose, TheParticlesOwnSurfaceGivesTheParticleAngle) {
  // A heap of spheres on a lattice; the profile is max(z + r) at each
  // particle's position: the two measurements apply the same rules.
  std::vector<Vec3> pos;
  std::vector<double> rad;
  std::vector<double> s, h;
  const double r = 0.5 * kD;
  for (double x = -0.05; x <= 0.05; x += kD) {
    const double top = heap(x, 0.02, 33.0);
    for (double z = r; z + r <= top + 1e-12; z += kD) {
      pos.push_back({x, 0.0, z});
      rad.push_back(r);
      s.push_back(x);
      h.push_back(z + r);
    }
  }
  const AngleOfRepose from_particles = measure_slice_angle_of_repose(pos, rad);
  const AngleOfRepose from_profile = measure_profile_angle_of_repose(s, h, kD);
  EXPECT_NEAR(from_profile.mean_deg, from_particles.mean_deg, 1e-9);
  EXPECT_NEAR(from_profile.crest_height_m, from_particles.crest_height_m, 1e-12);
}

TEST(ProfileAngleOfRepose, RefusesWhatCannotBeAProfile) {
  const std::vector<double> s{0.0, 1e-3, 2e-3};
  EXPECT_THROW(measure_profile_angle_of_repose(s, {1e-3, 2e-3}, kD), std::invalid_argument);
  EXPECT_THROW(measure_profile_angle_of_repose(s, {1e-3, 2e-3, 3e-3}, 0.0), std::invalid_argument);
  EXPECT_THROW(measure_profile_angle_of_repose({0.0, std::nan(""), 1.0}, {1e-3, 2e-3, 3e-3}, kD),
               std::invalid_argument);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(measure_profile_angle_of_repose(s, {nan, nan, nan}, kD), std::runtime_error);
  // A flat layer: no slope on either side.
  std::vector<double> flat_s, flat_h;
  for (double x = -0.05; x <= 0.05; x += 1e-4) {
    flat_s.push_back(x);
    flat_h.push_back(2e-3);
  }
  try {
    measure_profile_angle_of_repose(flat_s, flat_h, kD);
    FAIL() << "a flat layer has no angle";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("too flat"), std::string::npos) << e.what();
  }
  AoRCommonOptions with_box;
  with_box.selection = SelectionBox{{-1, -1, -1}, {1, 1, 1}};
  EXPECT_THROW(measure_profile_angle_of_repose(s, {1e-3, 2e-3, 3e-3}, kD, with_box),
               std::invalid_argument);
}

}  // namespace
}  // namespace demcal::dem
