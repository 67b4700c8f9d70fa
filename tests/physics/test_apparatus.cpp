// The laboratory tests on real (small) DEM runs: they end by themselves, their
// observables are measured, and the angle of repose follows friction.
#include "dem/apparatus/rectangular_container.hpp"
#include "dem/apparatus/sandglass.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

namespace demcal::dem {
namespace {

GranularMaterial quartz_sand(double mu_s, double mu_r) {
  GranularMaterial m;
  m.particle = Material{"quartz", 2650.0, 0.0, 1e7, 0.25};
  m.wall = Material{"glass", 2500.0, 6e10, 0.0, 0.25};
  m.particle_particle.restitution = 0.6;
  m.particle_particle.sliding_friction = mu_s;
  m.particle_particle.rolling_friction = mu_r;
  m.particle_wall = m.particle_particle;
  m.contact.rolling = "cdt";
  m.sizes = std::shared_ptr<const SizeDistribution>(make_uniform(3e-4, 6e-4));
  return m;
}

double container_angle(double mu_s, double mu_r) {
  RectangularContainerOptions o;
  o.width_m = 0.12;
  o.height_m = 0.05;
  o.thickness_diameters = 4.0;
  o.boundary = "periodic";
  o.fill_mass_kg = 0.004;
  o.reduction.coarse_graining_factor = 2.5;
  RectangularContainer c(o, quartz_sand(mu_s, mu_r), RunProtocol{});
  const ApparatusResult r = c.run(nullptr);
  EXPECT_TRUE(r.details["pile_settled"].get<bool>());
  if (!r.observables["angle_of_repose_deg"].is_number()) {
    ADD_FAILURE() << r.details.dump();
    return 0.0;
  }
  const double angle = r.observables["angle_of_repose_deg"].get<double>();
  std::cout << "container mu_s " << mu_s << " mu_r " << mu_r << ": AoR " << angle << " +- "
            << r.observables["angle_of_repose_uncertainty_deg"].get<double>() << " deg, "
            << r.details["particles"] << " particles\n";
  return angle;
}

TEST(RectangularContainer, AngleOfReposeRisesWithFriction) {
  const double low = container_angle(0.3, 0.05);
  const double high = container_angle(0.52, 0.3);
  EXPECT_GT(low, 5.0);
  EXPECT_GT(high, low + 5.0);
}

TEST(Sandglass, QuickSliceDischargesAndMeasuresEveryObservable) {
  SandglassOptions o;
  o.upper_diameter_m = 0.04;
  o.fill_mass_kg = 0.02;
  o.reduction.slice = true;
  o.reduction.coarse_graining_factor = 2.5;
  const GranularMaterial sand = quartz_sand(0.52, 0.3);
  Sandglass s(o, sand, RunProtocol{});
  const ApparatusResult r = s.run(nullptr);
  std::cout << r.observables.dump() << "\n";
  const auto& obs = r.observables;
  ASSERT_TRUE(obs["discharge_time_s"].is_number()) << r.details["discharge"].dump();
  EXPECT_GT(obs["discharge_time_s"].get<double>(), 0.05);
  EXPECT_GT(obs["mass_flow_rate_kg_s"].get<double>(), 0.0);
  // Random loose packings of spheres: solid fraction 0.5-0.65.
  const double rho = obs["bulk_density_kg_m3"].get<double>();
  EXPECT_GT(rho, 0.45 * 2650.0);
  EXPECT_LT(rho, 0.66 * 2650.0);
  ASSERT_TRUE(obs["angle_of_repose_deg"].is_number()) << r.details.dump();
  EXPECT_GT(obs["angle_of_repose_deg"].get<double>(), 10.0);
  EXPECT_LT(obs["angle_of_repose_deg"].get<double>(), 50.0);
  // m(t) never decreases and ends at the fill.
  const auto& m = r.series["discharged_mass"]["mass_kg"];
  for (std::size_t k = 1; k < m.size(); ++k) EXPECT_GE(m[k].get<double>(), m[k - 1].get<double>());
  EXPECT_NEAR(m.back().get<double>(), r.details["discharge"]["total_mass_kg"].get<double>(), 1e-12);
}

TEST(Sandglass, RefusesAFillTheChamberCannotHoldBeforeRunning) {
  SandglassOptions o;
  o.fill_mass_kg = 5.0;
  try {
    Sandglass s(o, quartz_sand(0.5, 0.1), RunProtocol{});
    FAIL() << "expected a refusal";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cannot hold the fill"), std::string::npos) << e.what();
  }
  o.fill_mass_kg = 0.05;
  o.orifice_diameter_m = 0.0008;  // below three (coarse-grained) diameters
  o.reduction.coarse_graining_factor = 2.5;
  EXPECT_THROW(Sandglass(o, quartz_sand(0.5, 0.1), RunProtocol{}), std::invalid_argument);
}

}  // namespace
}  // namespace demcal::dem
