// The TOML config reader: a valid config builds the simulation it describes,
// and every kind of mistake is a ConfigError that points at file, line and key.

#include "config/simulation_config.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace demcal::cli {
namespace {

using namespace demcal::config;

// Small enough to step in a unit test: 20 grains filled at t = 0 above a floor.
const char* const kMinimal = R"(# minimal config
[simulation]
name = "mini"

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

[[material]]
name = "steel"
density_kg_m3 = 7800
shear_modulus_pa = 7.9e10
poisson_ratio = 0.29

[[interaction]]
materials = ["grain", "grain"]
restitution = 0.6
sliding_friction = 0.5
rolling_friction = 0.1

[[interaction]]
materials = ["grain", "steel"]
restitution = 0.5
sliding_friction = 0.9
rolling_friction = 0.3

[[wall]]
name = "floor"
type = "plane"
material = "steel"
point_m = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]

[[insertion]]
type = "fill"
material = "grain"
count = 20
size = { distribution = "uniform", min_diameter_m = 1.0e-3, max_diameter_m = 1.5e-3 }
region = { shape = "box", lower_m = [0.001, 0.001, 0.005], upper_m = [0.019, 0.019, 0.03] }

[run]
end_time_s = 0.01
)";

// Writes a config into the system temp directory (never the repository).
class TempConfig {
 public:
  TempConfig(const std::string& name, const std::string& text)
      : path_(std::filesystem::temp_directory_path() /
              ("demcal_test_" + std::to_string(::getpid()) + "_" + name + ".toml")) {
    std::ofstream(path_) << text;
  }
  ~TempConfig() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }
  std::string file_name() const { return path_.filename().string(); }

 private:
  std::filesystem::path path_;
};

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test setup: \"" << from << "\" not in the config";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// 1-based number of the first line containing `needle`.
std::size_t line_of(const std::string& text, const std::string& needle) {
  std::istringstream in(text);
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n)
    if (line.find(needle) != std::string::npos) return n;
  ADD_FAILURE() << "test setup: \"" << needle << "\" not in the config";
  return 0;
}

// Loads `text` and expects a ConfigError naming the file, "<file>:<line>:" and the key.
std::string expect_config_error(const std::string& name, const std::string& text, std::size_t line,
                                const std::string& key,
                                const std::vector<std::string>& overrides = {}) {
  TempConfig cfg(name, text);
  try {
    load_simulation_config(cfg.path(), overrides);
    ADD_FAILURE() << name << ": expected a ConfigError naming " << key;
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(cfg.file_name() + ":" + std::to_string(line) + ":"), std::string::npos)
        << "message lacks file:line " << cfg.file_name() << ":" << line << ": " << msg;
    EXPECT_NE(msg.find(key), std::string::npos) << "message lacks the key " << key << ": " << msg;
    return msg;
  }
  return {};
}

TEST(ConfigTest, MinimalConfigBuildsTheSimulation) {
  TempConfig cfg("minimal", kMinimal);
  SimulationConfig sc = load_simulation_config(cfg.path(), {});
  ASSERT_NE(sc.simulation, nullptr);
  dem::Simulation& sim = *sc.simulation;
  EXPECT_EQ(sc.name, "mini");
  EXPECT_EQ(sim.materials().size(), 2u);
  EXPECT_EQ(sim.walls().size(), 1u);
  EXPECT_EQ(sim.inserters().size(), 1u);
  EXPECT_EQ(sc.wall_names, std::vector<std::string>{"floor"});
  EXPECT_EQ(sim.walls()[0]->type_name(), "plane");
  EXPECT_DOUBLE_EQ(sim.materials()[1].shear_modulus_pa, 7.9e10);
  EXPECT_DOUBLE_EQ(sc.run.end_time_s, 0.01);
  EXPECT_TRUE(sc.run.stop_at_rest);
  EXPECT_EQ(sc.output.directory, std::filesystem::path("out/mini"));
  EXPECT_EQ(sim.options().threads, 1);
  EXPECT_EQ(sim.options().seed, 1u);
  EXPECT_DOUBLE_EQ(sim.options().gravity_m_s2.z, -9.81);
  // Defaults are written into the resolved config (it goes into run.json).
  EXPECT_EQ(sc.resolved["simulation"]["seed"].value<std::int64_t>(), 1);
  EXPECT_EQ(sc.resolved["contact"]["adhesion"].value<std::string>(), "none");
  EXPECT_EQ(sc.resolved["output"]["directory"].value<std::string>(), "out/mini");
  EXPECT_DOUBLE_EQ(*sc.resolved["interaction"][0]["rolling_damping_ratio"].value<double>(), 0.3);
  EXPECT_EQ(sc.resolved["wall"][0]["velocity_m_s"].as_array()->size(), 3u);
  // The fill happens at t = 0, on the first step.
  sim.step();
  EXPECT_EQ(sim.particles().size(), 20u);
  EXPECT_EQ(sim.inserters()[0]->inserted(), 20u);
}

TEST(ConfigTest, UnknownKeyIsAnError) {
  const std::string text = replace(kMinimal, "rolling_friction = 0.3\n",
                                   "rolling_friction = 0.3\nslding_friction = 0.4\n");
  const std::string msg = expect_config_error("unknown_key", text, line_of(text, "slding_friction"),
                                              "interaction[1].slding_friction");
  EXPECT_NE(msg.find("unknown key"), std::string::npos) << msg;
}

TEST(ConfigTest, UnknownTopLevelTableIsAnError) {
  const std::string text = std::string(kMinimal) + "\n[outptu]\nvtk = false\n";
  expect_config_error("unknown_table", text, line_of(text, "[outptu]"), "outptu");
}

TEST(ConfigTest, MissingRequiredKeyIsAnError) {
  const std::string text = replace(kMinimal, "end_time_s = 0.01\n", "stop_at_rest = false\n");
  const std::string msg =
      expect_config_error("missing_key", text, line_of(text, "[run]"), "run.end_time_s");
  EXPECT_NE(msg.find("missing"), std::string::npos) << msg;
}

TEST(ConfigTest, WrongTypeIsAnError) {
  const std::string text = replace(kMinimal, "density_kg_m3 = 7800", "density_kg_m3 = \"heavy\"");
  const std::string msg = expect_config_error("wrong_type", text, line_of(text, "\"heavy\""),
                                              "material[1].density_kg_m3");
  EXPECT_NE(msg.find("expected a number > 0, got \"heavy\" (a string)"), std::string::npos) << msg;
}

TEST(ConfigTest, OutOfRangeValueIsAnError) {
  const std::string text = replace(kMinimal, "sliding_friction = 0.9", "sliding_friction = -0.2");
  const std::string msg = expect_config_error("out_of_range", text, line_of(text, "-0.2"),
                                              "interaction[1].sliding_friction");
  EXPECT_NE(msg.find("expected a number >= 0, got -0.2"), std::string::npos) << msg;
}

TEST(ConfigTest, UnknownMaterialInAnInteractionIsAnError) {
  const std::string text =
      replace(kMinimal, "materials = [\"grain\", \"steel\"]", "materials = [\"grain\", \"stone\"]");
  const std::string msg = expect_config_error("unknown_material", text, line_of(text, "\"stone\""),
                                              "interaction[1].materials");
  EXPECT_NE(msg.find("\"stone\""), std::string::npos) << msg;
  EXPECT_NE(msg.find("\"steel\""), std::string::npos) << "lists the defined materials: " << msg;
}

TEST(ConfigTest, UnknownContactPartIsAnErrorListingTheKnownOnes) {
  const std::string text = replace(kMinimal, "rolling = \"epsd\"", "rolling = \"spring\"");
  const std::string msg =
      expect_config_error("unknown_part", text, line_of(text, "\"spring\""), "contact.rolling");
  for (const auto& name : dem::known_part_names("rolling"))
    EXPECT_NE(msg.find("\"" + name + "\""), std::string::npos) << name << " not listed: " << msg;
}

TEST(ConfigTest, MissingInteractionForATouchingPairIsAnError) {
  const std::string text =
      replace(kMinimal, "materials = [\"grain\", \"steel\"]", "materials = [\"steel\", \"steel\"]");
  const std::string msg = expect_config_error(
      "missing_pair", text, line_of(text, "material = \"steel\""), "wall[0].material");
  EXPECT_NE(msg.find("no [[interaction]]"), std::string::npos) << msg;
}

TEST(ConfigTest, EngineConstructorErrorsPointAtTheirTable) {
  // Openings must increase; the size distribution's constructor rejects this.
  const std::string text = replace(
      kMinimal,
      "size = { distribution = \"uniform\", min_diameter_m = 1.0e-3, max_diameter_m = 1.5e-3 }",
      "size = { distribution = \"sieve\", sieve = [[1.5e-3, 0.0], [1.0e-3, 1.0]] }");
  expect_config_error("engine_error", text, line_of(text, "sieve = "), "insertion[0].size");
}

TEST(ConfigTest, SyntaxErrorNamesFileAndLine) {
  const std::string text = replace(kMinimal, "end_time_s = 0.01", "end_time_s = = 0.01");
  TempConfig cfg("syntax", text);
  try {
    load_simulation_config(cfg.path(), {});
    ADD_FAILURE() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(cfg.file_name() + ":" +
                                         std::to_string(line_of(text, "= = 0.01")) + ":"),
              std::string::npos)
        << e.what();
  }
}

TEST(ConfigTest, OverridesTakeEffect) {
  TempConfig cfg("overrides", kMinimal);
  SimulationConfig sc = load_simulation_config(
      cfg.path(),
      {"interaction.grain-grain.sliding_friction=0.4", "interaction[1].restitution=0.7",
       "material.grain.density_kg_m3=1000", "simulation.seed=7", "domain.upper_m[2]=0.05",
       "output.directory=results/x", "run.stop_at_rest=false", "wall.floor.point_m=[0, 0, 0.001]",
       "simulation.restitution_model=linear_spring_formula"});
  const dem::Simulation& sim = *sc.simulation;
  EXPECT_DOUBLE_EQ(*sc.resolved["interaction"][0]["sliding_friction"].value<double>(), 0.4);
  EXPECT_DOUBLE_EQ(*sc.resolved["interaction"][1]["restitution"].value<double>(), 0.7);
  EXPECT_DOUBLE_EQ(sim.materials()[0].density_kg_m3, 1000.0);
  EXPECT_EQ(sim.options().seed, 7u);
  EXPECT_DOUBLE_EQ(sim.options().domain.upper_m.z, 0.05);
  EXPECT_EQ(sc.output.directory, std::filesystem::path("results/x"));
  EXPECT_FALSE(sc.run.stop_at_rest);
  EXPECT_EQ(sim.options().restitution_model, dem::RestitutionModel::kLinearSpringFormula);
  dem::WallContactPoint cp;
  ASSERT_TRUE(sim.walls()[0]->nearest_point({0.01, 0.01, 0.002}, 1.0, 0.0, cp));
  EXPECT_NEAR(cp.distance_m, 0.001, 1e-12);
}

TEST(ConfigTest, OverrideOfAnUnknownKeyIsAnError) {
  // Into an existing table: reported by the strict build, at that table's line.
  std::string msg = expect_config_error("set_unknown", kMinimal, line_of(kMinimal, "[run]"),
                                        "run.end_tme_s", {"run.end_tme_s=1"});
  EXPECT_NE(msg.find("--set run.end_tme_s=1"), std::string::npos) << msg;
  // Index out of range.
  msg = expect_config_error("set_index", kMinimal, line_of(kMinimal, "[[interaction]]"),
                            "interaction[5]", {"interaction[5].sliding_friction=0.3"});
  EXPECT_NE(msg.find("--set interaction[5].sliding_friction=0.3"), std::string::npos) << msg;
  // A selector that matches nothing.
  msg = expect_config_error("set_selector", kMinimal, line_of(kMinimal, "[[material]]"),
                            "material.clay", {"material.clay.density_kg_m3=1000"});
  EXPECT_NE(msg.find("\"grain\""), std::string::npos) << "lists the selectors: " << msg;
  // An out-of-range value given by --set points at the key it replaced.
  msg = expect_config_error("set_range", kMinimal, line_of(kMinimal, "sliding_friction = 0.9"),
                            "interaction[1].sliding_friction",
                            {"interaction.steel-grain.sliding_friction=-1"});
  EXPECT_NE(msg.find("(from --set interaction.steel-grain.sliding_friction=-1)"), std::string::npos)
      << msg;
}

TEST(ConfigTest, OverrideValuesAreParsedAsToml) {
  ConfigDocument doc = parse_config_string(kMinimal, "inline.toml");
  apply_override(doc, "simulation.name=pile-2");  // a bare word is a string
  apply_override(doc, "domain.periodic=[true, false, false]");
  apply_override(doc, "insertion[0].size={distribution=\"monodisperse\", diameter_m=1.2e-3}");
  SimulationConfig sc = build_simulation(std::move(doc));
  EXPECT_EQ(sc.name, "pile-2");
  EXPECT_TRUE(sc.simulation->options().domain.periodic[0]);
  EXPECT_DOUBLE_EQ(sc.simulation->inserters()[0]->sizes().max_diameter_m(), 1.2e-3);

  ConfigDocument bad = parse_config_string(kMinimal, "inline.toml");
  EXPECT_THROW(apply_override(bad, "simulation.seed"), ConfigError);       // no '='
  EXPECT_THROW(apply_override(bad, "domain.upper_m=[1, 2"), ConfigError);  // not TOML
  EXPECT_THROW(apply_override(bad, "simulation..seed=1"), ConfigError);    // empty key
}

}  // namespace
}  // namespace demcal::cli
