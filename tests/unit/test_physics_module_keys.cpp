// The config keys of the switchable physics modules (cohesion, air drag, the
// size spread, particle–wall friction): each reaches the engine, each mistake
// is a ConfigError naming file:line and the key, the aliases and design
// parameters address them, and a config without them resolves as before (so
// the run store's hashes of existing studies do not change).

#include "config/design_config.hpp"
#include "study/run_store.hpp"
#include "config/simulation_config.hpp"
#include "config/study_config.hpp"
#include "dem/size_distribution.hpp"
#include "tests/support/study_text.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace demcal::cli {
namespace {

using namespace demcal::config;
using namespace demcal::study;

const std::string kStudy = R"([study]
name = "modules"

)" +
    testing::sand_and_glass_tables({.size =
                  R"({ distribution = "uniform", mean_diameter_m = 4.5e-4, relative_half_width = 0.33 })"}) +
    R"(
[apparatus.rectangular_container]
width_m = 0.22
height_m = 0.1
thickness_diameters = 4.0
boundary = "periodic"
fill_mass_kg = 0.055
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7
)";

const std::string kFile = "study.toml";

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test setup: \"" << from << "\" not in the text";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::size_t line_of(const std::string& text, const std::string& needle) {
  std::istringstream in(text);
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n)
    if (line.find(needle) != std::string::npos) return n;
  ADD_FAILURE() << "test setup: \"" << needle << "\" not in the text";
  return 0;
}

std::string at_line(const std::string& text, const std::string& needle) {
  return kFile + ":" + std::to_string(line_of(text, needle)) + ": ";
}

StudyConfig build(const std::string& text, const std::vector<std::string>& overrides = {}) {
  ConfigDocument doc = parse_config_string(text, kFile);
  for (const auto& o : overrides) apply_override(doc, o, study_override_aliases());
  return build_study(std::move(doc));
}

void expect_error(const std::string& text, const std::vector<std::string>& parts,
                  const std::vector<std::string>& overrides = {}) {
  try {
    build(text, overrides);
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    for (const auto& p : parts)
      EXPECT_NE(msg.find(p), std::string::npos) << "message lacks \"" << p << "\": " << msg;
  }
}

const std::string kJkr =
    replace(kStudy, "rolling = \"cdt\"\n", "rolling = \"cdt\"\nadhesion = \"jkr\"\n");
const std::string kJkrWithGamma = replace(kJkr, "sliding_friction = 0.52\n",
                                          "sliding_friction = 0.52\nsurface_energy_j_m2 = 0.02\n");

// --- cohesion ---

TEST(PhysicsModuleKeys, NewKeysAbsentResolveAsBefore) {
  StudyConfig s = build(kStudy);
  EXPECT_FALSE(s.resolved["air"]);
  EXPECT_FALSE(s.resolved["interaction"]["particle_particle"]["surface_energy_j_m2"]);
  EXPECT_FALSE(s.resolved["interaction"]["particle_wall"]["surface_energy_j_m2"]);
  EXPECT_FALSE(s.material.air_drag.has_value());
  EXPECT_EQ(s.material.particle_particle.surface_energy_j_m2, 0.0);
}

TEST(PhysicsModuleKeys, JkrWithASurfaceEnergyBuilds) {
  StudyConfig s = build(kJkrWithGamma);
  EXPECT_EQ(s.material.contact.adhesion, "jkr");
  EXPECT_DOUBLE_EQ(s.material.particle_particle.surface_energy_j_m2, 0.02);
  EXPECT_EQ(s.material.particle_wall.surface_energy_j_m2, 0.0);
  EXPECT_EQ(s.resolved["interaction"]["particle_particle"]["surface_energy_j_m2"].value<double>(),
            0.02);
  EXPECT_EQ(s.apparatus.front().apparatus->simulation().contact_law().describe(),
            "normal=hertz adhesion=jkr tangential=mindlin rolling=cdt");
  // The aliases reach both surface energies.
  StudyConfig t = build(kJkr, {"surface_energy=0.1", "surface_energy_wall=0.03"});
  EXPECT_DOUBLE_EQ(t.material.particle_particle.surface_energy_j_m2, 0.1);
  EXPECT_DOUBLE_EQ(t.material.particle_wall.surface_energy_j_m2, 0.03);
  // An explicit 0 is a cohesionless point of a cohesive design, not a mistake.
  EXPECT_NO_THROW(build(kJkr, {"surface_energy=0"}));
}

TEST(PhysicsModuleKeys, JkrWithoutASurfaceEnergyIsRefusedAtTheAdhesionKey) {
  expect_error(kJkr, {at_line(kJkr, "adhesion = \"jkr\""), "contact.adhesion", "\"jkr\" needs",
                      "surface_energy_j_m2"});
}

TEST(PhysicsModuleKeys, SurfaceEnergyWithoutAnAdhesionPartIsRefusedAtItsKey) {
  const std::string text = replace(kStudy, "sliding_friction = 0.5\n",
                                   "sliding_friction = 0.5\nsurface_energy_j_m2 = 0.04\n");
  expect_error(text,
               {at_line(text, "surface_energy_j_m2 = 0.04"),
                "interaction.particle_wall.surface_energy_j_m2", "contact.adhesion is \"none\""});
  // Through the alias the message names the option.
  expect_error(
      kStudy,
      {"interaction.particle_particle.surface_energy_j_m2", "(from --set surface_energy=0.04)"},
      {"surface_energy=0.04"});
  // 0 with "none" says nothing false: accepted.
  EXPECT_NO_THROW(build(kStudy, {"surface_energy=0"}));
}

TEST(PhysicsModuleKeys, NegativeSurfaceEnergyIsRefused) {
  const std::string text =
      replace(kJkrWithGamma, "surface_energy_j_m2 = 0.02", "surface_energy_j_m2 = -1");
  expect_error(text, {at_line(text, "surface_energy_j_m2 = -1"),
                      "interaction.particle_particle.surface_energy_j_m2", "expected a number >= 0",
                      "got -1"});
}

// --- air drag ---

TEST(PhysicsModuleKeys, AirTableTurnsOnTheDragWithItsDefaults) {
  StudyConfig s = build(std::string(kStudy) + "\n[air]\ndrag = \"schiller_naumann\"\n");
  ASSERT_TRUE(s.material.air_drag.has_value());
  EXPECT_DOUBLE_EQ(s.material.air_drag->density_kg_m3, 1.2);
  EXPECT_DOUBLE_EQ(s.material.air_drag->dynamic_viscosity_pa_s, 1.8e-5);
  EXPECT_EQ(s.resolved["air"]["dynamic_viscosity_pa_s"].value<double>(), 1.8e-5);
  // Toggled and changed from the command line.
  StudyConfig t = build(kStudy, {"air.drag=schiller_naumann", "air.density_kg_m3=1.0"});
  ASSERT_TRUE(t.material.air_drag.has_value());
  EXPECT_DOUBLE_EQ(t.material.air_drag->density_kg_m3, 1.0);
  EXPECT_FALSE(build(kStudy, {"air.drag=none"}).material.air_drag.has_value());
}

TEST(PhysicsModuleKeys, AirTableMistakesAreRefusedAtTheirKeys) {
  const std::string base = std::string(kStudy) + "\n[air]\ndrag = \"schiller_naumann\"\n";
  expect_error(base + "viscosity = 1e-5\n",
               {at_line(base + "viscosity = 1e-5\n", "viscosity = 1e-5"), "air.viscosity",
                "unknown key", "\"dynamic_viscosity_pa_s\""});
  expect_error(base + "density_kg_m3 = 0\n", {"air.density_kg_m3", "expected a number > 0"});
  expect_error(kStudy, {"air.drag", "\"schiller_naumann\"", "got \"stokes\""}, {"air.drag=stokes"});
}

TEST(PhysicsModuleKeys, DragScaleReachesTheDragAndIsWrittenInOnlyWhenGiven) {
  const std::string air = std::string(kStudy) + "\n[air]\ndrag = \"schiller_naumann\"\n";
  StudyConfig s = build(air + "drag_scale = 0.5\n");
  ASSERT_TRUE(s.material.air_drag.has_value());
  EXPECT_DOUBLE_EQ(s.material.air_drag->drag_scale, 0.5);
  EXPECT_EQ(s.resolved["air"]["drag_scale"].value<double>(), 0.5);
  EXPECT_FALSE(build(air).resolved["air"]["drag_scale"]);
  // The alias, and the diagnosis' "off" end on a study without [air]: 0 is no drag, not a mistake.
  for (const std::string& o : {std::string("air.drag_scale=2"), std::string("drag_scale=2")}) {
    SCOPED_TRACE(o);
    const StudyConfig t = build(kStudy, {"air.drag=schiller_naumann", o});
    ASSERT_TRUE(t.material.air_drag.has_value());
    EXPECT_DOUBLE_EQ(t.material.air_drag->drag_scale, 2.0);
  }
  const StudyConfig off = build(kStudy, {"air.drag=schiller_naumann", "drag_scale=0"});
  ASSERT_TRUE(off.material.air_drag.has_value());
  EXPECT_EQ(off.material.air_drag->drag_scale, 0.0);
  EXPECT_NE(off.apparatus.front().apparatus, nullptr);  // built, with its AirDrag
}

TEST(PhysicsModuleKeys, NegativeOrNonFiniteDragScaleIsRefusedNamingTheKey) {
  const std::string air = std::string(kStudy) + "\n[air]\ndrag = \"schiller_naumann\"\n";
  const std::string text = air + "drag_scale = -1\n";
  expect_error(text, {at_line(text, "drag_scale = -1"), "air.drag_scale", "expected a number >= 0",
                      "got -1"});
  expect_error(air + "drag_scale = inf\n", {"air.drag_scale", "expected a number >= 0"});
  expect_error(air + "drag_scale = \"1\"\n", {"air.drag_scale", "expected a number >= 0"});
  expect_error(kStudy, {"air.drag_scale", "expected a number >= 0", "(from --set drag_scale=-0.5)"},
               {"air.drag=schiller_naumann", "drag_scale=-0.5"});
}

TEST(PhysicsModuleKeys, AirWithoutADragScaleResolvesAndHashesAsBefore) {
  // drag_scale is not written in when absent: the resolved [air] table, and the
  // run keys of studies with and without [air], are those pinned before the key
  // existed (a change would orphan the runs of existing stores). The hashes are those of
  // key_version 2 (spatial particle order the default, issue 13); with version 1 they were
  // 2c3790966e5e1b72 and db956850adb34953.
  const StudyConfig s = build(std::string(kStudy) + "\n[air]\ndrag = \"schiller_naumann\"\n");
  ASSERT_TRUE(s.resolved["air"].as_table());
  std::ostringstream air;
  air << toml::toml_formatter(*s.resolved["air"].as_table());
  EXPECT_EQ(air.str(), "density_kg_m3 = 1.2\ndrag = 'schiller_naumann'\ndynamic_viscosity_pa_s = 1.8e-05");
  EXPECT_EQ(run_key_for(s, "rectangular_container", 1, 1).hash, "bf1ab62e429beff1");
  EXPECT_EQ(run_key_for(build(kStudy), "rectangular_container", 1, 1).hash, "d664089c3b80de5a");
  EXPECT_DOUBLE_EQ(s.material.air_drag->drag_scale, 1.0);
}

// --- size spread ---

TEST(PhysicsModuleKeys, SizeSpreadIsOneKeyAtAFixedMean) {
  StudyConfig s = build(kStudy);
  EXPECT_NEAR(s.material.sizes->min_diameter_m(), 4.5e-4 * 0.67, 1e-15);
  EXPECT_NEAR(s.material.sizes->max_diameter_m(), 4.5e-4 * 1.33, 1e-15);
  for (const std::string& o :
       {std::string("material.size.relative_half_width=0.1"), std::string("size_spread=0.1")}) {
    SCOPED_TRACE(o);
    const StudyConfig t = build(kStudy, {o});
    EXPECT_NEAR(t.material.sizes->min_diameter_m(), 4.05e-4, 1e-15);
    EXPECT_NEAR(t.material.sizes->max_diameter_m(), 4.95e-4, 1e-15);
    EXPECT_EQ(t.resolved["material"]["size"]["relative_half_width"].value<double>(), 0.1);
  }
}

TEST(PhysicsModuleKeys, InvalidSizeSpreadIsRefusedNamingTheKey) {
  for (const char* w : {"1.0", "-0.1", "1.5"})
    expect_error(kStudy,
                 {at_line(kStudy, "size = "), "material.size.relative_half_width",
                  "expected a number in [0, 1)", std::string("(from --set size_spread=") + w},
                 {std::string("size_spread=") + w});
  // The two forms of "uniform" do not mix.
  const std::string mixed = replace(kStudy, "relative_half_width = 0.33",
                                    "relative_half_width = 0.33, max_diameter_m = 6e-4");
  expect_error(mixed, {"material.size.max_diameter_m", "not both forms"});
  // The bounds form stays as it was.
  StudyConfig b = build(replace(kStudy, "mean_diameter_m = 4.5e-4, relative_half_width = 0.33",
                                "min_diameter_m = 3e-4, max_diameter_m = 6e-4"));
  EXPECT_DOUBLE_EQ(b.material.sizes->max_diameter_m(), 6e-4);
}

TEST(PhysicsModuleKeys, ADesignVariesTheModuleParameters) {
  const std::string text = kJkrWithGamma +
                           "\n[design]\nkind = \"latin_hypercube\"\npoints = 4\n"
                           "parameters = { size_spread = { lower = 0.0, upper = 0.4 }, "
                           "surface_energy = { lower = 0.0, upper = 0.1 }, "
                           "mu_s_wall = { lower = 0.2, upper = 0.6 } }\n";
  StudyConfig s = build(text);
  ASSERT_TRUE(s.design.has_value());
  const std::vector<std::string> expected = {"material.size.relative_half_width",
                                             "interaction.particle_particle.surface_energy_j_m2",
                                             "interaction.particle_wall.sliding_friction"};
  EXPECT_EQ(s.design->parameter_paths, expected);
  // Both ends of each range build (what `demcal doe` checks before it runs).
  StudySource source{kFile, text, {}};
  EXPECT_NO_THROW(check_design_bounds(source, *s.design));
  ConfigDocument doc = source.document();
  apply_design_values(doc, *s.design, {0.2, 0.05, 0.3}, "design point 0");
  StudyConfig point = build_study(std::move(doc));
  EXPECT_NEAR(point.material.sizes->max_diameter_m(), 4.5e-4 * 1.2, 1e-15);
  EXPECT_DOUBLE_EQ(point.material.particle_particle.surface_energy_j_m2, 0.05);
  EXPECT_DOUBLE_EQ(point.material.particle_wall.sliding_friction, 0.3);
}

// --- particle–wall friction ---

TEST(PhysicsModuleKeys, WallFrictionAliasesSetTheParticleWallPair) {
  StudyConfig s = build(kStudy, {"mu_s_wall=0.31", "mu_r_wall=0.07"});
  EXPECT_DOUBLE_EQ(s.material.particle_wall.sliding_friction, 0.31);
  EXPECT_DOUBLE_EQ(s.material.particle_wall.rolling_friction, 0.07);
  EXPECT_DOUBLE_EQ(s.material.particle_particle.sliding_friction, 0.52);
  EXPECT_DOUBLE_EQ(s.material.particle_particle.rolling_friction, 0.3);
  expect_error(kStudy, {"interaction.particle_wall.rolling_friction", "(from --set mu_r_wall=-1)"},
               {"mu_r_wall=-1"});
}

// --- the sampled spread ---

TEST(PhysicsModuleKeys, SampledSizesHaveTheStatedMeanAndHalfWidth) {
  const double mean = 4.5e-4, w = 0.33;
  const auto sizes = dem::make_uniform_about_mean(mean, w);
  dem::Random rng(11);
  const int n = 200000;
  double sum = 0.0, lo = 1.0, hi = 0.0, sum_d3 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double d = sizes->sample_diameter_m(rng);
    sum += d;
    sum_d3 += d * d * d;
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  // Uniform: sd of the mean = w mean / sqrt(3 n) ~ 1.9e-4 relative; 5 sigma.
  EXPECT_NEAR(sum / n, mean, 5.0 * w * mean / std::sqrt(3.0 * n));
  EXPECT_GE(lo, mean * (1.0 - w));
  EXPECT_LE(hi, mean * (1.0 + w));
  EXPECT_NEAR(0.5 * (hi - lo) / mean, w, 1e-3 * w);
  EXPECT_NEAR(sum_d3 / n, sizes->mean_diameter_cubed_m3(), 0.01 * sizes->mean_diameter_cubed_m3());
  EXPECT_NE(sizes->describe().find("+- 33 %"), std::string::npos) << sizes->describe();
  EXPECT_THROW(dem::make_uniform_about_mean(mean, 1.0), std::invalid_argument);
  EXPECT_THROW(dem::make_uniform_about_mean(mean, -0.01), std::invalid_argument);
  EXPECT_NO_THROW(dem::make_uniform_about_mean(mean, 0.0));
}

// --- the plain simulation config ---

const char* const kPlain = R"([simulation]
name = "plain"
gravity_m_s2 = [0.0, 0.0, -9.81]

[domain]
lower_m = [0.0, 0.0, 0.0]
upper_m = [0.02, 0.02, 0.04]

[contact]
normal = "hertz"
tangential = "mindlin"
rolling = "epsd"

[[material]]
name = "grain"
density_kg_m3 = 2650.0
youngs_modulus_pa = 1.0e7
poisson_ratio = 0.3

[[interaction]]
materials = ["grain", "grain"]
restitution = 0.6
sliding_friction = 0.5
rolling_friction = 0.1

[[insertion]]
type = "pour"
material = "grain"
count = 1
velocity_m_s = [0.0, 0.0, -1.0]
size = { distribution = "uniform", mean_diameter_m = 1.0e-3, relative_half_width = 0.0 }
region = { shape = "box", lower_m = [0.008, 0.008, 0.02], upper_m = [0.012, 0.012, 0.03] }

[run]
end_time_s = 0.01
)";

SimulationConfig build_plain(const std::string& text,
                             const std::vector<std::string>& overrides = {}) {
  ConfigDocument doc = parse_config_string(text, "plain.toml");
  for (const auto& o : overrides) apply_override(doc, o);
  return build_simulation(std::move(doc));
}

TEST(PhysicsModuleKeys, PlainConfigAirDragActsOnTheParticles) {
  auto force_z = [](SimulationConfig& c) {
    c.simulation->time_step_s();  // inserts at t = 0 and evaluates the forces
    const dem::Particles& p = c.simulation->particles();
    EXPECT_EQ(p.size(), 1u);
    return p.force_n[0].z / p.mass_kg[0];
  };
  SimulationConfig without = build_plain(kPlain);
  EXPECT_FALSE(without.resolved["air"]);
  EXPECT_NEAR(force_z(without), -9.81, 1e-12);
  SimulationConfig with =
      build_plain(std::string(kPlain) + "\n[air]\ndrag = \"schiller_naumann\"\n");
  const double m = 2650.0 * std::numbers::pi / 6.0 * 1e-9;
  const double drag = dem::sphere_drag_force_n(dem::AirProperties{}, 1e-3, {0, 0, -1.0}).z;  // up
  EXPECT_NEAR(force_z(with), -9.81 + drag / m, 1e-9);
  EXPECT_FALSE(with.resolved["air"]["drag_scale"]);
  SimulationConfig doubled =
      build_plain(std::string(kPlain) + "\n[air]\ndrag = \"schiller_naumann\"\n", {"air.drag_scale=2"});
  EXPECT_NEAR(force_z(doubled), -9.81 + 2.0 * drag / m, 1e-9);
  SimulationConfig off =
      build_plain(std::string(kPlain) + "\n[air]\ndrag = \"schiller_naumann\"\ndrag_scale = 0\n");
  EXPECT_NEAR(force_z(off), -9.81, 1e-12);
  try {
    build_plain(std::string(kPlain) + "\n[air]\ndrag = \"schiller_naumann\"\ndrag_scale = -1\n");
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("air.drag_scale: expected a number >= 0"), std::string::npos) << msg;
  }
}

TEST(PhysicsModuleKeys, PlainConfigJkrNeedsAndAllowsSurfaceEnergies) {
  const std::string jkr =
      replace(kPlain, "rolling = \"epsd\"\n", "rolling = \"epsd\"\nadhesion = \"jkr\"\n");
  try {
    build_plain(jkr);
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(
        msg.find("plain.toml:" + std::to_string(line_of(jkr, "adhesion")) + ": contact.adhesion"),
        std::string::npos)
        << msg;
  }
  EXPECT_NO_THROW(build_plain(jkr, {"interaction[0].surface_energy_j_m2=0.05"}));
  try {
    build_plain(kPlain, {"interaction.grain-grain.surface_energy_j_m2=0.05"});
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("interaction[0].surface_energy_j_m2"), std::string::npos) << msg;
    EXPECT_NE(msg.find("contact.adhesion is \"none\""), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace demcal::cli
