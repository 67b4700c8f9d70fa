// Deck writers (engines/lammps_deck.hpp, engines/liggghts_deck.hpp) against
// golden files in tests/data/engines/ (DEMCAL_UPDATE_GOLDEN=1 rewrites them),
// the layouts' numbers against the demcal apparatus', and the refusals.
#include "engines/lammps_deck.hpp"
#include "engines/liggghts_deck.hpp"

#include "tests/support/engine_fixtures.hpp"
#include "tests/support/golden.hpp"

#include <gtest/gtest.h>
#include <sstream>
#include <string>
#include <vector>

namespace demcal::engines {
namespace {

using testing::expect_golden;
using testing::peer_material;

dem::PouredSlabPileOptions small_pile() {
  dem::PouredSlabPileOptions o;
  o.particles = 1500;
  o.box_length_m = 0.06;
  o.box_height_m = 0.04;
  return o;
}

dem::RectangularContainerOptions container() {
  dem::RectangularContainerOptions o;
  o.width_m = 0.1;
  o.height_m = 0.05;
  o.thickness_diameters = 6.0;
  o.boundary = "walls";
  o.fill_mass_kg = 0.005;
  return o;
}

std::string record_text(const Deck& d) { return d.record.dump(1) + "\n"; }

TEST(EnginesDecks, LammpsPouredSlabPileGolden) {
  const auto r = write_lammps_deck(small_pile());
  ASSERT_TRUE(r.ok()) << r.refusal;
  expect_golden(r.deck->script, "engines/lammps_poured_slab_pile.in");
  expect_golden(record_text(*r.deck), "engines/lammps_poured_slab_pile.record.json");
  EXPECT_TRUE(r.deck->mass_series_name.empty());
}

TEST(EnginesDecks, LammpsRectangularContainerGolden) {
  // A polydisperse coarse-grained material with a reduced modulus.
  auto m = peer_material();
  m.sizes = dem::make_uniform(0.8e-3, 1.2e-3);
  auto o = container();
  o.reduction.coarse_graining_factor = 1.5;
  o.reduction.shear_modulus_pa = 5e6;
  const auto r = write_lammps_deck(o, m, dem::RunProtocol{});
  ASSERT_TRUE(r.ok()) << r.refusal;
  expect_golden(r.deck->script, "engines/lammps_rectangular_container.in");
  EXPECT_NE(r.deck->script.find("diam poly 8"), std::string::npos);
  EXPECT_NE(r.deck->script.find("yplane 0 NULL"), std::string::npos);  // front wall
}

TEST(EnginesDecks, LammpsSandglassSliceGolden) {
  const auto r =
      write_lammps_deck(testing::small_sandglass_slice(4.0), peer_material(), dem::RunProtocol{});
  ASSERT_TRUE(r.ok()) << r.refusal;
  expect_golden(r.deck->script, "engines/lammps_sandglass_slice.in");
  EXPECT_EQ(r.deck->mass_series_name, "mass_series.txt");
  // The slice's share of the fill, as dem::Sandglass computes it: 0.01 kg x 4 mm / 24 mm.
  const double share = 0.01 * 4e-3 / 0.024;
  const double grain = 2650.0 * M_PI / 6.0 * 1e-9;
  EXPECT_EQ(r.deck->record["layout"]["particles"].get<std::size_t>(),
            static_cast<std::size_t>(std::llround(share / grain)));
}

TEST(EnginesDecks, LammpsConicalPileGolden) {
  dem::ConicalPileOptions o;
  o.funnel_top_diameter_m = 0.02;
  o.funnel_outlet_diameter_m = 0.006;
  o.feed_height_m = 0.02;
  o.drop_height_m = 0.02;
  o.base_diameter_m = 0.03;
  o.fill_mass_kg = 0.004;
  const auto r = write_lammps_deck(o, peer_material(), dem::RunProtocol{});
  ASSERT_TRUE(r.ok()) << r.refusal;
  expect_golden(r.deck->script, "engines/lammps_conical_pile.in");
  EXPECT_NE(r.deck->script.find("cone z 0 0 0.003 0.01"), std::string::npos);
  EXPECT_EQ(r.deck->record["measurement"]["kind"], "conical_angle_of_repose");
  // dem::ConicalPile's plate height: max(0.3 r_base, 10 d).
  EXPECT_DOUBLE_EQ(r.deck->record["measurement"]["base_height_m"].get<double>(), 0.01);
}

TEST(EnginesDecks, LiggghtsGoldens) {
  const auto pile = write_liggghts_deck(small_pile());
  ASSERT_TRUE(pile.ok()) << pile.refusal;
  expect_golden(pile.deck->script, "engines/liggghts_poured_slab_pile.in");
  EXPECT_TRUE(pile.deck->files.empty());

  const auto glass =
      write_liggghts_deck(testing::small_sandglass_slice(6.0), peer_material(), dem::RunProtocol{});
  ASSERT_TRUE(glass.ok()) << glass.refusal;
  expect_golden(glass.deck->script, "engines/liggghts_sandglass_slice.in");
  ASSERT_EQ(glass.deck->files.size(), 5u);  // two chamber walls, the shut plate, two plate halves
  for (const auto& [name, text] : glass.deck->files)
    expect_golden(text, "engines/liggghts_sandglass_slice_" + name);
}

// LIGGGHTS's fix wall/gran keeps an attractive normal force at the end of a
// wall impact unless its line ends with "limitForce on" (read only after the
// geometry). With it open, the rolling limit |F_n| mu_r R stays open too and a
// grain leaves the floor spinning up to 30 % slower than on demcal's wall
// (bench/logs/2026-12-07_lammps-pile-gap/impact/). Every wall, primitive or
// mesh, of every apparatus must carry it.
TEST(EnginesDecks, EveryLiggghtsWallKeepsTheNormalForceRepulsive) {
  auto walls_of = [](const std::string& script) {
    std::vector<std::string> lines;
    std::istringstream in(script);
    for (std::string line; std::getline(in, line);)
      if (line.find("wall/gran") != std::string::npos && line.rfind("fix", 0) == 0)
        lines.push_back(line);
    return lines;
  };
  const auto pile = write_liggghts_deck(small_pile());
  const auto glass =
      write_liggghts_deck(testing::small_sandglass_slice(6.0), peer_material(), dem::RunProtocol{});
  ASSERT_TRUE(pile.ok()) << pile.refusal;
  ASSERT_TRUE(glass.ok()) << glass.refusal;
  bool primitive = false, mesh = false;
  for (const auto* deck : {&*pile.deck, &*glass.deck}) {
    const auto lines = walls_of(deck->script);
    EXPECT_FALSE(lines.empty());
    for (const auto& line : lines) {
      primitive = primitive || line.find(" primitive ") != std::string::npos;
      mesh = mesh || line.find(" mesh n_meshes ") != std::string::npos;
      const std::string tail = " limitForce on";
      ASSERT_GE(line.size(), tail.size());
      EXPECT_EQ(line.substr(line.size() - tail.size()), tail) << line;
    }
  }
  EXPECT_TRUE(primitive);
  EXPECT_TRUE(mesh);
  EXPECT_EQ(engines::deck_revision("liggghts"), 2);
  EXPECT_EQ(engines::deck_revision("lammps"), 1);
}

TEST(EnginesDecks, RefusalsNameWhatIsMissing) {
  const auto m = peer_material();
  const dem::RunProtocol p;
  auto full = testing::small_sandglass_slice(4.0);
  full.reduction.slice = false;
  auto r = write_lammps_deck(full, m, p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.refusal.find("full (3D) sandglass"), std::string::npos) << r.refusal;

  // LIGGGHTS takes the hopper's slanted plates and the conical pile's funnel as
  // STL meshes (engines/stl_mesh.hpp): one mesh per solid, the funnel's outlet
  // disc unfixed when the material is let go.
  auto cone = testing::small_sandglass_slice(6.0);
  cone.bottom = "conical";
  const auto hopper = write_liggghts_deck(cone, m, p);
  ASSERT_TRUE(hopper.ok()) << hopper.refusal;
  int plates = 0;
  for (const auto& [name, text] : hopper.deck->files)
    plates +=
        name.find("hopper") != std::string::npos && text.find("endsolid") != std::string::npos;
  EXPECT_EQ(plates, 2);
  const auto funnel = write_liggghts_deck(dem::ConicalPileOptions{}, m, p);
  ASSERT_TRUE(funnel.ok()) << funnel.refusal;
  const std::string& fs = funnel.deck->script;
  const auto let_go = fs.find("# --- open the outlet");
  ASSERT_NE(let_go, std::string::npos) << fs;
  EXPECT_NE(fs.find("unfix           mesh_", let_go), std::string::npos) << fs;
  EXPECT_NE(fs.find("fix             wall_meshes_open", let_go), std::string::npos) << fs;
  dem::ConicalPileOptions slice;
  slice.reduction.slice = true;
  EXPECT_NE(write_lammps_deck(slice, m, p).refusal.find("V-shaped funnel"), std::string::npos);

  // LIGGGHTS's mesh walls in a thin periodic slab.
  const auto thin = write_liggghts_deck(testing::small_sandglass_slice(4.0), m, p);
  ASSERT_FALSE(thin.ok());
  EXPECT_NE(thin.refusal.find("thinner than 6 diameters"), std::string::npos) << thin.refusal;

  // A contact law the engine cannot run: the mapping's refusal comes through.
  EXPECT_NE(write_lammps_deck(container(), peer_material("cdt"), p)
                .refusal.find("constant directional torque"),
            std::string::npos);

  // An invalid description is an error, as in demcal, not a refusal.
  auto bad = container();
  bad.fill_mass_kg = -1.0;
  EXPECT_THROW(write_lammps_deck(bad, m, p), std::invalid_argument);
}

TEST(EnginesDecks, DemcalsTimeStepRule) {
  // 0.2 Rayleigh times of the smallest grain, as Simulation takes it.
  const auto r = write_lammps_deck(container(), peer_material(), dem::RunProtocol{});
  ASSERT_TRUE(r.ok());
  dem::Material g = peer_material().particle;
  EXPECT_DOUBLE_EQ(r.deck->record["layout"]["time_step_s"].get<double>(),
                   0.2 * dem::rayleigh_time_s(g, 0.5e-3));
}

}  // namespace
}  // namespace demcal::engines
