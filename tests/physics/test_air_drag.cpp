// Air drag (AirDrag, Schiller–Naumann) against its force balance: a sphere
// falling from rest through still air reaches the terminal velocity v_t where
//   m g = 3 pi mu d v_t (1 + 0.15 Re^0.687),  Re = rho_air v_t d / mu
// (solved here by bisection), in the Stokes regime (d = 20 um, Re ~ 0.04) and
// for a 450 um quartz grain (Re ~ 100); with drag_scale s the balance is
// m g = s F_SN(v_t), and s = 0 is free fall; the force opposes the motion and
// vanishes at rest; a coarse-grained parcel falls at its grains' terminal velocity.
#include "physics_fixtures.hpp"

#include "dem/air_drag.hpp"
#include "dem/apparatus/granular_material.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace demcal::dem {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.81;
constexpr double kQuartz = 2650.0;

// The terminal velocity of the balance above (times air.drag_scale), by bisection in v.
double terminal_velocity(double diameter_m, const AirProperties& air) {
  const double weight = kQuartz * kPi / 6.0 * diameter_m * diameter_m * diameter_m * kG;
  auto drag = [&](double v) {
    const double re = air.density_kg_m3 * v * diameter_m / air.dynamic_viscosity_pa_s;
    const double factor = re < 1000.0 ? 1.0 + 0.15 * std::pow(re, 0.687) : 0.44 * re / 24.0;
    return air.drag_scale * 3.0 * kPi * air.dynamic_viscosity_pa_s * diameter_m * v * factor;
  };
  double lo = 0.0, hi = 100.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (drag(mid) < weight ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// A sphere dropped from rest in a periodic column (nothing to hit), run for
// ten times the time it needs to reach v_t at g; returns its final speed.
double fall(double diameter_m, double coarse_graining_factor = 1.0,
            const AirProperties& air = AirProperties{}) {
  const double v_t = terminal_velocity(diameter_m / coarse_graining_factor, air);
  const double length = 20.0 * diameter_m;
  auto o =
      testing::options_in_box({-length, -length, -length}, {length, length, length}, {0, 0, -kG});
  o.domain.periodic = {false, false, true};
  // The drag relaxes v over ~v_t / g; 2000 steps over it resolve the approach.
  o.time_step_s = v_t / kG / 2000.0;
  auto s = testing::make_scene(o, testing::interaction(0.5, 0.5));
  s.sim->add_body_force(std::make_unique<AirDrag>(air, coarse_graining_factor));
  s.sim->add_particle({0, 0, 0}, 0.5 * diameter_m, s.material);
  s.sim->run_until(10.0 * v_t / kG);
  return -s.sim->particles().velocity_m_s[0].z;
}

TEST(AirDrag, TerminalVelocityInTheStokesRegime) {
  const double d = 20e-6;
  const AirProperties air;
  const double expected = terminal_velocity(d, air);
  const double stokes = kQuartz * kG * d * d / (18.0 * air.dynamic_viscosity_pa_s);
  const double v = fall(d);
  const double re = air.density_kg_m3 * v * d / air.dynamic_viscosity_pa_s;
  std::cout << "d = 20 um: v_t = " << v << " m/s, Schiller-Naumann " << expected << " m/s (error "
            << 100.0 * (v / expected - 1.0) << " %), Stokes " << stokes << " m/s, Re = " << re
            << "\n";
  EXPECT_NEAR(v, expected, 0.01 * expected);
  EXPECT_LT(re, 0.1);
}

TEST(AirDrag, TerminalVelocityOfA450MicronQuartzGrain) {
  const double d = 450e-6;
  const AirProperties air;
  const double expected = terminal_velocity(d, air);
  const double v = fall(d);
  std::cout << "d = 450 um: v_t = " << v << " m/s, Schiller-Naumann " << expected << " m/s (error "
            << 100.0 * (v / expected - 1.0)
            << " %), Re = " << air.density_kg_m3 * v * d / air.dynamic_viscosity_pa_s << "\n";
  EXPECT_NEAR(v, expected, 0.01 * expected);
}

TEST(AirDrag, ACoarseGrainedParcelFallsAtItsGrainsTerminalVelocity) {
  // A parcel of 4 x 450 um stands for 64 grains of 450 um, and falls like one of them.
  const double f = 4.0;
  const double grain = terminal_velocity(450e-6, AirProperties{});
  const double v = fall(f * 450e-6, f);
  std::cout << "parcel f = 4: v_t = " << v << " m/s, the grain's " << grain << " m/s, a 1.8 mm "
            << "grain's " << terminal_velocity(f * 450e-6, AirProperties{}) << " m/s\n";
  EXPECT_NEAR(v, grain, 0.01 * grain);
}

TEST(AirDrag, AScaledDragReachesTheScaledBalance) {
  // The whole force scales, Re-dependent part included: at Re ~ 70-160 the
  // terminal velocity is not that of a rescaled Stokes law.
  const double d = 450e-6;
  for (const double scale : {0.5, 2.0}) {
    SCOPED_TRACE(scale);
    AirProperties air;
    air.drag_scale = scale;
    const double expected = terminal_velocity(d, air);
    const double v = fall(d, 1.0, air);
    std::cout << "d = 450 um, drag_scale " << scale << ": v_t = " << v << " m/s, balance "
              << expected << " m/s (error " << 100.0 * (v / expected - 1.0) << " %)\n";
    EXPECT_NEAR(v, expected, 0.01 * expected);
  }
}

TEST(AirDrag, ZeroScaleIsFreeFall) {
  AirProperties air;
  air.drag_scale = 0.0;
  const double d = 450e-6, length = 20.0 * d;
  auto o =
      testing::options_in_box({-length, -length, -length}, {length, length, length}, {0, 0, -kG});
  o.domain.periodic = {false, false, true};
  o.time_step_s = 1e-5;
  auto s = testing::make_scene(o, testing::interaction(0.5, 0.5));
  s.sim->add_body_force(std::make_unique<AirDrag>(air));
  s.sim->add_particle({0, 0, 0}, 0.5 * d, s.material);
  s.sim->run_until(0.1);
  const double t = s.sim->time_s();
  EXPECT_NEAR(-s.sim->particles().velocity_m_s[0].z, kG * t, 1e-9 * kG * t);
  // Its force is exactly nothing, even in motion.
  Particles p;
  p.add({0, 0, 0}, 2e-4, kQuartz, 0, 0, {0.3, -0.4, 1.2});
  std::vector<Vec3> force(1), torque(1);
  AirDrag(air).add(p, 0, 1, force, torque);
  EXPECT_EQ(norm(force[0]), 0.0);
}

TEST(AirDrag, ScaleOneIsTheUnscaledDragBitForBit) {
  Particles p;
  p.add({0, 0, 0}, 2e-4, kQuartz, 0, 0, {0.3, -0.4, 1.2});
  std::vector<Vec3> force(1), torque(1);
  const double f = 3.0;
  AirDrag(AirProperties{}, f).add(p, 0, 1, force, torque);
  const Vec3 unscaled = f * f * f * sphere_drag_force_n(AirProperties{}, 2.0 * 2e-4 / f, p.velocity_m_s[0]);
  EXPECT_EQ(force[0].x, unscaled.x);
  EXPECT_EQ(force[0].y, unscaled.y);
  EXPECT_EQ(force[0].z, unscaled.z);
}

TEST(AirDrag, ANegativeOrNonFiniteScaleIsRefused) {
  for (const double scale : {-1.0, std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::quiet_NaN()}) {
    AirProperties air;
    air.drag_scale = scale;
    EXPECT_THROW(air.validate(), std::invalid_argument) << scale;
    EXPECT_THROW((void)AirDrag{air}, std::invalid_argument) << scale;
  }
}

TEST(AirDrag, OpposesTheMotionAndVanishesAtRest) {
  Particles p;
  p.add({0, 0, 0}, 2e-4, kQuartz, 0, 0, {0.3, -0.4, 1.2});
  p.add({0, 0, 0}, 2e-4, kQuartz, 0, 1, {0, 0, 0});
  std::vector<Vec3> force(2), torque(2);
  const AirDrag drag(AirProperties{});
  drag.add(p, 0, 2, force, torque);
  const Vec3 v = p.velocity_m_s[0];
  EXPECT_LT(dot(force[0], v), 0.0);
  EXPECT_NEAR(norm(cross(force[0], v)), 0.0, 1e-12 * norm(force[0]) * norm(v));
  EXPECT_EQ(norm(force[1]), 0.0);
  EXPECT_EQ(norm(torque[0]) + norm(torque[1]), 0.0);
  // Stokes at vanishing speed: -3 pi mu d v.
  const Vec3 slow{1e-9, 0, 0};
  const Vec3 f = sphere_drag_force_n(AirProperties{}, 4e-4, slow);
  EXPECT_NEAR(f.x, -3.0 * kPi * 1.8e-5 * 4e-4 * 1e-9, 1e-6 * 3.0 * kPi * 1.8e-5 * 4e-4 * 1e-9);
}

TEST(AirDrag, ApparatusMaterialsGetTheParcelDrag) {
  // install_materials (every apparatus goes through it) adds the drag with the
  // reduction's coarse-graining factor.
  GranularMaterial m;
  m.particle = testing::sand();
  m.wall = testing::sand();
  m.wall.name = "wall";
  m.air_drag = AirProperties{};
  ModelReduction r;
  r.coarse_graining_factor = 3.0;
  Simulation sim(testing::options_in_box({-1, -1, -1}, {1, 1, 1}, {0, 0, -kG}));
  install_materials(sim, m, r);
  const std::size_t i = sim.add_particle({0, 0, 0}, 3.0 * 225e-6, 0, {0, 0, -1.0});
  sim.time_step_s();  // prepares: the forces of the initial state
  // Acceleration = -g + the grain's drag per unit mass at 1 m/s.
  const Particles& p = sim.particles();
  const double grain_mass = kQuartz * kPi / 6.0 * std::pow(450e-6, 3);
  const double expected =
      -kG + sphere_drag_force_n(AirProperties{}, 450e-6, p.velocity_m_s[i]).z / grain_mass;
  EXPECT_NEAR(p.force_n[i].z / p.mass_kg[i], expected, 1e-9 * kG);
}

}  // namespace
}  // namespace demcal::dem
