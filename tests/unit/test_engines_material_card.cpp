// The material card (engines/material_card.hpp): golden files for every
// format, the warning when the target engine is not the calibrated one, the
// intervals carried through the mapping, and the refusals.
#include "engines/material_card.hpp"

#include "tests/support/engine_fixtures.hpp"
#include "tests/support/golden.hpp"

#include <gtest/gtest.h>

namespace demcal::engines {
namespace {

MaterialCardInput calibrated_input(const std::string& rolling = "epsd") {
  MaterialCardInput in;
  in.material = testing::peer_material(rolling);
  in.material.particle_particle.sliding_friction = 0.52;
  in.material.particle_particle.rolling_friction = 0.12;
  in.reduction.coarse_graining_factor = 2.0;
  in.reduction.shear_modulus_pa = 5e6;
  in.calibrated = {
      {"particle_particle.sliding_friction", 0.52, 0.47, 0.58},
      {"particle_particle.rolling_friction", 0.12, 0.09, 0.16},
      {"particle_particle.restitution", 0.6, CalibratedParameter::kNaN, CalibratedParameter::kNaN}};
  in.provenance.study = "sand-aor";
  in.provenance.calibrated_engine_version = "0.1.0";
  return in;
}

TEST(EnginesMaterialCard, Goldens) {
  const auto in = calibrated_input();
  for (const auto& [format, file] :
       std::vector<std::pair<CardFormat, std::string>>{{CardFormat::kLammps, "card_lammps.in"},
                                                       {CardFormat::kLiggghts, "card_liggghts.in"},
                                                       {CardFormat::kJson, "card.json"}}) {
    const auto card = write_material_card(in, format);
    ASSERT_TRUE(card.ok()) << card.refusal;
    testing::expect_golden(*card.text, "engines/" + file);
  }
  const auto edem = write_material_card(calibrated_input("cdt"), CardFormat::kEdemCsv);
  ASSERT_TRUE(edem.ok()) << edem.refusal;
  testing::expect_golden(*edem.text, "engines/card_edem.csv");
}

TEST(EnginesMaterialCard, WarnsWhenTheTargetIsNotTheCalibratedEngine) {
  auto in = calibrated_input();
  const auto lammps = *write_material_card(in, CardFormat::kLammps).text;
  EXPECT_NE(lammps.find("# WARNING: calibrated on demcal, written for LAMMPS"), std::string::npos);
  in.provenance.calibrated_engine = Engine::kLammps;
  EXPECT_EQ(write_material_card(in, CardFormat::kLammps).text->find("WARNING"), std::string::npos);
  EXPECT_NE(write_material_card(in, CardFormat::kLiggghts).text->find("WARNING"),
            std::string::npos);
}

TEST(EnginesMaterialCard, IntervalsGoThroughTheMapping) {
  const auto text = *write_material_card(calibrated_input(), CardFormat::kLammps).text;
  EXPECT_NE(text.find("particle_particle.sliding_friction = 0.52  [0.47, 0.58]"), std::string::npos)
      << text;
  EXPECT_NE(text.find("-> particle-particle mindlin mu_s 0.47 .. 0.58"), std::string::npos) << text;
  // mu_r moves the sds limit and the rolling spring.
  EXPECT_NE(text.find("-> particle-particle sds mu_r 0.09 .. 0.16"), std::string::npos) << text;
  EXPECT_NE(text.find("particle_particle.restitution = 0.6  (fixed)"), std::string::npos);
  EXPECT_NE(text.find("coarse graining factor 2"), std::string::npos);
  EXPECT_NE(text.find("shear modulus 5e+06 Pa (reduced)"), std::string::npos);
}

TEST(EnginesMaterialCard, Refusals) {
  EXPECT_NE(write_material_card(calibrated_input("cdt"), CardFormat::kLammps)
                .refusal.find("constant directional torque"),
            std::string::npos);
  EXPECT_NE(
      write_material_card(calibrated_input("epsd"), CardFormat::kEdemCsv).refusal.find("epsd"),
      std::string::npos);
  // A constant rolling spring: LAMMPS runs it as calibrated; LIGGGHTS and EDEM
  // have none and refuse it by name.
  EXPECT_NE(write_material_card(calibrated_input("sds"), CardFormat::kEdemCsv).refusal.find("sds"),
            std::string::npos);
  EXPECT_NE(write_material_card(calibrated_input("sds"), CardFormat::kLiggghts)
                .refusal.find("constant rolling spring"),
            std::string::npos);
  const auto sds = write_material_card(calibrated_input("sds"), CardFormat::kLammps);
  ASSERT_TRUE(sds.ok()) << sds.refusal;
  EXPECT_NE(sds.text->find("rolling sds, restitution"), std::string::npos) << *sds.text;
  EXPECT_EQ(sds.text->find("rolling spring constant in LAMMPS"), std::string::npos) << *sds.text;
  auto bad = calibrated_input();
  bad.calibrated.push_back({"particle_particle.mu", 1.0, 0.0, 2.0});
  EXPECT_THROW(write_material_card(bad, CardFormat::kJson), std::invalid_argument);
  EXPECT_EQ(card_format_from_name("edem-csv"), CardFormat::kEdemCsv);
  EXPECT_THROW(card_format_from_name("yade"), std::invalid_argument);
}

}  // namespace
}  // namespace demcal::engines
