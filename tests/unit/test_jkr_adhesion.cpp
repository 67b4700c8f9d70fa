// The JKR adhesion part's closed forms: the contact radius solves the JKR
// overlap relation everywhere on the stable branch, the force and stored energy
// are consistent (dU/d delta = F), the extremes are JKR's (pull-off 3 pi gamma R*,
// zero load, breakage), the hold test agrees with the critical distance, and
// gamma = 0 leaves a dry contact exactly as the normal part made it.

#include "dem/contact/contact_law.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace demcal::dem {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kE = 5.5e6;     // E*, Pa
constexpr double kGamma = 0.05;  // J/m^2
constexpr double kR = 2.5e-4;    // R*, m

TEST(JkrAdhesion, ContactRadiusSolvesTheOverlapRelationOnTheStableBranch) {
  for (double d = -3.0; d < 1e6; d = d < 0.0 ? d + 0.125 : (d == 0.0 ? 1e-3 : d * 1.5)) {
    const double s = jkr::root_of_overlap(d);
    EXPECT_GE(s, 1.0 - 1e-12) << "D = " << d;
    // s^4 - 4 s = D, relative to the size of the terms.
    EXPECT_NEAR(s * s * s * s - 4.0 * s, d, 1e-12 * (s * s * s * s + 4.0 * s)) << "D = " << d;
  }
  // In SI: delta = a^2 / R - 2 sqrt(pi gamma a / E) at the radius returned.
  for (double overlap : {-6e-7, -1e-7, 0.0, 1e-7, 1e-6, 1e-5, 1e-4}) {
    const JkrContact c = jkr::contact(kE, kGamma, kR, overlap);
    const double a = c.contact_radius_m;
    EXPECT_NEAR(a * a / kR - 2.0 * std::sqrt(kPi * kGamma * a / kE), overlap, 1e-12 * (a * a / kR))
        << "overlap " << overlap;
    EXPECT_NEAR(c.force_n,
                4.0 * kE * a * a * a / (3.0 * kR) - 4.0 * std::sqrt(kPi * kGamma * kE * a * a * a),
                1e-10 * (4.0 * kE * a * a * a / (3.0 * kR)));
    // The Hertz force at the same overlap, as the Hertz part computes it.
    const double dp = std::max(overlap, 0.0);
    EXPECT_NEAR(c.hertz_force_n, 4.0 / 3.0 * kE * std::sqrt(kR) * std::pow(dp, 1.5),
                1e-10 * (c.hertz_force_n + 1e-12));
  }
}

TEST(JkrAdhesion, ForceAndEnergyAreConsistentAndHaveJkrsExtremes) {
  const double critical = jkr::critical_separation_m(kE, kGamma, kR);
  const double pull_off = 3.0 * kPi * kGamma * kR;
  double min_force = 0.0;
  for (double x = -critical; x < 5.0 * critical; x += critical * 1e-4)
    min_force = std::min(min_force, jkr::contact(kE, kGamma, kR, x).force_n);
  EXPECT_NEAR(-min_force, pull_off, 1e-6 * pull_off);
  // Zero load at a0 = (9 pi gamma R^2 / E)^(1/3).
  const double a0 = std::cbrt(9.0 * kPi * kGamma * kR * kR / kE);
  const double delta0 = a0 * a0 / kR - 2.0 * std::sqrt(kPi * kGamma * a0 / kE);
  EXPECT_NEAR(jkr::contact(kE, kGamma, kR, delta0).force_n, 0.0, 1e-9 * pull_off);
  // Broken at zero energy; dU/d delta = F by central differences.
  EXPECT_NEAR(jkr::contact(kE, kGamma, kR, -critical).energy_j, 0.0, 1e-12 * pull_off * critical);
  for (double x : {-0.9 * critical, -0.2 * critical, 0.5 * critical, 20.0 * critical}) {
    const double h = 1e-5 * critical;
    const double du = (jkr::contact(kE, kGamma, kR, x + h).energy_j -
                       jkr::contact(kE, kGamma, kR, x - h).energy_j) /
                      (2.0 * h);
    EXPECT_NEAR(du, jkr::contact(kE, kGamma, kR, x).force_n, 1e-5 * pull_off) << x;
  }
}

TEST(JkrAdhesion, HoldsExactlyUpToTheCriticalDistance) {
  PairCoefficients c;
  c.youngs_modulus_eff_pa = kE;
  c.surface_energy_j_m2 = kGamma;
  const JkrAdhesion part;
  const double critical = part.max_separation_m(c, kR);
  // -(3/4) (4 pi^2 gamma^2 R / E^2)^(1/3), Johnson's critical separation with w = 2 gamma.
  EXPECT_NEAR(critical, 0.75 * std::cbrt(4.0 * kPi * kPi * kGamma * kGamma * kR / (kE * kE)),
              1e-12 * critical);
  EXPECT_TRUE(part.holds(c, kR, -0.999 * critical));
  EXPECT_FALSE(part.holds(c, kR, -1.001 * critical));
  c.surface_energy_j_m2 = 0.0;
  EXPECT_FALSE(part.holds(c, kR, -1e-15));
  EXPECT_EQ(part.max_separation_m(c, kR), 0.0);
}

TEST(JkrAdhesion, ZeroSurfaceEnergyLeavesTheDryContactUntouched) {
  ContactKinematics k;
  k.normal = {0, 0, 1};
  k.overlap_m = 2e-6;
  k.radius_eff_m = kR;
  k.mass_eff_kg = 1e-6;
  k.normal_speed_m_s = -0.1;
  PairCoefficients c;
  c.youngs_modulus_eff_pa = kE;
  c.damping_beta = 0.2;
  ContactHistory h;
  ContactForce dry, wet;
  HertzNormal{}.apply(k, c, h, dry);
  HertzNormal{}.apply(k, c, h, wet);
  JkrAdhesion{}.apply(k, c, h, wet);
  EXPECT_EQ(wet.normal_force_n, dry.normal_force_n);
  EXPECT_EQ(wet.friction_load_n, dry.friction_load_n);
  EXPECT_EQ(wet.contact_radius_m, dry.contact_radius_m);
  EXPECT_EQ(wet.elastic_energy_j, dry.elastic_energy_j);
  // With gamma: at rest the total is F_JKR, and the friction load is F + 2 F_po.
  c.surface_energy_j_m2 = kGamma;
  k.normal_speed_m_s = 0.0;
  ContactForce f;
  HertzNormal{}.apply(k, c, h, f);
  JkrAdhesion{}.apply(k, c, h, f);
  const JkrContact j = jkr::contact(kE, kGamma, kR, k.overlap_m);
  EXPECT_NEAR(f.normal_force_n, j.force_n, 1e-12 * j.hertz_force_n);
  EXPECT_NEAR(f.friction_load_n, j.force_n + 6.0 * kPi * kGamma * kR, 1e-12 * j.hertz_force_n);
  EXPECT_EQ(f.contact_radius_m, j.contact_radius_m);
  // Held at negative overlap, the Hertz part gives nothing and JKR pulls.
  k.overlap_m = -1e-7;
  ContactForce g;
  HertzNormal{}.apply(k, c, h, g);
  EXPECT_EQ(g.normal_force_n, 0.0);
  EXPECT_EQ(g.contact_radius_m, 0.0);
  JkrAdhesion{}.apply(k, c, h, g);
  EXPECT_LT(g.normal_force_n, 0.0);
  EXPECT_GT(g.friction_load_n, 0.0);
}

TEST(JkrAdhesion, OnlyLawsWithItHoldContactsBeyondTouching) {
  ContactLawSpec spec;
  auto holds = [](const ContactLaw& law) {
    return with_contact_kernel(law, [](const auto& kernel) {
      return std::decay_t<decltype(kernel)>::kHoldsBeyondTouching;
    });
  };
  EXPECT_FALSE(holds(make_contact_law(spec)));
  spec.adhesion = "jkr";
  EXPECT_TRUE(holds(make_contact_law(spec)));
  const auto names = known_part_names("adhesion");
  EXPECT_NE(std::find(names.begin(), names.end(), "jkr"), names.end());
}

}  // namespace
}  // namespace demcal::dem
