// Beverloo's law on real DEM discharges: the full (3D) sandglass with a flat
// bottom and a circular orifice at two orifice sizes (7 and 10 mean diameters),
// fitted exactly by W = C rho_bulk sqrt(g) (D0 - k d)^2.5. A free-flowing
// material (mu_s 0.3, mu_r 0.05): Beverloo's constants for spheres are
// C 0.55-0.65, k 1.4-1.5; the issue asks for C in 0.5-0.7 and k in 1-3. The
// shear modulus is 1e6 Pa so the test runs in seconds: the bed's overlaps stay
// below 1 % of a radius (bed pressure ~800 Pa), and the flow rate is set by
// the geometry and friction, not the stiffness. The full curve (four orifices,
// the paper's material) is studies/beverloo.
#include "dem/apparatus/sandglass.hpp"
#include "dem/measure/beverloo.hpp"

#include <gtest/gtest.h>

#include <iostream>

namespace demcal::dem {
namespace {

struct FlowRate {
  double rate_kg_s = 0.0;
  double r_squared = 0.0;
  double bulk_density_kg_m3 = 0.0;
  double diameter_m = 0.0;
};

FlowRate flow_rate(double orifice_diameters) {
  GranularMaterial m;
  m.particle = Material{"quartz", 2650.0, 0.0, 1e6, 0.25};
  m.wall = Material{"steel", 7800.0, 0.0, 1e6, 0.3};
  m.particle_particle.restitution = 0.6;
  m.particle_particle.sliding_friction = 0.3;
  m.particle_particle.rolling_friction = 0.05;
  m.particle_wall = m.particle_particle;
  m.contact.rolling = "cdt";
  m.sizes = std::shared_ptr<const SizeDistribution>(make_uniform(3e-4, 6e-4));
  SandglassOptions o;
  o.reduction.coarse_graining_factor = 6.0;  // mean diameter 2.80 mm
  const double d = 2.7965e-3;
  o.upper_diameter_m = 0.072;  // 26 d: 2.6 x the larger orifice
  o.upper_height_m = 0.2;
  o.bottom = "flat";
  o.orifice_diameter_m = orifice_diameters * d;
  o.fill_mass_kg = 0.3;  // a bed about 20 d deep once settled
  o.lower_diameter_m = 0.08;
  o.drop_height_m = 0.03;
  o.form_pile = false;
  RunProtocol p;
  p.max_settle_s = 0.4;
  p.max_flow_s = 0.25;  // the bed drops by at most a third meanwhile
  Sandglass s(o, m, p);
  const ApparatusResult r = s.run(nullptr);
  const auto& flow = r.details["discharge"];
  FlowRate f;
  f.rate_kg_s = r.observables["mass_flow_rate_kg_s"].get<double>();
  f.r_squared = flow["mass_flow_rate_r_squared"].get<double>();
  f.bulk_density_kg_m3 = r.observables["bulk_density_kg_m3"].get<double>();
  f.diameter_m = s.particle_diameter_m();
  std::cout << "orifice " << orifice_diameters << " d: " << 1e3 * f.rate_kg_s << " g/s (R^2 " << f.r_squared
            << "), bulk density " << f.bulk_density_kg_m3 << " kg/m3, " << r.details["particles"] << " grains\n";
  return f;
}

TEST(Beverloo, TwoOrificesGiveConstantsInTheLawsRange) {
  const FlowRate small = flow_rate(7.0), large = flow_rate(10.0);
  // Continuous flow: m(t) a straight line over the steady window.
  EXPECT_GT(small.r_squared, 0.98);
  EXPECT_GT(large.r_squared, 0.98);
  BeverlooSetup setup;
  setup.bulk_density_kg_m3 = 0.5 * (small.bulk_density_kg_m3 + large.bulk_density_kg_m3);
  setup.particle_diameter_m = small.diameter_m;
  const BeverlooFit fit = fit_beverloo(setup, {7.0 * 2.7965e-3, 10.0 * 2.7965e-3}, {small.rate_kg_s, large.rate_kg_s});
  std::cout << "Beverloo: C = " << fit.c << ", k = " << fit.k << "\n";
  EXPECT_GT(fit.c, 0.5);
  EXPECT_LT(fit.c, 0.7);
  EXPECT_GT(fit.k, 1.0);
  EXPECT_LT(fit.k, 3.0);
}

}  // namespace
}  // namespace demcal::dem
