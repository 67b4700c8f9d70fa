// A fill of more grains than protocol.max_particles is refused before the
// apparatus is built, with the estimate and what to change; a fill the
// chamber cannot hold is still named as such; a chamber far larger than its
// fill is checked in time proportional to the fill (the fuzzer's timeout: a
// 0.15 kg fill of 0.4 mm sand in an 8 x 15 cm chamber used to list 6e6 sites).
#include "dem/apparatus/sandglass.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace demcal::dem {
namespace {

GranularMaterial fine_sand() {
  GranularMaterial m;
  m.particle.name = "sand";
  m.particle.density_kg_m3 = 2650.0;
  m.particle.shear_modulus_pa = 1e7;
  m.particle.poisson_ratio = 0.25;
  m.wall.name = "glass";
  m.wall.density_kg_m3 = 2500.0;
  m.wall.youngs_modulus_pa = 6.3e10;
  m.wall.poisson_ratio = 0.23;
  m.particle_particle.restitution = 0.6;
  m.particle_particle.sliding_friction = 0.5;
  m.particle_wall = m.particle_particle;
  m.sizes = make_uniform(3e-4, 5e-4);
  return m;
}

SandglassOptions big_full_sandglass() {
  SandglassOptions o;
  o.upper_diameter_m = 0.08;
  o.upper_height_m = 0.15;
  o.orifice_diameter_m = 0.022;
  o.fill_mass_kg = 0.15;
  o.lower_diameter_m = 0.15;
  o.drop_height_m = 0.10;
  return o;
}

std::string refusal(const SandglassOptions& o, const RunProtocol& p) {
  try {
    Sandglass s(o, fine_sand(), p);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ParticleCap, AFillOfTooManyGrainsIsRefusedWithTheEstimate) {
  const std::string what = refusal(big_full_sandglass(), RunProtocol{});
  EXPECT_NE(what.find("grains of"), std::string::npos) << what;
  EXPECT_NE(what.find("protocol.max_particles = 1e+06"), std::string::npos) << what;
  EXPECT_NE(what.find("coarse_graining_factor"), std::string::npos) << what;
}

TEST(ParticleCap, TheCapIsTheUsersToRaise) {
  SandglassOptions o = big_full_sandglass();
  o.reduction.coarse_graining_factor = 3.0;  // ~6e4 grains: under the default cap
  EXPECT_EQ(refusal(o, RunProtocol{}), "");
  RunProtocol strict;
  strict.max_particles = 1000;
  EXPECT_NE(refusal(o, strict).find("more than protocol.max_particles = 1e+03"), std::string::npos);
}

TEST(ParticleCap, AChamberTooSmallIsStillNamedAsSuch) {
  SandglassOptions o = big_full_sandglass();
  o.reduction.coarse_graining_factor = 3.0;
  o.upper_height_m = 0.02;
  const std::string what = refusal(o, RunProtocol{});
  EXPECT_NE(what.find("cannot hold the fill"), std::string::npos) << what;
}

}  // namespace
}  // namespace demcal::dem
