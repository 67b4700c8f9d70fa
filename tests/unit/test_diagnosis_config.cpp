// The [diagnosis] table and the candidate registry of `demcal diagnose`: bad
// input is refused with the file, line and key before anything runs, and every
// candidate's switches and keys are ones a study accepts.

#include "config/design_config.hpp"
#include "config/physics_candidates.hpp"
#include "config/study_config.hpp"
#include "config/toml_reader.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace demcal::cli {
namespace {

using namespace demcal::config;

std::string tiny_study() {
  std::ifstream in(std::filesystem::path(DEMCAL_SOURCE_DIR) / "tests/data/doe-tiny/study.toml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

StudyConfig build(const std::string& text, const std::vector<std::string>& overrides = {}) {
  ConfigDocument doc = parse_config_string(text, "diag.toml");
  for (const auto& o : overrides) apply_override(doc, o, study_override_aliases());
  return build_study(std::move(doc));
}

std::string error_of(const std::string& text) {
  try {
    build(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(DiagnosisConfig, DefaultsAndOverridesAreRead) {
  const StudyConfig s = build(tiny_study() +
                              "\n[diagnosis]\nalpha = 0.05\nleading = 1\n"
                              "[diagnosis.cohesion]\nupper = 0.01\nprobe = 0.004\n");
  ASSERT_TRUE(s.diagnosis);
  EXPECT_EQ(s.diagnosis->candidates, physics_candidate_names());
  EXPECT_DOUBLE_EQ(s.diagnosis->alpha, 0.05);
  EXPECT_EQ(s.diagnosis->leading, 1);
  EXPECT_EQ(s.diagnosis->probe_grid, 200);
  EXPECT_EQ(s.diagnosis->design_extensions, 2);
  EXPECT_EQ(
      build(tiny_study() + "\n[diagnosis]\ndesign_extensions = 0\n").diagnosis->design_extensions,
      0);
  EXPECT_EQ(s.diagnosis->candidate_refinements, 0);
  EXPECT_EQ(build(tiny_study() + "\n[diagnosis]\ncandidate_refinements = 2\n")
                .diagnosis->candidate_refinements,
            2);
  EXPECT_DOUBLE_EQ(*s.diagnosis->ranges.at("cohesion").upper, 0.01);
  EXPECT_DOUBLE_EQ(*s.diagnosis->ranges.at("cohesion").probe, 0.004);
  // [diagnosis] does not enter a run's inputs (so not its hash).
  EXPECT_FALSE(resolved_for(s, "rectangular_container")["diagnosis"]);
}

// [diagnosis.plausible]: per design parameter, the material's [lower, upper]; it must hold
// the design's box, and a study without a design has nothing to bound.
TEST(DiagnosisConfig, PlausibleRangesAreReadPerDesignParameter) {
  const StudyConfig s = build(tiny_study() + "\n[diagnosis.plausible]\nmu_r = [0.0, 1.0]\n");
  ASSERT_TRUE(s.diagnosis);
  ASSERT_EQ(s.diagnosis->plausible.size(), 1u);
  EXPECT_DOUBLE_EQ(s.diagnosis->plausible.at("mu_r").first, 0.0);
  EXPECT_DOUBLE_EQ(s.diagnosis->plausible.at("mu_r").second, 1.0);
  EXPECT_TRUE(build(tiny_study() + "\n[diagnosis]\nalpha = 0.05\n").diagnosis->plausible.empty());

  std::string without_design = tiny_study();
  const auto from = without_design.find("[design]");
  ASSERT_NE(from, std::string::npos);
  const auto to = without_design.find("\n[", from + 1);
  without_design.erase(from, to == std::string::npos ? std::string::npos : to + 1 - from);
  const std::string m = error_of(without_design + "\n[diagnosis.plausible]\nmu_r = [0.0, 1.0]\n");
  EXPECT_NE(m.find("diagnosis.plausible"), std::string::npos) << m;
  EXPECT_NE(m.find("no [design]"), std::string::npos) << m;
}

TEST(DiagnosisConfig, BadInputNamesTheKey) {
  std::string m = error_of(tiny_study() + "\n[diagnosis]\ncandidates = [\"gravity\"]\n");
  EXPECT_NE(m.find("diagnosis.candidates"), std::string::npos) << m;
  EXPECT_NE(m.find("\"cohesion\""), std::string::npos) << m;
  m = error_of(tiny_study() + "\n[diagnosis]\nhold_out = [\"hopper\"]\n");
  EXPECT_NE(m.find("diagnosis.hold_out"), std::string::npos) << m;
  m = error_of(tiny_study() + "\n[diagnosis]\nhold_out = [\"rectangular_container\"]\n");
  EXPECT_NE(m.find("holds out every setup"), std::string::npos) << m;
  m = error_of(tiny_study() + "\n[diagnosis]\nalpha = 0.7\n");
  EXPECT_NE(m.find("diagnosis.alpha"), std::string::npos) << m;
  m = error_of(tiny_study() + "\n[diagnosis.cohesion]\nlower = 0.01\nupper = 0.001\n");
  EXPECT_NE(m.find("diagnosis.cohesion.upper"), std::string::npos) << m;
  m = error_of(tiny_study() + "\n[diagnosis]\nprobe_grid = 1\n");
  EXPECT_NE(m.find("diagnosis.probe_grid"), std::string::npos) << m;
  m = error_of(tiny_study() + "\n[diagnosis]\ndesign_extensions = 11\n");
  EXPECT_NE(m.find("diagnosis.design_extensions"), std::string::npos) << m;
  m = error_of(tiny_study() + "\n[diagnosis]\ndesign_extensions = 1.5\n");
  EXPECT_NE(m.find("diagnosis.design_extensions"), std::string::npos) << m;
  m = error_of(tiny_study() + "\n[diagnosis]\ncandidate_refinements = 6\n");
  EXPECT_NE(m.find("diagnosis.candidate_refinements"), std::string::npos) << m;
  m = error_of(tiny_study() + "\n[diagnosis]\ncandidate_refinements = -1\n");
  EXPECT_NE(m.find("diagnosis.candidate_refinements"), std::string::npos) << m;
  m = error_of(tiny_study() + "\n[diagnosis]\ncolour = 1\n");
  EXPECT_NE(m.find("diagnosis.colour: unknown key"), std::string::npos) << m;
}

TEST(PhysicsCandidates, EverySwitchAndKeyIsAcceptedByAStudy) {
  // The size spread needs the mean form of the size distribution.
  std::string text = tiny_study();
  const std::string minmax =
      "size = { distribution = \"uniform\", min_diameter_m = 3.0e-4, max_diameter_m = 6.0e-4 }";
  ASSERT_NE(text.find(minmax), std::string::npos);
  text.replace(text.find(minmax), minmax.size(),
               "size = { distribution = \"uniform\", mean_diameter_m = 4.5e-4, relative_half_width "
               "= 0.333 }");
  for (const auto& c : physics_candidates()) {
    SCOPED_TRACE(c.name);
    std::vector<std::string> overrides;
    for (const auto& [k, v] : c.switches) overrides.push_back(k + "=\"" + v + "\"");
    for (const auto& k : c.keys) {
      std::ostringstream s;
      s << k << "=" << (c.lower + c.upper) / 2;
      overrides.push_back(s.str());
    }
    EXPECT_NO_THROW(build(text, overrides));
    EXPECT_LT(c.lower, c.upper);
    if (c.off_value) {
      EXPECT_GE(*c.off_value, c.lower);
      EXPECT_LE(*c.off_value, c.upper);
      EXPECT_NE(c.probe, *c.off_value);
    }
  }
}

TEST(PhysicsCandidates, AirDragIsOneWhoseDerivedStudyBuildsWithoutAnAirTable) {
  const PhysicsCandidate* c = find_physics_candidate("air_drag");
  ASSERT_NE(c, nullptr);
  ASSERT_TRUE(c->off_value);
  EXPECT_EQ(*c->off_value, 0.0);
  EXPECT_EQ(c->parameter, "drag_scale");
  EXPECT_EQ(c->keys, std::vector<std::string>{"air.drag_scale"});
  const std::vector<std::pair<std::string, std::string>> on = {{"air.drag", "schiller_naumann"}};
  EXPECT_EQ(c->switches, on);
  EXPECT_EQ(c->lower, 0.0);
  EXPECT_EQ(c->upper, 3.0);
  EXPECT_EQ(c->probe, 1.5);
  // What diagnose's derived_study() writes for a probe: the study (here one
  // without [air]) with the switch and the key set at "off" as set_config_value
  // does, and a list design over (mu_r, the candidate's key).
  ASSERT_EQ(tiny_study().find("[air]"), std::string::npos);
  ConfigDocument doc = parse_config_string(tiny_study(), "diag.toml");
  for (const char* k : {"design", "calibration", "diagnosis", "output"}) doc.table.erase(k);
  for (const auto& [key, value] : c->switches)
    set_config_value(doc, key, toml::value<std::string>(value), "diagnosis air_drag");
  for (const auto& key : c->keys)
    set_config_value(doc, key, toml::value<double>(*c->off_value), "diagnosis air_drag");
  std::ostringstream text;
  text << toml::toml_formatter(doc.table) << "\n\n[design]\nkind = \"list\"\nreplicates = 1\n"
       << "values = [[0.25, " << shortest_decimal(c->probe)
       << "]]\nparameters = { mu_r = { lower = 0.1, "
       << "upper = 0.4 }, " << toml_key_text(c->keys.front())
       << " = { lower = " << shortest_decimal(c->lower)
       << ", upper = " << shortest_decimal(c->upper) << " } }\n";
  const StudyConfig derived = build(text.str());
  ASSERT_TRUE(derived.material.air_drag.has_value()) << text.str();
  EXPECT_EQ(derived.material.air_drag->drag_scale, 0.0);
  ASSERT_TRUE(derived.design.has_value());
  EXPECT_EQ(derived.design->parameter_paths.back(), "air.drag_scale");
  const StudySource source{"diag.toml", text.str(), {}};
  EXPECT_NO_THROW(check_design_bounds(source, *derived.design));
  ConfigDocument probe = source.document();
  apply_design_values(probe, *derived.design, {0.25, c->probe}, "design point 0");
  const StudyConfig at_probe = build_study(std::move(probe));
  ASSERT_TRUE(at_probe.material.air_drag.has_value());
  EXPECT_EQ(at_probe.material.air_drag->drag_scale, 1.5);
  // build_study built the apparatus, and with it the AirDrag (which validates the scale).
  ASSERT_FALSE(at_probe.apparatus.empty());
  EXPECT_NE(at_probe.apparatus.front().apparatus, nullptr);
}

}  // namespace
}  // namespace demcal::cli
