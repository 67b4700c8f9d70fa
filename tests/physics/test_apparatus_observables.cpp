// Every apparatus writes only observables the registry (io/observable_registry.hpp)
// declares measured by its kind, and measures what the registry says it does: on
// small real DEM runs (coarse-grained slices, a few seconds each).
#include "dem/apparatus/conical_pile.hpp"
#include "dem/apparatus/rectangular_container.hpp"
#include "dem/apparatus/sandglass.hpp"
#include "io/observable_registry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace demcal::dem {
namespace {

GranularMaterial sand() {
  GranularMaterial m;
  m.particle = Material{"quartz", 2650.0, 0.0, 1e7, 0.25};
  m.wall = Material{"glass", 2500.0, 6e10, 0.0, 0.25};
  m.particle_particle.restitution = 0.6;
  m.particle_particle.sliding_friction = 0.5;
  m.particle_particle.rolling_friction = 0.2;
  m.particle_wall = m.particle_particle;
  m.contact.rolling = "cdt";
  m.sizes = std::shared_ptr<const SizeDistribution>(make_uniform(3e-4, 6e-4));
  return m;
}

// The stable observables the run gave a number for, and those the registry says
// the kind measures.
std::vector<std::string> measured(const ApparatusResult& r) {
  std::vector<std::string> names;
  for (const auto& o : io::observable_registry())
    if (o.kind == io::ObservableKind::stable && r.observables.contains(std::string(o.name)) &&
        r.observables[std::string(o.name)].is_number())
      names.emplace_back(o.name);
  return names;
}
std::vector<std::string> declared(const std::string& kind) {
  std::vector<std::string> names;
  for (const auto& o : io::observable_registry())
    if (o.kind == io::ObservableKind::stable && io::measures(kind, o.name))
      names.emplace_back(o.name);
  return names;
}

void check(Apparatus& a, const std::vector<std::string>& not_yet_computed) {
  const ApparatusResult r = a.run(nullptr);
  EXPECT_EQ(protocol::observables_not_measured_by(a.name(), r.observables),
            std::vector<std::string>{})
      << r.observables.dump();
  std::vector<std::string> expected;
  for (const auto& name : declared(a.name()))
    if (std::find(not_yet_computed.begin(), not_yet_computed.end(), name) == not_yet_computed.end())
      expected.push_back(name);
  EXPECT_EQ(measured(r), expected) << r.observables.dump() << "\n" << r.details.dump();
}

// The registry declares bulk_density_kg_m3 measured by every kind (a heap's bulk density
// is a laboratory measurement, the analytic evaluator gives it); the DEM's pile and
// container do not compute it yet (io/observable_registry.cpp).
const std::vector<std::string> kPileGap = {"bulk_density_kg_m3"};

TEST(ApparatusObservables, RectangularContainer) {
  RectangularContainerOptions o;
  o.width_m = 0.12;
  o.height_m = 0.05;
  o.thickness_diameters = 4.0;
  o.boundary = "periodic";
  o.fill_mass_kg = 0.002;
  o.reduction.coarse_graining_factor = 2.5;
  RectangularContainer c(o, sand(), RunProtocol{});
  check(c, kPileGap);
}

TEST(ApparatusObservables, ConicalPile) {
  ConicalPileOptions o;
  o.funnel_top_diameter_m = 0.06;
  o.funnel_outlet_diameter_m = 0.012;
  o.feed_height_m = 0.08;
  o.drop_height_m = 0.04;
  o.base_diameter_m = 0.04;
  o.fill_mass_kg = 0.006;
  o.reduction.slice = true;
  o.reduction.coarse_graining_factor = 2.0;
  ConicalPile p(o, sand(), RunProtocol{});
  check(p, kPileGap);
}

// The pile must give an angle whatever the seed (a change of the engine's rounding acts as a
// new one): 0.01 kg left a heap of 6.6-11.4 deg over seeds 1-8, a crest of a few grains, and
// none at all with a one-ulp change of the contact normal (2026-12-05); 0.02 kg gives
// 16.9-21.0 deg.
TEST(ApparatusObservables, Sandglass) {
  SandglassOptions o;
  o.upper_diameter_m = 0.04;
  o.fill_mass_kg = 0.02;
  o.reduction.slice = true;
  o.reduction.coarse_graining_factor = 2.5;
  Sandglass s(o, sand(), RunProtocol{});
  check(s, {});
}

}  // namespace
}  // namespace demcal::dem
