// The capillary liquid bridge (adhesion = "liquid_bridge") against Willett et
// al. (2000)'s closed form and Lian et al. (1993)'s rupture distance, every
// expected value computed here from the formulas as published:
//   F(S) = 2 pi R gamma cos(theta) / (1 + 2.1 S+ + 10 S+^2),  S+ = (S / 2) sqrt(R / V),
// (Willett's own variables: S the full gap, S+ the half-gap scaled; the part
// writes it with S~ = S sqrt(R / V), i.e. 1.05 and 2.5), R = 2 R*, and
//   S_c = (1 + theta / 2) V^(1/3).
// Two grains (and a grain and a plane wall), touching, are pulled apart at an
// imposed speed: the tension follows F(S) at every step and vanishes within
// one step's travel of S_c; pushed back, nothing acts until they touch again.
#include "physics_fixtures.hpp"

#include "dem/contact/contact_law.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <numbers>

namespace demcal::dem {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kR = 0.5e-3;          // grain radius, m
constexpr double kGamma = 0.072;       // water, N/m
constexpr double kThetaDeg = 20.0;     // contact angle
constexpr double kFraction = 1.0e-3;   // bridge volume / (4/3 pi R_D^3)

// R_D = 2 R*: kR for two equal grains, 2 kR for a grain on a plane.
double derjaguin_radius(bool against_wall) { return against_wall ? 2.0 * kR : kR; }
double volume(double r_d) { return kFraction * 4.0 / 3.0 * kPi * r_d * r_d * r_d; }
double theta_rad() { return kThetaDeg * kPi / 180.0; }
// Willett et al. (2000), in their half-gap variable.
double willett_force(double gap, double r_d) {
  const double s_plus = 0.5 * gap * std::sqrt(r_d / volume(r_d));
  return 2.0 * kPi * r_d * kGamma * std::cos(theta_rad()) / (1.0 + 2.1 * s_plus + 10.0 * s_plus * s_plus);
}
double rupture_gap(double r_d) { return (1.0 + 0.5 * theta_rad()) * std::cbrt(volume(r_d)); }

InteractionParameters wet(double gamma = kGamma) {
  InteractionParameters p = testing::interaction(0.5, 0.5, 0.0);
  p.part_values[liquid_bridge::kSurfaceTensionSlot] = gamma;
  p.part_values[liquid_bridge::kContactAngleSlot] = kThetaDeg;
  p.part_values[liquid_bridge::kVolumeFractionSlot] = kFraction;
  return p;
}

PairCoefficients wet_pair() {
  PairCoefficients c;
  c.youngs_modulus_eff_pa = 5.5e6;
  c.part_values = wet().part_values;
  return c;
}

TEST(LiquidBridge, ForceFollowsWillettAgainstSeparation) {
  const PairCoefficients c = wet_pair();
  for (bool wall : {false, true}) {
    const double r_d = derjaguin_radius(wall);
    const liquid_bridge::Bridge b = liquid_bridge::Bridge::of(c, 0.5 * r_d);
    // Touching: 2 pi R gamma cos(theta); a grain on a plane: 4 pi R_grain gamma cos(theta).
    EXPECT_NEAR(b.force_n(0.0), 2.0 * kPi * r_d * kGamma * std::cos(theta_rad()), 1e-15);
    EXPECT_NEAR(b.force_n(-1e-6), b.force_n(0.0), 0.0);  // overlapping: the touching value
    const double sc = rupture_gap(r_d);
    for (double x : {0.01, 0.1, 0.3, 0.5, 0.8, 0.99}) {
      const double f = b.force_n(x * sc);
      EXPECT_NEAR(f, willett_force(x * sc, r_d), 1e-12 * willett_force(0.0, r_d)) << x;
    }
    // Monotone decreasing, and about a quarter of F(0) where S+ = 1/2 (1 + 1.05 + 2.5 = 4.55).
    const double s_unit = std::sqrt(volume(r_d) / r_d);
    EXPECT_NEAR(b.force_n(s_unit), b.force_n(0.0) / 4.55, 1e-12 * b.force_n(0.0));
    EXPECT_EQ(b.force_n(1.0001 * sc), 0.0);
  }
}

TEST(LiquidBridge, RupturesAtLiansDistanceAndEnergyIsConsistent) {
  const PairCoefficients c = wet_pair();
  const LiquidBridge part;
  for (bool wall : {false, true}) {
    const double r_d = derjaguin_radius(wall), r_eff = 0.5 * r_d;
    const double sc = rupture_gap(r_d);
    EXPECT_NEAR(part.max_separation_m(c, r_eff), sc, 1e-12 * sc);
    EXPECT_TRUE(part.holds(c, r_eff, -0.999 * sc));
    EXPECT_FALSE(part.holds(c, r_eff, -1.001 * sc));
    // U(S_c) = 0 and -dU/dS = -F (attraction) by central differences.
    const liquid_bridge::Bridge b = liquid_bridge::Bridge::of(c, r_eff);
    EXPECT_NEAR(b.energy_j(sc * (1.0 - 1e-12)), 0.0, 1e-9 * b.force_n(0.0) * sc);
    for (double x : {-0.05, 0.05, 0.3, 0.7, 0.95}) {
      const double h = 1e-6 * sc;
      const double du = (b.energy_j(x * sc + h) - b.energy_j(x * sc - h)) / (2.0 * h);
      EXPECT_NEAR(du, b.force_n(x * sc), 1e-6 * b.force_n(0.0)) << x;
    }
  }
  PairCoefficients dry = c;
  dry.part_values[liquid_bridge::kSurfaceTensionSlot] = 0.0;
  EXPECT_FALSE(part.holds(dry, kR, -1e-15));
  EXPECT_EQ(part.max_separation_m(dry, kR), 0.0);
}

TEST(LiquidBridge, ZeroSurfaceTensionLeavesTheDryContactUntouched) {
  ContactKinematics k;
  k.normal = {0, 0, 1};
  k.overlap_m = 2e-6;
  k.radius_eff_m = 0.5 * kR;
  k.mass_eff_kg = 1e-6;
  k.normal_speed_m_s = -0.1;
  PairCoefficients c = wet_pair();
  c.damping_beta = 0.2;
  c.part_values[liquid_bridge::kSurfaceTensionSlot] = 0.0;
  ContactHistory h;
  ContactForce dry, wet_force;
  HertzNormal{}.apply(k, c, h, dry);
  HertzNormal{}.apply(k, c, h, wet_force);
  LiquidBridge{}.apply(k, c, h, wet_force);
  EXPECT_EQ(wet_force.normal_force_n, dry.normal_force_n);
  EXPECT_EQ(wet_force.elastic_energy_j, dry.elastic_energy_j);
}

TEST(LiquidBridge, DeclaresItsParametersAndIsRegistered) {
  const auto names = known_part_names("adhesion");
  EXPECT_NE(std::find(names.begin(), names.end(), "liquid_bridge"), names.end());
  int found = 0;
  for (const RegisteredPartParameter& r : registered_part_parameters())
    if (r.part == "liquid_bridge") {
      ++found;
      EXPECT_EQ(r.role, "adhesion");
      EXPECT_FALSE(r.parameter.written_when_absent) << r.parameter.key;
    }
  EXPECT_EQ(found, 3);
  // A value out of its declared range is refused by name.
  InteractionParameters p = wet();
  p.part_values[liquid_bridge::kContactAngleSlot] = 95.0;
  try {
    p.validate("pp: ");
    ADD_FAILURE() << "a 95 deg contact angle was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("contact_angle_deg"), std::string::npos) << e.what();
  }
}

struct Pull {
  int steps_checked = 0;
  double worst_relative_error = 0.0;
  double break_gap_m = -1.0;  // the last gap with the contact on
  bool force_while_apart = false;
};

// Grain(s) touching, pulled apart along the axis at an imposed speed past the
// rupture, then pushed back to touching.
Pull pull_apart(bool against_wall) {
  const double r_d = derjaguin_radius(against_wall);
  const double speed = 0.02;  // m/s: ~1000 steps across the bridge's range
  auto o = testing::options_in_box({-0.01, -0.01, -0.01}, {0.01, 0.01, 0.01}, {0, 0, 0});
  o.contact.adhesion = "liquid_bridge";
  o.contact.rolling = "none";
  auto s = testing::make_scene(o, wet());
  Simulation& sim = *s.sim;
  std::size_t moving = 0;
  Vec3 axis;
  const double start_overlap = 1e-8;
  if (against_wall) {
    sim.add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), s.material);
    moving = sim.add_particle({0, 0, kR - start_overlap}, kR, s.material);
    axis = {0, 0, 1};
  } else {
    sim.add_particle({0, 0, 0}, kR, s.material);
    moving = sim.add_particle({2.0 * kR - start_overlap, 0, 0}, kR, s.material);
    axis = {1, 0, 0};
  }
  for (std::size_t i = 0; i < sim.particles().size(); ++i) {
    Particles& p = sim.mutable_particles();
    p.inv_mass_kg[i] = 0.0;
    p.inv_inertia_kg_m2[i] = 0.0;
    p.velocity_m_s[i] = i == moving ? speed * axis : Vec3{};
  }
  auto gap = [&] {
    const Particles& p = sim.particles();
    return against_wall ? p.position_m[moving].z - kR
                        : p.position_m[moving].x - p.position_m[0].x - 2.0 * kR;
  };
  const double sc = rupture_gap(r_d);
  Pull out;
  sim.step();
  while (gap() < 1.5 * sc) {
    sim.step();
    if (sim.contact_count() > 0) {
      out.break_gap_m = gap();
      if (gap() > 0.0) {
        const double tension = -dot(sim.particles().force_n[moving], axis);
        const double expected = willett_force(gap(), r_d);
        out.worst_relative_error =
            std::max(out.worst_relative_error, std::abs(tension - expected) / expected);
        ++out.steps_checked;
      }
    }
  }
  EXPECT_EQ(sim.contact_count(), 0u) << "still held at 1.5 rupture distances";
  sim.mutable_particles().velocity_m_s[moving] = -speed * axis;
  while (gap() > 1e-7) {
    sim.step();
    if (gap() > 1e-7 && (sim.contact_count() > 0 || norm(sim.particles().force_n[moving]) > 0.0))
      out.force_while_apart = true;
  }
  return out;
}

void check_pull(bool against_wall) {
  const double sc = rupture_gap(derjaguin_radius(against_wall));
  const Pull p = pull_apart(against_wall);
  std::cout << std::setprecision(7) << (against_wall ? "sphere-wall" : "sphere-sphere") << ": "
            << p.steps_checked << " steps with a bridge, worst relative force error "
            << p.worst_relative_error << ", ruptured at " << p.break_gap_m / sc << " S_c\n";
  EXPECT_GT(p.steps_checked, 100);
  // The force is evaluated at the gap of the step's start; the positions the
  // test reads are the same ones, so only rounding separates them.
  EXPECT_LT(p.worst_relative_error, 1e-6);
  // Ruptured within one step's travel (speed dt ~ 1e-8 m here) of S_c.
  EXPECT_NEAR(p.break_gap_m, sc, 0.01 * sc);
  EXPECT_LT(p.break_gap_m, sc);
  EXPECT_FALSE(p.force_while_apart) << "a bridge formed before the surfaces touched again";
}

TEST(LiquidBridge, TwoGrainsPulledApartFeelWillettsForceUntilLiansRupture) { check_pull(false); }

TEST(LiquidBridge, AGrainPulledOffAPlaneWallFeelsTheSpherePlaneBridge) { check_pull(true); }

}  // namespace
}  // namespace demcal::dem
