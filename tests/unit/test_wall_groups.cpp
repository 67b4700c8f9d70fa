// Walls of an apparatus may touch the grains with different interactions: a
// group named in GranularMaterial::particle_wall_by_group gets a wall material
// of its own with that interaction, every other wall keeps particle_wall, and
// a material without groups installs exactly what it always did.
#include "config/study_config.hpp"
#include "config/toml_reader.hpp"
#include "dem/apparatus/conical_pile.hpp"
#include "dem/apparatus/granular_material.hpp"
#include "dem/apparatus/rectangular_container.hpp"
#include "dem/apparatus/sandglass.hpp"
#include "dem/simulation.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace demcal::dem {
namespace {

GranularMaterial sand() {
  GranularMaterial m;
  m.particle.name = "sand";
  m.particle.density_kg_m3 = 2650.0;
  m.particle.shear_modulus_pa = 1e6;
  m.particle.poisson_ratio = 0.25;
  m.wall.name = "glass";
  m.wall.density_kg_m3 = 2500.0;
  m.wall.youngs_modulus_pa = 6.3e10;
  m.wall.poisson_ratio = 0.23;
  m.particle_particle.restitution = 0.6;
  m.particle_particle.sliding_friction = 0.52;
  m.particle_wall = m.particle_particle;
  m.particle_wall.sliding_friction = 0.52;  // lined: the sand itself
  m.sizes = make_uniform(3e-3, 6e-3);
  return m;
}

RectangularContainerOptions small_container(const std::string& boundary) {
  RectangularContainerOptions o;
  o.width_m = 0.16;
  o.height_m = 0.06;
  o.thickness_diameters = 4.0;
  o.boundary = boundary;
  o.fill_mass_kg = 0.05;
  return o;
}

// The sliding friction the grains feel against wall `index`.
double wall_friction(const Simulation& sim, std::size_t index) {
  const InteractionParameters* p = sim.interaction(0, sim.wall_material(index));
  EXPECT_NE(p, nullptr);
  return p ? p->sliding_friction : -1.0;
}

TEST(WallGroups, EveryApparatusNamesItsGroups) {
  for (const auto& names : {Sandglass::wall_group_names(), RectangularContainer::wall_group_names(),
                            ConicalPile::wall_group_names()}) {
    EXPECT_FALSE(names.empty());
    EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  }
}

TEST(WallGroups, WithoutGroupsEveryWallSharesOneMaterial) {
  const RectangularContainer c(small_container("walls"), sand(), RunProtocol{});
  const Simulation& sim = c.simulation();
  ASSERT_EQ(sim.materials().size(), 2u);  // what a material without groups always installed
  for (std::size_t i = 0; i < sim.walls().size(); ++i) {
    EXPECT_EQ(sim.wall_material(i), 1);
    EXPECT_DOUBLE_EQ(wall_friction(sim, i), 0.52);
  }
}

TEST(WallGroups, ABareFloorUnderLinedWalls) {
  GranularMaterial m = sand();
  InteractionParameters bare = m.particle_wall;
  bare.sliding_friction = 0.3;
  bare.rolling_friction = 0.05;
  m.particle_wall_by_group["floor"] = bare;
  m.particle_wall_by_group["no_such_group"] = bare;  // groups an apparatus lacks are not used by it
  const RectangularContainer c(small_container("walls"), m, RunProtocol{});
  const Simulation& sim = c.simulation();
  ASSERT_EQ(sim.materials().size(), 3u);
  ASSERT_EQ(sim.walls().size(),
            5u);  // floor, two end walls, two side walls: the order they are added in
  EXPECT_DOUBLE_EQ(wall_friction(sim, 0), 0.3);
  EXPECT_DOUBLE_EQ(sim.interaction(0, sim.wall_material(0))->rolling_friction, 0.05);
  for (std::size_t i = 1; i < 5; ++i) EXPECT_DOUBLE_EQ(wall_friction(sim, i), 0.52) << "wall " << i;
  // The floor's material is the wall material under another name.
  EXPECT_EQ(sim.materials()[static_cast<std::size_t>(sim.wall_material(0))].youngs_modulus_pa,
            6.3e10);
}

TEST(WallGroups, TheSandglassHopperLinedAndItsFloorBare) {
  GranularMaterial m = sand();
  InteractionParameters bare = m.particle_wall;
  bare.sliding_friction = 0.25;
  m.particle_wall_by_group["floor"] = bare;
  SandglassOptions o;
  o.reduction.slice = true;
  o.fill_mass_kg = 0.05;
  m.sizes = make_uniform(
      3e-4, 6e-4);  // the paper's sand; the test builds the apparatus, it does not run it
  const Sandglass s(o, m, RunProtocol{});
  const Simulation& sim = s.simulation();
  // The floor is the first wall the sandglass adds; the rest are lined.
  EXPECT_DOUBLE_EQ(wall_friction(sim, 0), 0.25);
  for (std::size_t i = 1; i < sim.walls().size(); ++i)
    EXPECT_DOUBLE_EQ(wall_friction(sim, i), 0.52) << "wall " << i;
}

// The study config: [interaction.particle_wall.<group>] gives a group its own
// values over particle_wall's, key by key.
TEST(WallGroups, AStudyConfigGivesTheFloorItsOwnFriction) {
  std::ifstream in(std::string(DEMCAL_SOURCE_DIR) + "/tests/bad_input/base/study.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  const std::size_t at = toml.find("[protocol]");
  ASSERT_NE(at, std::string::npos);
  toml.insert(at, "[interaction.particle_wall.floor]\nsliding_friction = 0.21\n\n");
  const config::StudyConfig study =
      config::build_study(config::parse_config_string(toml, "study.toml"));
  ASSERT_EQ(study.apparatus.size(), 1u);
  const Simulation& sim = study.apparatus[0].apparatus->simulation();
  const InteractionParameters* floor = sim.interaction(0, sim.wall_material(0));
  const InteractionParameters* hopper =
      sim.interaction(0, sim.wall_material(sim.walls().size() - 1));
  ASSERT_NE(floor, nullptr);
  ASSERT_NE(hopper, nullptr);
  EXPECT_DOUBLE_EQ(floor->sliding_friction, 0.21);
  EXPECT_NE(hopper->sliding_friction, 0.21);
  // Keys the group does not give are particle_wall's.
  EXPECT_DOUBLE_EQ(floor->restitution, hopper->restitution);
  EXPECT_DOUBLE_EQ(floor->rolling_friction, hopper->rolling_friction);
}

}  // namespace
}  // namespace demcal::dem
