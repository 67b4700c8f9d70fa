// Insertion never creates overlaps, reaches its amount, and says so when it cannot.
#include "dem/insertion/inserter.hpp"
#include "dem/simulation.hpp"
#include "dem/wall/cylinder_wall.hpp"
#include "dem/wall/plane_wall.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace demcal::dem {
namespace {

std::unique_ptr<Simulation> container(bool periodic_y = false) {
  SimulationOptions o;
  o.domain.lower_m = {-0.02, -0.02, -0.001};
  o.domain.upper_m = {0.02, 0.02, 0.08};
  o.domain.periodic = {false, periodic_y, false};
  auto sim = std::make_unique<Simulation>(o);
  Material m;
  m.name = "sand";
  m.youngs_modulus_pa = 1e7;
  const int s = sim->add_material(m);
  InteractionParameters p;
  sim->set_interaction(s, s, p);
  sim->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), s);
  sim->add_wall(std::make_unique<CylinderWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, 0.08, 0.015), s);
  return sim;
}

double min_gap(const Simulation& sim) {
  const auto& p = sim.particles();
  double gap = 1e9;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j)
      gap = std::min(gap, norm(p.position_m[i] - p.position_m[j]) - p.radius_m[i] - p.radius_m[j]);
  return gap;
}

double max_radial(const Simulation& sim) {
  double r = 0.0;
  const auto& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    r = std::max(r, std::hypot(p.position_m[i].x, p.position_m[i].y) + p.radius_m[i]);
  return r;
}

TEST(FillInserter, RandomAndLatticeFillsHaveNoOverlapsAndStayInsideTheCylinder) {
  for (const char* method : {"random", "lattice"}) {
    auto sim = container();
    FillOptions f;
    f.amount.count = 800;
    f.method = method;
    sim->add_inserter(make_fill_inserter(make_cylinder_region({0, 0, 0.001}, 0.0149, 0.06),
                                         make_uniform(0.8e-3, 1.6e-3), f));
    sim->time_step_s();  // inserts at t = 0
    EXPECT_EQ(sim->particles().size(), 800u) << method;
    EXPECT_GE(min_gap(*sim), 0.0) << method;
    EXPECT_LE(max_radial(*sim), 0.015) << method;
  }
}

TEST(FillInserter, FillsToATargetMass) {
  auto sim = container();
  FillOptions f;
  f.amount.mass_kg = 2e-3;
  sim->add_inserter(make_fill_inserter(make_cylinder_region({0, 0, 0.001}, 0.0149, 0.06),
                                       make_monodisperse(1e-3), f));
  sim->time_step_s();
  double mass = 0.0;
  for (double m : sim->particles().mass_kg) mass += m;
  EXPECT_GE(mass, 2e-3);
  EXPECT_LT(mass, 2e-3 + 2650.0 * 3.15 * 1e-9 / 6.0 * 1.01);  // at most one particle more
}

TEST(FillInserter, SaysWhenTheRegionCannotHoldTheAmount) {
  auto sim = container();
  FillOptions f;
  f.amount.count = 5000;
  sim->add_inserter(make_fill_inserter(make_box_region({-0.005, -0.005, 0.001}, {0.005, 0.005, 0.006}),
                                       make_monodisperse(1e-3), f));
  try {
    sim->time_step_s();
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot hold"), std::string::npos) << e.what();
  }
}

TEST(PourInserter, PoursItsCountWithoutOverlapsAtAnyInsertion) {
  auto sim = container(true);
  PourOptions p;
  p.amount.count = 300;
  p.velocity_m_s = {0, 0, -0.5};
  sim->add_inserter(make_pour_inserter(make_box_region({-0.01, -0.01, 0.05}, {0.01, 0.01, 0.06}),
                                       make_uniform(0.8e-3, 1.2e-3), p));
  std::size_t seen = 0;
  while (!sim->insertion_finished() && sim->time_s() < 1.0) {
    sim->step();
    if (sim->particles().size() != seen) {
      seen = sim->particles().size();
      // New particles may touch old ones only after they moved, never at birth.
      EXPECT_GE(min_gap(*sim), -1e-5);
    }
  }
  EXPECT_EQ(sim->particles().size(), 300u);
  EXPECT_TRUE(sim->insertion_finished());
}

TEST(PourInserter, SteadyRateInsertsOnSchedule) {
  auto sim = container();
  PourOptions p;
  p.amount.count = 100;
  p.rate_particles_per_s = 1000.0;
  sim->add_inserter(make_pour_inserter(make_box_region({-0.01, -0.01, 0.03}, {0.01, 0.01, 0.06}),
                                       make_monodisperse(1e-3), p));
  sim->run_until(0.0505);
  EXPECT_NEAR(static_cast<double>(sim->particles().size()), 51.0, 1.0);
}

}  // namespace
}  // namespace demcal::dem
