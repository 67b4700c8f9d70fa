// Contact parts declare their own parameters (dem/contact/part_parameter.hpp):
// the registry holds each key once and each slot once, the readers, the range
// check, coarse graining and `demcal schema` take them from it, a part's keys
// absent leave the resolved config (and so the run key) as it was, and the
// liquid bridge -- one file plus one registration -- reaches the engine from a
// study config.

#include "config/physics_candidates.hpp"
#include "config/schema.hpp"
#include "config/study_config.hpp"
#include "dem/contact/contact_law.hpp"
#include "study/run_store.hpp"
#include "tests/support/study_text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

namespace demcal::config {
namespace {

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

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test setup: \"" << from << "\" not in the text";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

StudyConfig build(const std::string& text, const std::vector<std::string>& overrides = {}) {
  ConfigDocument doc = parse_config_string(text, "study.toml");
  for (const auto& o : overrides) apply_override(doc, o, study_override_aliases());
  return build_study(std::move(doc));
}

const std::string kWet = replace(
    replace(kStudy, "rolling = \"cdt\"\n", "rolling = \"cdt\"\nadhesion = \"liquid_bridge\"\n"),
    "sliding_friction = 0.52\n", "sliding_friction = 0.52\nsurface_tension_n_m = 0.002\n");

TEST(ContactPartParameters, EachKeyAndSlotIsDeclaredOnce) {
  std::set<std::string> keys;
  std::set<int> slots;
  for (const dem::RegisteredPartParameter& r : dem::registered_part_parameters()) {
    EXPECT_TRUE(keys.insert(r.parameter.key).second) << r.parameter.key;
    if (r.parameter.legacy_field == nullptr) {
      EXPECT_TRUE(slots.insert(r.parameter.slot).second) << r.parameter.key;
    }
    EXPECT_TRUE(r.parameter.accepts(r.parameter.default_value)) << r.parameter.key;
  }
  for (const char* k : {"surface_energy_j_m2", "surface_tension_n_m", "contact_angle_deg",
                        "liquid_bridge_volume_fraction"})
    EXPECT_TRUE(keys.count(k)) << k;
}

TEST(ContactPartParameters, AbsentKeysLeaveRunKeysAsTheyWere) {
  const StudyConfig dry = build(kStudy);
  for (const char* k : {"surface_tension_n_m", "contact_angle_deg", "liquid_bridge_volume_fraction"})
    EXPECT_FALSE(dry.resolved["interaction"]["particle_particle"][k]) << k;
  // The hash test_physics_module_keys pins for this very study (key_version 2).
  EXPECT_EQ(study::run_key_for(dry, "rectangular_container", 1, 1).hash, "d664089c3b80de5a");
  // Given at the part's default: accepted without the part, and in the key.
  const StudyConfig zero = build(kStudy, {"interaction.particle_particle.surface_tension_n_m=0"});
  EXPECT_NE(study::run_key_for(zero, "rectangular_container", 1, 1).hash, "d664089c3b80de5a");
}

TEST(ContactPartParameters, TheLiquidBridgeReachesTheEngineFromAStudy) {
  const StudyConfig s = build(kWet, {"interaction.particle_wall.contact_angle_deg=30"});
  EXPECT_EQ(s.material.contact.adhesion, "liquid_bridge");
  const auto& pp = s.material.particle_particle.part_values;
  const auto& pw = s.material.particle_wall.part_values;
  EXPECT_DOUBLE_EQ(pp[dem::liquid_bridge::kSurfaceTensionSlot], 0.002);
  EXPECT_DOUBLE_EQ(pp[dem::liquid_bridge::kVolumeFractionSlot], 1e-3);  // the default
  EXPECT_DOUBLE_EQ(pw[dem::liquid_bridge::kSurfaceTensionSlot], 0.0);   // dry walls
  EXPECT_DOUBLE_EQ(pw[dem::liquid_bridge::kContactAngleSlot], 30.0);
  EXPECT_FALSE(s.resolved["interaction"]["particle_particle"]["contact_angle_deg"]);
  EXPECT_EQ(s.apparatus.front().apparatus->simulation().contact_law().describe(),
            "normal=hertz adhesion=liquid_bridge tangential=mindlin rolling=cdt");
}

// The constant rolling spring ("sds", dem/contact/constant_spring_rolling.hpp):
// its reference overlap per pair reaches the engine, the default elsewhere;
// given with another rolling part, or out of its range, it is refused at its key.
TEST(ContactPartParameters, TheConstantRollingSpringReachesTheEngineFromAStudy) {
  const std::string sds = replace(kStudy, "rolling = \"cdt\"\n", "rolling = \"sds\"\n");
  const StudyConfig s =
      build(sds, {"interaction.particle_particle.rolling_reference_overlap_fraction=0.002"});
  const int slot = dem::constant_spring_rolling::kReferenceOverlapSlot;
  EXPECT_DOUBLE_EQ(s.material.particle_particle.part_values[static_cast<std::size_t>(slot)], 0.002);
  EXPECT_DOUBLE_EQ(s.material.particle_wall.part_values[static_cast<std::size_t>(slot)], 0.005);
  EXPECT_EQ(s.apparatus.front().apparatus->simulation().contact_law().describe(),
            "normal=hertz adhesion=none tangential=mindlin rolling=sds");
  auto refused = [&](const std::string& text, const std::string& value,
                     const std::vector<std::string>& parts) {
    try {
      build(text, {"interaction.particle_particle.rolling_reference_overlap_fraction=" + value});
      ADD_FAILURE() << "accepted " << value;
    } catch (const ConfigError& e) {
      for (const auto& p : parts)
        EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
    }
  };
  refused(kStudy, "0.002", {"rolling_reference_overlap_fraction", "cdt"});
  refused(sds, "0", {"rolling_reference_overlap_fraction", "(0, 0.1]"});
  refused(sds, "0.5", {"rolling_reference_overlap_fraction", "(0, 0.1]"});
}

TEST(ContactPartParameters, CoarseGrainingFollowsTheDeclaredExponent) {
  for (const dem::RegisteredPartParameter& r : dem::registered_part_parameters()) {
    const double e = r.parameter.coarse_graining_exponent;
    EXPECT_DOUBLE_EQ(r.parameter.coarse_grained(0.5, 3.0), 0.5 * std::pow(3.0, e)) << r.parameter.key;
  }
  // JKR's gamma f^2 exactly as before (f * f, not pow).
  const dem::PartParameter& jkr = dem::JkrAdhesion::kParameters[0];
  EXPECT_EQ(jkr.coarse_grained(0.3, 6.1), 0.3 * (6.1 * 6.1));
}

TEST(ContactPartParameters, MoistureIsADiagnosisCandidateAStudyAccepts) {
  const PhysicsCandidate* c = find_physics_candidate("moisture");
  ASSERT_NE(c, nullptr);
  std::vector<std::string> overrides;
  for (const auto& [k, v] : c->switches) overrides.push_back(k + "=\"" + v + "\"");
  for (const auto& k : c->keys) overrides.push_back(k + "=" + std::to_string(c->probe));
  const StudyConfig s = build(kStudy, overrides);
  EXPECT_DOUBLE_EQ(s.material.particle_wall.part_values[dem::liquid_bridge::kSurfaceTensionSlot],
                   c->probe);
}

TEST(ContactPartParameters, GrainCohesionLeavesTheWallsTheirOwnSurfaceEnergy) {
  // The two cohesion candidates differ only on the walls: "cohesion" gives them the grains'
  // surface energy, "grain_cohesion" leaves them the study's (none here, and 1e-4 when the
  // study states one). The probe study is what the diagnosis runs.
  auto probed = [](const std::string& name, std::vector<std::string> overrides) {
    const PhysicsCandidate* c = find_physics_candidate(name);
    EXPECT_NE(c, nullptr) << name;
    for (const auto& [k, v] : c->switches) overrides.push_back(k + "=\"" + v + "\"");
    for (const auto& k : c->keys) overrides.push_back(k + "=" + std::to_string(c->probe));
    return std::pair{build(kStudy, overrides), c->probe};
  };
  const auto [both, probe] = probed("cohesion", {});
  EXPECT_DOUBLE_EQ(both.material.particle_particle.surface_energy_j_m2, probe);
  EXPECT_DOUBLE_EQ(both.material.particle_wall.surface_energy_j_m2, probe);
  const auto [grains, grain_probe] = probed("grain_cohesion", {});
  EXPECT_DOUBLE_EQ(grains.material.particle_particle.surface_energy_j_m2, grain_probe);
  EXPECT_DOUBLE_EQ(grains.material.particle_wall.surface_energy_j_m2, 0.0);
  const StudyConfig stated =
      probed("grain_cohesion", {"interaction.particle_wall.surface_energy_j_m2=1e-4"}).first;
  EXPECT_DOUBLE_EQ(stated.material.particle_wall.surface_energy_j_m2, 1e-4);
  EXPECT_EQ(find_physics_candidate("grain_cohesion")->off_value, 0.0);
}

TEST(Schema, ListsEveryPartWithItsKeysUnitsDefaultsAndRanges) {
  const std::string all = schema_text("");
  for (const std::string& role : dem::contact_roles())
    for (const std::string& part : dem::known_part_names(role))
      EXPECT_NE(all.find("contact." + role + " \"" + part + "\""), std::string::npos) << part;
  for (const std::string& name : physics_candidate_names())
    EXPECT_NE(all.find("diagnosis candidate \"" + name + "\""), std::string::npos) << name;
  const std::string bridge = schema_text("liquid_bridge");
  EXPECT_NE(bridge.find("surface_tension_n_m [N/m]  range [0, 1]  default 0 (absent: not written in)"),
            std::string::npos) << bridge;
  EXPECT_NE(bridge.find("contact_angle_deg [deg]  range [0, 90)"), std::string::npos) << bridge;
  EXPECT_NE(bridge.find("coarse grained as f^2"), std::string::npos) << bridge;
  EXPECT_EQ(bridge.find("jkr"), std::string::npos) << bridge;
  EXPECT_THROW(schema_text("wet_sand"), ConfigError);
}

}  // namespace
}  // namespace demcal::config
