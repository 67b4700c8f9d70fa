// The LAMMPS mappings of the concealed studies' effects (issue 19): JKR
// adhesion (cohesion), air drag, a polydisperse lattice fill (size spread).
// Golden decks in tests/data/engines/ (DEMCAL_UPDATE_GOLDEN=1 rewrites them),
// the mapped numbers against demcal's own laws, and what LIGGGHTS still refuses.
#include "engines/engine_measure.hpp"
#include "engines/lammps_deck.hpp"
#include "engines/liggghts_deck.hpp"

#include "dem/air_drag.hpp"
#include "dem/contact/jkr_adhesion.hpp"
#include "dem/particles.hpp"
#include "tests/support/engine_fixtures.hpp"
#include "tests/support/golden.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <regex>
#include <set>
#include <string>

namespace demcal::engines {
namespace {

using testing::expect_golden;
using testing::peer_material;

dem::GranularMaterial cohesive(double gamma_j_m2) {
  auto m = peer_material();
  m.contact.adhesion = "jkr";
  m.particle_particle.surface_energy_j_m2 = gamma_j_m2;
  m.particle_wall.surface_energy_j_m2 = 0.5 * gamma_j_m2;
  return m;
}

dem::SandglassOptions small_slice() {
  dem::SandglassOptions s;
  s.bottom = "flat";
  s.reduction.slice = true;
  s.reduction.slice_thickness_diameters = 4.0;
  s.upper_diameter_m = 0.024;
  s.orifice_diameter_m = 0.008;
  s.upper_height_m = 0.1;
  s.lower_diameter_m = 0.06;
  s.drop_height_m = 0.03;
  s.fill_mass_kg = 0.01;
  s.fill_lattice_spacing_diameters = 1.25;
  return s;
}

dem::RectangularContainerOptions small_container(const std::string& boundary) {
  dem::RectangularContainerOptions o;
  o.width_m = 0.1;
  o.height_m = 0.05;
  o.thickness_diameters = 6.0;
  o.boundary = boundary;
  o.fill_mass_kg = 0.005;
  return o;
}

// The numbers after `word` on the deck's line that starts with `head`.
std::string line_starting(const std::string& script, const std::string& head) {
  const auto at = script.find("\n" + head);
  if (at == std::string::npos) return "";
  return script.substr(at + 1, script.find('\n', at + 1) - at - 1);
}

TEST(EnginesEffects, JkrMapsOntoLammpsGranularJkrWithDemcalsStiffnessAndPullOff) {
  dem::ModelReduction r;
  r.coarse_graining_factor = 14.0;
  r.shear_modulus_pa = 1e7;
  // Walls with adhesion are refused (LAMMPS 29Sep2021's wall JKR gives NaN),
  // unless run dry by choice.
  const auto refused = map_to_lammps(cohesive(4e-4), r);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.refusal.find("particle_wall.surface_energy_j_m2"), std::string::npos)
      << refused.refusal;
  MappingOptions dry_walls;
  dry_walls.allow_dry_walls = true;
  const auto mapped = map_to_lammps(cohesive(4e-4), r, dry_walls);
  ASSERT_TRUE(mapped.ok()) << mapped.refusal;
  const LammpsMapping& m = mapped.value();
  ASSERT_TRUE(m.particle_particle.jkr);
  // gamma x f^2, as install_materials coarse-grains it.
  EXPECT_NEAR(m.particle_particle.surface_energy_j_m2, 4e-4 * 196.0, 1e-15);
  EXPECT_FALSE(m.particle_wall.jkr);
  EXPECT_EQ(m.particle_wall.granular_words().rfind("hertz ", 0), 0u);
  // LAMMPS's jkr E with nu = 0 mixes to E / 2: it must give back demcal's E*.
  const double e_star = 0.75 * m.particle_particle.normal_stiffness_pa;
  const std::string words = m.particle_particle.granular_words();
  EXPECT_EQ(words.rfind("jkr " + deck_number(2.0 * e_star) + " ", 0), 0u) << words;
  EXPECT_EQ(words.find("limit_damping"), std::string::npos) << words;  // LAMMPS refuses it with jkr
  EXPECT_NE(words.find(" 0 " + deck_number(4e-4 * 196.0) + " damping tsuji tangential mindlin"),
            std::string::npos)
      << words;
  // The pull-off force LAMMPS computes from these numbers (3 pi gamma R*) is
  // demcal's; so is the JKR force at an overlap (demcal's curve vs LAMMPS's
  // closed form of a(delta), both at D = delta R*/a_c^2 = 1).
  const double gamma = m.particle_particle.surface_energy_j_m2, reff = 0.25e-3;
  const double ac = std::cbrt(dem::jkr::critical_radius_cubed_m3(e_star, gamma, reff));
  const double delta = ac * ac / reff;
  const dem::JkrContact c = dem::jkr::contact(e_star, gamma, reff, delta);
  const double a = c.contact_radius_m;
  const double lammps_force =
      4.0 / 3.0 * e_star * a * a * a / reff -
      2.0 * std::numbers::pi * a * a * std::sqrt(4.0 * gamma * e_star / (std::numbers::pi * a));
  EXPECT_NEAR(lammps_force, c.force_n, 1e-9 * std::abs(c.force_n));
  // The statement of what differs goes into the record.
  bool stated = false, dry = false;
  for (const auto& s : m.approximations) {
    stated = stated || s.find("force-controlled") != s.npos;
    dry = dry || s.find("walls dry") != s.npos;
  }
  EXPECT_TRUE(stated);
  EXPECT_TRUE(dry);
  // Dry materials keep the hertz words, unchanged.
  EXPECT_EQ(map_to_lammps(peer_material(), r)
                .value()
                .particle_particle.granular_words()
                .rfind("hertz ", 0),
            0u);
}

TEST(EnginesEffects, LammpsSandglassSliceWithJkrGolden) {
  auto m = cohesive(1e-3);
  m.particle_wall.surface_energy_j_m2 = 0.0;  // walls without adhesion: the deck LAMMPS can run
  const auto r = write_lammps_deck(small_slice(), m, dem::RunProtocol{});
  ASSERT_TRUE(r.ok()) << r.refusal;
  expect_golden(r.deck->script, "engines/lammps_sandglass_slice_jkr.in");
  EXPECT_NE(line_starting(r.deck->script, "fix             wall_floor").find("granular hertz "),
            std::string::npos);
  EXPECT_NE(line_starting(r.deck->script, "pair_coeff").find("* * jkr "), std::string::npos);
}

TEST(EnginesEffects, AirDragIsDemcalsSchillerNaumannAsAtomStyleVariables) {
  auto m = peer_material();
  m.sizes = dem::make_monodisperse(0.2e-3);  // 2.8 mm parcels of 0.2 mm grains
  m.air_drag = dem::AirProperties{};
  m.air_drag->drag_scale = 0.8;
  auto o = small_container("periodic");
  o.reduction.coarse_graining_factor = 14.0;
  const auto r = write_lammps_deck(o, m, dem::RunProtocol{});
  ASSERT_TRUE(r.ok()) << r.refusal;
  expect_golden(r.deck->script, "engines/lammps_rectangular_container_air_drag.in");
  const std::string& s = r.deck->script;
  EXPECT_NE(s.find("fix             air_drag all addforce v_drag_fx v_drag_fy v_drag_fz"),
            std::string::npos);
  // Evaluate the deck's expressions as LAMMPS would, for one atom, and compare
  // with demcal's AirDrag on the same parcel.
  auto coefficient = [&](const std::string& name) {
    const std::string line = line_starting(s, "variable        " + name + " atom ");
    const std::string rest = line.substr(line.find(" atom ") + 6);
    return std::stod(rest.substr(0, rest.find('*')));
  };
  const double re_per_radius_speed = coefficient("drag_re");
  const double c_per_radius = coefficient("drag_c");
  const double radius = 0.7e-3, speed = 1.3;
  const double re = re_per_radius_speed * radius * speed;
  const double k = re < 1000.0 ? 1.0 + 0.15 * std::pow(re, 0.687) : 0.44 / 24.0 * re;
  const double lammps_fz = c_per_radius * radius * k * (-speed);

  dem::Particles p;
  p.add({0.0, 0.0, 0.0}, radius, 2650.0, 0, 1, {0.0, 0.0, -speed});
  std::vector<dem::Vec3> force(1), torque(1);
  dem::AirDrag(*m.air_drag, 14.0).add(p, 0, 1, force, torque);
  EXPECT_NEAR(lammps_fz, force[0].z, 1e-12 * std::abs(force[0].z));
  EXPECT_GT(lammps_fz, 0.0);  // opposes the fall
  EXPECT_TRUE(r.deck->record["mapping"].contains("air_drag"));
  // Without drag the record has no such entry (records of earlier decks unchanged).
  auto still = m;
  still.air_drag.reset();
  EXPECT_FALSE(
      write_lammps_deck(o, still, dem::RunProtocol{}).deck->record["mapping"].contains("air_drag"));
}

TEST(EnginesEffects, PolydisperseLatticeFillGolden) {
  auto m = peer_material();
  m.sizes = dem::make_uniform(0.7e-3, 1.3e-3);
  const auto r = write_lammps_deck(small_slice(), m, dem::RunProtocol{});
  ASSERT_TRUE(r.ok()) << r.refusal;
  expect_golden(r.deck->script, "engines/lammps_sandglass_slice_polydisperse.in");
  const std::string& s = r.deck->script;
  EXPECT_NE(s.find("create_box      8 box"), std::string::npos);
  EXPECT_NE(s.find("set             type 2*8 type 1"), std::string::npos);
  // The type/ratio shares, applied in turn to what is still type 1, give every
  // class its number fraction 1/8.
  const std::regex ratio("type/ratio ([0-9]+) ([0-9.e-]+) ");
  double left = 1.0;
  int classes = 0;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), ratio); it != std::sregex_iterator();
       ++it) {
    const double share = std::stod((*it)[2]);
    EXPECT_NEAR(left * share, 1.0 / 8.0, 1e-12);
    left -= left * share;
    ++classes;
  }
  EXPECT_EQ(classes, 7);
  EXPECT_NEAR(left, 1.0 / 8.0, 1e-12);
  // The lattice is spaced for the largest grain: 1.25 x 1.3 mm.
  EXPECT_DOUBLE_EQ(r.deck->record["layout"]["lattice_fill"]["spacing_m"].get<double>(),
                   1.25 * 1.3e-3);
  // A monodisperse fill keeps its one type and one diameter (goldens of before).
  const auto mono = write_lammps_deck(small_slice(), peer_material(), dem::RunProtocol{});
  EXPECT_NE(mono.deck->script.find("create_box      1 box"), std::string::npos);
}

TEST(EnginesEffects, SandglassSliceHopperGolden) {
  // The concealed base study's sandglass has a hopper (bottom = "conical", 30 deg).
  auto o = small_slice();
  o.bottom = "conical";
  o.hopper_half_angle_deg = 30.0;
  const auto r = write_lammps_deck(o, peer_material(), dem::RunProtocol{});
  ASSERT_TRUE(r.ok()) << r.refusal;
  expect_golden(r.deck->script, "engines/lammps_sandglass_slice_hopper.in");
  // dem::Sandglass's hopper: from the orifice's edge (r0 = 4 mm) up to the
  // chamber wall (ru = 12 mm) over (ru - r0) / tan 30 deg.
  const double h = 0.008 / std::tan(30.0 * std::numbers::pi / 180.0);
  const auto& plates = r.deck->record["layout"]["slanted_plates"];
  ASSERT_EQ(plates.size(), 2u);
  EXPECT_DOUBLE_EQ(plates[1]["x_lower_m"].get<double>(), 0.004);
  EXPECT_DOUBLE_EQ(plates[1]["tilt_x_m"].get<double>(), 0.008);
  EXPECT_NEAR(plates[1]["z_upper_m"].get<double>() - plates[1]["z_lower_m"].get<double>(), h,
              1e-15);
  EXPECT_NE(r.deck->script.find("prism -0.006 -0.004 INF INF 0.03 "), std::string::npos);
  // The chamber walls start where the hopper ends, the fill above both.
  EXPECT_NEAR(r.deck->record["layout"]["blocks"][0]["lower_m"][2].get<double>(), 0.03 + h, 1e-15);
  EXPECT_GE(r.deck->record["layout"]["lattice_fill"]["region"]["lower_m"][2].get<double>(),
            0.03 + h);
  // A flat bottom writes no plates and no record entry (goldens of before).
  EXPECT_FALSE(write_lammps_deck(small_slice(), peer_material(), dem::RunProtocol{})
                   .deck->record["layout"]
                   .contains("slanted_plates"));
}

TEST(EnginesEffects, SandglassBulkDensityFromTheSettledFill) {
  // A block of 20 x 10 grains of 1 mm filling a flat-bottomed chamber 20 mm
  // wide to 10 mm, in a 4 mm slice: dem::Sandglass's rule gives mass / volume.
  ParticleDump fill;
  for (int i = 0; i < 20; ++i)
    for (int k = 0; k < 10; ++k) {
      fill.id.push_back(static_cast<std::int64_t>(fill.id.size()) + 1);
      fill.type.push_back(1);
      fill.position_m.push_back({-0.0095 + 0.001 * i, 0.002, 0.0305 + 0.001 * k});
      fill.radius_m.push_back(0.5e-3);
      fill.velocity_m_s.push_back({});
    }
  MassSeries m;
  for (int i = 0; i <= 40; ++i) {
    const double t = 0.005 * i;
    const double out = std::min(1e-3, std::max(0.0, 0.01 * (t - 0.01)));
    m.time_s.push_back(t);
    m.discharged_kg.push_back(out);
    m.above_orifice_kg.push_back(1e-3 - out);
  }
  nlohmann::json plan = {{"kind", "sandglass_slice"}, {"apparatus", "sandglass"},
                         {"orifice_plane_z_m", 0.03}, {"orifice_width_m", 0.008},
                         {"form_pile", false},        {"stall_time_s", 0.05},
                         {"density_kg_m3", 2650.0}};
  plan["bulk_density"] = {{"upper_radius_m", 0.01},     {"orifice_radius_m", 0.004},
                          {"orifice_plane_z_m", 0.03},  {"hopper_height_m", 0.0},
                          {"slice_thickness_m", 0.004}, {"mean_diameter_m", 1e-3}};
  const double mass = 200 * 2650.0 * std::numbers::pi / 6.0 * 1e-9;
  const auto flat = measure_engine_output(plan, ParticleDump{}, &m, &fill);
  EXPECT_NEAR(flat.observables["bulk_density_kg_m3"].get<double>(), mass / (0.02 * 0.01 * 0.004),
              1e-9);
  // With a hopper 4 mm high below the same surface: the frustum (r0 + ru) h d
  // replaces 2 ru h d.
  plan["bulk_density"]["hopper_height_m"] = 0.004;
  const auto hopper = measure_engine_output(plan, ParticleDump{}, &m, &fill);
  const double volume = (0.004 + 0.01) * 0.004 * 0.004 + 0.02 * 0.006 * 0.004;
  EXPECT_NEAR(hopper.observables["bulk_density_kg_m3"].get<double>(), mass / volume, 1e-9);
  // No settled fill given: no bulk density (LIGGGHTS decks write none).
  EXPECT_FALSE(
      measure_engine_output(plan, ParticleDump{}, &m).observables.contains("bulk_density_kg_m3"));
}

TEST(EnginesEffects, ConcealedBaseStudysSandglassIsWrittenForEveryTruth) {
  // tests/concealed/base_study.toml.in's sandglass and material (rolling epsd:
  // LAMMPS refuses cdt without the substitute), with each truth's effect.
  dem::SandglassOptions s;
  s.upper_diameter_m = 0.08;
  s.upper_height_m = 0.15;
  s.bottom = "conical";
  s.hopper_half_angle_deg = 30.0;
  s.orifice_diameter_m = 0.022;
  s.fill_mass_kg = 0.15;
  s.lower_diameter_m = 0.15;
  s.drop_height_m = 0.10;
  s.reduction.slice = true;
  s.reduction.slice_thickness_diameters = 4.2;
  s.reduction.coarse_graining_factor = 14.0;
  s.reduction.shear_modulus_pa = 1.0e7;
  auto base = [] {
    dem::GranularMaterial m;
    m.particle = {"fine-quartz-sand", 2650.0, 0.0, 3.0e10, 0.25};
    m.wall = {"glass", 2500.0, 6.3e10, 0.0, 0.23};
    m.particle_particle.restitution = 0.6;
    m.particle_particle.sliding_friction = 0.5;
    m.particle_particle.rolling_friction = 0.2;
    m.particle_wall = m.particle_particle;
    m.contact.rolling = "epsd";
    m.sizes = dem::make_uniform_about_mean(2.0e-4, 0.25);
    return m;
  };
  dem::RunProtocol p;
  p.rest_speed_m_s = 5.0e-3;
  auto cohesion = base();
  cohesion.contact.adhesion = "jkr";
  cohesion.particle_particle.surface_energy_j_m2 = 4e-4;
  auto wall_friction = base();
  wall_friction.particle_wall.sliding_friction = 0.15;
  auto drag = base();
  drag.air_drag = dem::AirProperties{};
  auto spread = base();
  spread.sizes = dem::make_uniform_about_mean(2.0e-4, 0.55);
  for (const auto& m : {base(), cohesion, wall_friction, drag, spread}) {
    const auto r = write_lammps_deck(s, m, p);
    ASSERT_TRUE(r.ok()) << r.refusal;
    EXPECT_EQ(r.deck->record["layout"]["slanted_plates"].size(), 2u);
  }
  // The cohesion truth as it stands (wall surface energy too) is refused by name.
  cohesion.particle_wall.surface_energy_j_m2 = 4e-4;
  EXPECT_NE(write_lammps_deck(s, cohesion, p).refusal.find("particle_wall.surface_energy_j_m2"),
            std::string::npos);
}

TEST(EnginesEffects, ConicalPilePolydisperseFillIsWritten) {
  dem::ConicalPileOptions o;
  o.funnel_top_diameter_m = 0.02;
  o.funnel_outlet_diameter_m = 0.006;
  o.feed_height_m = 0.05;
  o.drop_height_m = 0.02;
  o.base_diameter_m = 0.03;
  o.fill_mass_kg = 0.004;
  auto m = peer_material();
  m.sizes = dem::make_uniform(0.8e-3, 1.2e-3);
  const auto r = write_lammps_deck(o, m, dem::RunProtocol{});
  ASSERT_TRUE(r.ok()) << r.refusal;
  EXPECT_NE(r.deck->script.find("type/ratio 8 "), std::string::npos);
}

TEST(EnginesEffects, LiggghtsStillRefusesTheEffects) {
  const dem::RunProtocol p;
  auto six = small_slice();
  six.reduction.slice_thickness_diameters = 6.0;
  EXPECT_NE(write_liggghts_deck(six, cohesive(1e-3), p).refusal.find("adhesion \"jkr\""),
            std::string::npos);
  auto drag = peer_material();
  drag.air_drag = dem::AirProperties{};
  EXPECT_NE(write_liggghts_deck(six, drag, p).refusal.find("air drag"), std::string::npos);
}

// LIGGGHTS 3.8 has no set type/ratio: its polydisperse lattice fill draws each
// site into a size class with type/fraction (the shares, applied in turn to
// what is still type 1, give every class its number fraction), uses types 3..
// for the classes (type 2 is the walls), gives every material table those
// types as grains, and resets them to 1 before anything runs.
TEST(EnginesEffects, LiggghtsPolydisperseLatticeFill) {
  auto six = small_slice();
  // Six of the largest diameters, LIGGGHTS's least periodic mesh slab.
  six.reduction.slice_thickness_diameters = 8.0;
  auto poly = peer_material();
  poly.sizes = dem::make_uniform(0.8e-3, 1.2e-3);
  const auto r = write_liggghts_deck(six, poly, dem::RunProtocol{});
  ASSERT_TRUE(r.ok()) << r.refusal;
  const std::string& s = r.deck->script;
  EXPECT_NE(s.find("create_box      9 box"), std::string::npos);
  const std::regex fraction("type/fraction ([0-9]+) ([0-9.e-]+) ");
  double left = 1.0;
  std::set<int> types;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), fraction); it != std::sregex_iterator();
       ++it) {
    types.insert(std::stoi((*it)[1]));
    const double share = std::stod((*it)[2]);
    EXPECT_NEAR(left * share, 1.0 / 8.0, 1e-12);
    left -= left * share;
  }
  EXPECT_EQ(types, (std::set<int>{3, 4, 5, 6, 7, 8, 9}));
  EXPECT_NEAR(left, 1.0 / 8.0, 1e-12);
  for (int t = 3; t <= 9; ++t)
    EXPECT_NE(s.find("set             type " + std::to_string(t) + " type 1"), std::string::npos);
  // 9 x 9 pairs: the walls' column and row carry the particle-wall friction.
  EXPECT_NE(s.find("coefficientFriction peratomtypepair 9 0.5 0.9 0.5"), std::string::npos) << s;
  EXPECT_LT(s.find("type 9 type 1"), s.find("\nrun "));
}

}  // namespace
}  // namespace demcal::engines
