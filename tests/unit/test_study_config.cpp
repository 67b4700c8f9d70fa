// The study config reader and the apparatus path of `demcal simulate`: a valid
// study builds every apparatus it defines (building is cheap: nothing runs),
// and every kind of mistake, including a geometry that cannot hold its fill,
// is a ConfigError naming file, line, table and key before anything runs.

#include "study/run_record.hpp"
#include "cli/simulate_command.hpp"
#include "config/study_config.hpp"
#include "tests/support/study_text.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace demcal::cli {
namespace {

using namespace demcal::config;
using namespace demcal::study;

// Small, coarse-grained and sliced so that building all three is instant.
const std::string kStudy = R"(# a study with all three apparatus
[study]
name = "unit-study"
seed = 3

)" +
    testing::sand_and_glass_tables({.size =
                  R"({ distribution = "uniform", min_diameter_m = 3.0e-4, max_diameter_m = 6.0e-4 })"}) +
    R"(
[apparatus.sandglass]
upper_diameter_m = 0.08
upper_height_m = 0.12
bottom = "conical"
hopper_half_angle_deg = 30.0
orifice_diameter_m = 0.02
fill_mass_kg = 0.31
lower_diameter_m = 0.2
drop_height_m = 0.08
slice = true
slice_thickness_diameters = 4.2
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7

[apparatus.conical_pile]
funnel_top_diameter_m = 0.08
funnel_outlet_diameter_m = 0.02
funnel_half_angle_deg = 30.0
feed_height_m = 0.125
drop_height_m = 0.06
base_diameter_m = 0.12
fill_mass_kg = 0.2
slice = true
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7

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
  EXPECT_NE(at, std::string::npos) << "test setup: \"" << from << "\" not in the study";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Cuts [apparatus.<name>] (up to the next table header or the end) out of the study.
std::string without_table(std::string text, const std::string& header) {
  const std::size_t at = text.find(header);
  EXPECT_NE(at, std::string::npos) << "test setup: " << header << " not in the study";
  if (at == std::string::npos) return text;
  const std::size_t next = text.find("\n[", at + 1);
  text.erase(at, next == std::string::npos ? std::string::npos : next + 1 - at);
  return text;
}

std::size_t line_of(const std::string& text, const std::string& needle) {
  std::istringstream in(text);
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n)
    if (line.find(needle) != std::string::npos) return n;
  ADD_FAILURE() << "test setup: \"" << needle << "\" not in the study";
  return 0;
}

StudyConfig build(const std::string& text, const std::vector<std::string>& overrides = {}) {
  ConfigDocument doc = parse_config_string(text, kFile);
  for (const auto& o : overrides) apply_override(doc, o, study_override_aliases());
  return build_study(std::move(doc));
}

// Expects a ConfigError whose message holds each of `parts`; returns it.
std::string expect_error(const std::string& text, const std::vector<std::string>& parts,
                         const std::vector<std::string>& overrides = {}) {
  try {
    build(text, overrides);
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    for (const auto& p : parts)
      EXPECT_NE(msg.find(p), std::string::npos) << "message lacks \"" << p << "\": " << msg;
    return msg;
  }
  return {};
}

std::string at_line(const std::string& text, const std::string& needle) {
  return kFile + ":" + std::to_string(line_of(text, needle)) + ": ";
}

TEST(StudyConfigTest, ValidStudyBuildsEachApparatus) {
  StudyConfig s = build(kStudy);
  EXPECT_EQ(s.name, "unit-study");
  ASSERT_EQ(s.apparatus.size(), 3u);
  // In file order, each built (its simulation assembled, nothing run).
  const std::vector<std::string> expected = {"sandglass", "conical_pile", "rectangular_container"};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(s.apparatus[i].name, expected[i]);
    ASSERT_NE(s.apparatus[i].apparatus, nullptr);
    EXPECT_EQ(s.apparatus[i].apparatus->name(), expected[i]);
    EXPECT_EQ(s.apparatus[i].apparatus->simulation().step_count(), 0);
    EXPECT_EQ(s.apparatus[i].apparatus->simulation().particles().size(), 0u);
  }
  EXPECT_EQ(s.protocol.seed, 3u);
  EXPECT_EQ(s.material.contact.rolling, "cdt");
  EXPECT_DOUBLE_EQ(s.material.particle_particle.sliding_friction, 0.52);
  EXPECT_DOUBLE_EQ(s.material.particle_wall.rolling_friction, 0.3);
  ASSERT_NE(s.material.sizes, nullptr);
  EXPECT_DOUBLE_EQ(s.material.sizes->max_diameter_m(), 6.0e-4);
  // Defaults come from dem::RunProtocol and are written into the resolved config.
  const dem::RunProtocol defaults;
  EXPECT_DOUBLE_EQ(s.protocol.max_flow_s, defaults.max_flow_s);
  EXPECT_EQ(s.resolved["protocol"]["max_flow_s"].value<double>(), defaults.max_flow_s);
  EXPECT_EQ(s.resolved["output"]["vtk"].value<bool>(), false);
  EXPECT_EQ(s.resolved["apparatus"]["conical_pile"]["slice_thickness_diameters"].value<double>(),
            4.0);
  // A run's record holds only its own apparatus, and the directory it wrote to.
  const toml::table r = resolved_for(s, "conical_pile");
  EXPECT_TRUE(r["apparatus"]["conical_pile"].is_table());
  EXPECT_FALSE(r["apparatus"]["sandglass"]);
  EXPECT_EQ(r["output"]["directory"].value<std::string>(), "out/unit-study/conical_pile");
}

TEST(StudyConfigTest, ShippedQuickStudiesAreValid) {
  for (const char* name : {"sandglass-quick", "conical-pile-quick", "container-quick"}) {
    SCOPED_TRACE(name);
    const std::filesystem::path path =
        std::filesystem::path(DEMCAL_SOURCE_DIR) / "studies" / name / "study.toml";
    StudyConfig s = load_study_config(path, {});
    EXPECT_EQ(s.name, name);
    EXPECT_EQ(s.apparatus.size(), 1u);
    EXPECT_DOUBLE_EQ(s.material.particle_particle.sliding_friction, 0.52);
    EXPECT_DOUBLE_EQ(s.material.particle_particle.rolling_friction, 0.3);
  }
}

TEST(StudyConfigTest, UnknownKeyInsideAnApparatusIsAnError) {
  const std::string text =
      replace(kStudy, "drop_height_m = 0.08\n", "drop_height_m = 0.08\norifice_shape = \"round\"\n");
  expect_error(text, {at_line(text, "orifice_shape"), "apparatus.sandglass.orifice_shape",
                      "unknown key", "\"orifice_diameter_m\""});
  // A misspelt required key is reported at the misspelling, not as merely missing.
  const std::string typo =
      replace(kStudy, "orifice_diameter_m = 0.02", "orifice_diamter_m = 0.02");
  expect_error(typo, {at_line(typo, "orifice_diamter_m"), "apparatus.sandglass.orifice_diameter_m",
                      "\"orifice_diamter_m\" a misspelling"});
}

TEST(StudyConfigTest, UnknownApparatusTableIsAnError) {
  const std::string text = replace(kStudy, "[apparatus.sandglass]", "[apparatus.sandglas]");
  expect_error(text, {"apparatus.sandglas", "unknown key", "\"sandglass\""});
}

TEST(StudyConfigTest, SeveralSetupsOfOneKindTakeNamesAndATypeWithoutChangingRunInputs) {
  // The sandglass at a second orifice, as a setup of its own.
  const std::size_t from = std::string(kStudy).find("[apparatus.sandglass]");
  const std::size_t to = std::string(kStudy).find("\n[", from + 1);
  std::string second = std::string(kStudy).substr(from, to - from);
  second = replace(second, "[apparatus.sandglass]", "[apparatus.orifice_24mm]\ntype = \"sandglass\"");
  second = replace(second, "orifice_diameter_m = 0.02", "orifice_diameter_m = 0.024");
  const std::string text = std::string(kStudy) + "\n" + second + "\n";
  StudyConfig s = build(text);
  ASSERT_EQ(s.apparatus.size(), 4u);
  EXPECT_EQ(s.apparatus[3].name, "orifice_24mm");
  EXPECT_EQ(s.apparatus[3].kind, "sandglass");
  EXPECT_EQ(s.apparatus[3].apparatus->name(), "sandglass");
  EXPECT_EQ(s.apparatus[0].kind, "sandglass");
  // A table named after its kind gets no type written in (its runs' inputs, and
  // so their hashes, are what they were before setups had names).
  EXPECT_FALSE(s.resolved["apparatus"]["sandglass"]["type"]);
  EXPECT_DOUBLE_EQ(*s.resolved["apparatus"]["orifice_24mm"]["orifice_diameter_m"].value<double>(), 0.024);
  const std::string bad = replace(text, "type = \"sandglass\"", "type = \"hourglass\"");
  expect_error(bad, {at_line(bad, "type = \"hourglass\""), "apparatus.orifice_24mm.type", "\"sandglass\""});
  const std::string untyped = replace(text, "type = \"sandglass\"\n", "");
  expect_error(untyped, {"apparatus.orifice_24mm", "type = \"<kind>\""});
}

TEST(StudyConfigTest, MissingDimensionIsAnError) {
  const std::string text = replace(kStudy, "drop_height_m = 0.08\n", "");
  expect_error(text, {at_line(text, "[apparatus.sandglass]"), "apparatus.sandglass.drop_height_m",
                      "missing required key"});
  // A container needs its thickness in one of two forms.
  const std::string thin = replace(kStudy, "thickness_diameters = 4.0\n", "");
  expect_error(thin, {"apparatus.rectangular_container.thickness_m", "thickness_diameters"});
}

// Found by the study_toml fuzzer: a slice 4.8e57 diameters thick once overflowed
// the fill lattice's site count (undefined behaviour); it must be a ConfigError.
TEST(StudyConfigTest, AnAbsurdlyLargeFillRegionIsAnErrorNotAnOverflow) {
  const std::string text = replace(kStudy, "slice_thickness_diameters = 4.2",
                                   "slice_thickness_diameters = 4.8e57");
  expect_error(text, {"apparatus.sandglass", "lattice spacings", "check the apparatus' lengths"});
}

TEST(StudyConfigTest, OutOfRangeValueIsAnError) {
  const std::string text =
      replace(kStudy, "orifice_diameter_m = 0.02", "orifice_diameter_m = -0.01");
  expect_error(text, {at_line(text, "orifice_diameter_m = -0.01"),
                      "apparatus.sandglass.orifice_diameter_m", "expected a number > 0",
                      "got -0.01"});
  // The same through --set, which the message names.
  expect_error(kStudy,
               {at_line(kStudy, "orifice_diameter_m"), "apparatus.sandglass.orifice_diameter_m",
                "(from --set apparatus.sandglass.orifice_diameter_m=-0.01)"},
               {"apparatus.sandglass.orifice_diameter_m=-0.01"});
}

TEST(StudyConfigTest, FillTheGeometryCannotHoldIsRefusedBeforeAnythingRuns) {
  const std::string text = replace(kStudy, "fill_mass_kg = 0.31", "fill_mass_kg = 5.0");
  expect_error(text, {at_line(text, "fill_mass_kg = 5.0"), "apparatus.sandglass.fill_mass_kg",
                      "cannot hold the fill"});
  // A refusal that names no key of the table is reported at the table.
  const std::string thin = replace(kStudy, "thickness_diameters = 4.0", "thickness_diameters = 3.0");
  expect_error(thin, {at_line(thin, "[apparatus.rectangular_container]"),
                      "apparatus.rectangular_container: rectangular_container: the thickness"});
}

TEST(StudyConfigTest, MaterialAndInteractionAreCheckedAtTheirKeys) {
  const std::string text = replace(kStudy, "poisson_ratio = 0.25", "poisson_ratio = 0.7");
  expect_error(text, {at_line(text, "poisson_ratio = 0.7"), "material.poisson_ratio"});
  const std::string no_wall = without_table(kStudy, "[interaction.particle_wall]");
  expect_error(no_wall, {"interaction.particle_wall", "missing"});
}

TEST(StudyConfigTest, UnknownApparatusNameListsTheDefinedOnes) {
  StudyConfig s = build(kStudy);
  try {
    select_apparatus(s, std::string("hopper"));
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    for (const char* p : {"study.toml", "--apparatus hopper", "\"sandglass\"", "\"conical_pile\"",
                          "\"rectangular_container\""})
      EXPECT_NE(msg.find(p), std::string::npos) << "message lacks " << p << ": " << msg;
  }
  EXPECT_EQ(select_apparatus(s, std::string("conical_pile")).name, "conical_pile");
}

TEST(StudyConfigTest, TwoApparatusWithoutAChoiceIsAnError) {
  StudyConfig s = build(without_table(kStudy, "[apparatus.rectangular_container]"));
  ASSERT_EQ(s.apparatus.size(), 2u);
  try {
    select_apparatus(s, std::nullopt);
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    for (const char* p : {"study.toml", "\"sandglass\"", "\"conical_pile\"", "--apparatus"})
      EXPECT_NE(msg.find(p), std::string::npos) << "message lacks " << p << ": " << msg;
  }
  // With exactly one defined, that one is run.
  StudyConfig one = build(without_table(without_table(kStudy, "[apparatus.rectangular_container]"),
                                        "[apparatus.conical_pile]"));
  EXPECT_EQ(select_apparatus(one, std::nullopt).name, "sandglass");
}

TEST(StudyConfigTest, MuSAndMuRAliasesSetTheParticleParticleFrictions) {
  StudyConfig s = build(kStudy, {"mu_s=0.61", "mu_r = 0.12"});
  EXPECT_DOUBLE_EQ(s.material.particle_particle.sliding_friction, 0.61);
  EXPECT_DOUBLE_EQ(s.material.particle_particle.rolling_friction, 0.12);
  // Particle-wall coefficients are not what the aliases name.
  EXPECT_DOUBLE_EQ(s.material.particle_wall.sliding_friction, 0.5);
  EXPECT_EQ(s.resolved["interaction"]["particle_particle"]["sliding_friction"].value<double>(),
            0.61);
  // An error in an aliased value names the option as the user typed it.
  expect_error(kStudy,
               {"interaction.particle_particle.sliding_friction", "(from --set mu_s=-0.1)"},
               {"mu_s=-0.1"});
}

TEST(StudyConfigTest, ApparatusOverridesTakeEffect) {
  StudyConfig s = build(kStudy, {"apparatus.sandglass.orifice_diameter_m=0.025"});
  EXPECT_EQ(s.resolved["apparatus"]["sandglass"]["orifice_diameter_m"].value<double>(), 0.025);
  expect_error(kStudy, {"apparatus.sandglass.orifice_width_m", "unknown key"},
               {"apparatus.sandglass.orifice_width_m=0.01"});
}

// --- the command ---

std::filesystem::path temp_dir(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("demcal_study_test_" + std::to_string(::getpid()) + "_" + name);
}

struct TempDir {
  explicit TempDir(const std::string& name) : path(temp_dir(name)) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  std::filesystem::path path;
};

TEST(StudyCommandTest, RefusesAnExistingRunRecordAndUnknownApparatusBeforeRunning) {
  TempDir dir("refuse");
  const std::filesystem::path study = dir.path / "study.toml";
  std::ofstream(study) << kStudy;
  std::ostringstream sink;
  SimulateOptions o;
  o.config = study;
  o.output_dir = (dir.path / "out").string();
  o.apparatus = "sandglass";
  std::filesystem::create_directories(dir.path / "out");
  std::ofstream(dir.path / "out" / "run.json") << "{}\n";
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_THROW(simulate(o, sink, sink), ConfigError);
  o.apparatus = "hopper";
  EXPECT_THROW(simulate(o, sink, sink), ConfigError);
  o.apparatus.reset();  // three defined, none chosen
  EXPECT_THROW(simulate(o, sink, sink), ConfigError);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
}

// The one run: a container of a few hundred coarse grains, a few seconds. Its pile must
// give an angle whatever the seed, since a change of the engine's rounding acts as a new
// seed: 0.012 kg in a 0.1 m box (until 2026-12-05) gave a heap too flat to fit in 6 of
// seeds 1-16; 0.02 kg in 0.14 m gave an angle for all 16 (14.4-17.8 deg).
TEST(StudyCommandTest, ContainerRunWritesObservablesSeriesAndDetails) {
  TempDir dir("run");
  const std::filesystem::path study = dir.path / "study.toml";
  std::ofstream(study) << kStudy;
  std::ostringstream out, progress;
  SimulateOptions o;
  o.config = study;
  o.output_dir = (dir.path / "out").string();
  o.apparatus = "rectangular_container";
  o.overrides = {"apparatus.rectangular_container.fill_mass_kg=0.02",
                 "apparatus.rectangular_container.width_m=0.14", "output.vtk=true"};
  const SimulateOutcome outcome = simulate(o, out, progress);
  ASSERT_TRUE(std::filesystem::exists(outcome.run_record));
  std::ifstream in(outcome.run_record);
  const nlohmann::json r = nlohmann::json::parse(in);
  EXPECT_EQ(r["apparatus"], "rectangular_container");
  EXPECT_EQ(r["seed"], 3);
  EXPECT_EQ(r["results"]["stopped_because"], "finished");
  EXPECT_GT(r["results"]["particles"].get<int>(), 100);
  EXPECT_GT(r["results"]["particle_steps"].get<double>(), 0.0);
  EXPECT_GT(r["results"]["wall_time_s"].get<double>(), 0.0);
  for (const std::string& name : stable_observable_names())
    EXPECT_TRUE(r["observables"].contains(name)) << name;
  EXPECT_TRUE(r["observables"]["discharge_time_s"].is_null());
  EXPECT_TRUE(r["observables"]["angle_of_repose_deg"].is_number()) << r["details"].dump();
  EXPECT_TRUE(r["series"].contains("pile"));
  EXPECT_EQ(r["details"]["boundary"], "periodic");
  EXPECT_EQ(r["inputs"]["apparatus"].size(), 1u);
  EXPECT_EQ(r["inputs"]["apparatus"]["rectangular_container"]["fill_mass_kg"], 0.02);
  EXPECT_GE(r["outputs"]["snapshots"].get<int>(), 1);
  EXPECT_TRUE(std::filesystem::exists(dir.path / "out" / "particles.pvd"));
  const std::string printed = out.str();
  EXPECT_NE(printed.find("angle_of_repose_deg = "), std::string::npos) << printed;
  EXPECT_NE(printed.find("discharge_time_s = null"), std::string::npos) << printed;
  EXPECT_NE(printed.find("run record: "), std::string::npos) << printed;
}

TEST(StudyCommandTest, ApparatusOptionOnAPlainConfigIsAnError) {
  SimulateOptions o;
  o.config = std::filesystem::path(DEMCAL_SOURCE_DIR) / "studies" / "poured-pile" / "study.toml";
  o.apparatus = "sandglass";
  o.output_dir = temp_dir("plain").string();
  std::ostringstream sink;
  try {
    simulate(o, sink, sink);
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--apparatus"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(temp_dir("plain")));
}

}  // namespace
}  // namespace demcal::cli
