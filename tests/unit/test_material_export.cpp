// `demcal export` (study/material_export.hpp): the calibrated material card
// from a study and its calibration output. Golden cards in tests/data/engines/
// (DEMCAL_UPDATE_GOLDEN=1 rewrites them); the calibration output is written
// here with the two things the export reads: the joint best minimum and the
// 95 % region's extent.
#include "cli/export_command.hpp"
#include "config/toml_reader.hpp"
#include "study/material_export.hpp"
#include "tests/support/golden.hpp"
#include "tests/support/test_files.hpp"
#include "tests/support/study_text.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

namespace demcal::study {
namespace {

namespace fs = std::filesystem;

std::string study_text(const std::string& rolling, const std::string& engine) {
  return R"([study]
name = "export-test"

)" +
    testing::sand_and_glass_tables({.rolling = rolling}) +
    R"(
[apparatus.rectangular_container]
width_m = 0.22
height_m = 0.1
thickness_diameters = 4.0
boundary = "periodic"
fill_mass_kg = 0.055
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7

[design]
kind = "full_factorial"
parameters = { mu_r = { lower = 0.05, upper = 0.6, levels = 3 }, mu_s = { lower = 0.2, upper = 0.9, levels = 3 } }
)" + engine;
}

// A study and the calibration output `demcal calibrate` would leave beside it.
fs::path write_calibrated_study(const std::string& name, const std::string& text) {
  const fs::path dir = testing::fresh_dir("export", name);
  testing::spit(dir / "study.toml", text);
  testing::spit(dir / "out" / "export-test" / "reports" / "calibration" / "calibration.json",
                R"({"joint": {"minima": [{"theta": [0.21, 0.51]}, {"theta": [0.5, 0.3]}],
  "region": {"available": true, "extent": [
    {"parameter": "mu_r", "lower": 0.12, "upper": 0.33},
    {"parameter": "mu_s", "lower": 0.37, "upper": 0.84}]}}})");
  return dir / "study.toml";
}

TEST(MaterialExport, TheCardsHoldTheCalibratedValuesAndTheirIntervals) {
  const fs::path study = write_calibrated_study("golden", study_text("epsd", ""));
  const fs::path out = study.parent_path() / "out" / "export-test";
  engines::MaterialCardInput in = material_card_input(
      study, {}, out / "reports" / "calibration" / "calibration.json", out / "runs");
  ASSERT_EQ(in.calibrated.size(), 2u);
  EXPECT_EQ(in.calibrated[0].name, "particle_particle.rolling_friction");
  EXPECT_EQ(in.calibrated[0].value, 0.21);
  EXPECT_EQ(in.calibrated[1].lower_95, 0.37);
  EXPECT_EQ(in.material.particle_particle.sliding_friction, 0.51);
  EXPECT_EQ(in.reduction.coarse_graining_factor, 6.0);
  EXPECT_EQ(in.provenance.calibrated_engine, engines::Engine::kDemcal);
  in.provenance.calibrated_engine_version = "(version)";  // the build's, not the golden's
  for (const auto& [format, file] :
       {std::pair{engines::CardFormat::kLiggghts, "export_epsd.liggghts.in"},
        std::pair{engines::CardFormat::kLammps, "export_epsd.lammps.in"},
        std::pair{engines::CardFormat::kJson, "export_epsd.json"}}) {
    const engines::CardResult card = engines::write_material_card(in, format);
    ASSERT_TRUE(card.ok()) << card.refusal;
    EXPECT_NE(card.text->find("0.21"), std::string::npos);
    testing::expect_golden(*card.text, std::string("engines/") + file);
  }
  fs::remove_all(study.parent_path());
}

TEST(MaterialExport, TheCommandWritesTheCardAndWarnsOfAnotherEngine) {
  const fs::path study = write_calibrated_study("command", study_text("cdt", ""));
  cli::ExportOptions o;
  o.card.study = study;
  o.card.output_dir = study.parent_path() / "out";
  o.card.to = "liggghts";
  std::ostringstream out, log;
  EXPECT_EQ(cli::run_export(o, out, log), 0);
  const fs::path card = study.parent_path() / "out/export-test/material/export-test.liggghts.in";
  EXPECT_NE(out.str().find(card.string()), std::string::npos) << out.str();
  const std::string text = testing::slurp(card);
  EXPECT_NE(text.find("WARNING: calibrated on demcal, written for LIGGGHTS"), std::string::npos);
  EXPECT_NE(text.find("[0.12, 0.33]"), std::string::npos) << text;
  EXPECT_NE(text.find("coarse graining factor 6"), std::string::npos) << text;
  EXPECT_NE(log.str().find("calibrated on demcal, the card is for liggghts"), std::string::npos)
      << log.str();
  // The EDEM card of the same calibration (cdt is EDEM's type A).
  o.card.to = "edem-csv";
  EXPECT_EQ(cli::run_export(o, out, log), 0);
  EXPECT_TRUE(fs::exists(study.parent_path() / "out/export-test/material/export-test.edem.csv"));
  // LAMMPS has no cdt: refused by name, no card written.
  o.card.to = "lammps";
  try {
    cli::run_export(o, out, log);
    ADD_FAILURE() << "a cdt card for LAMMPS was written";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("constant directional torque"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(study.parent_path() / "out/export-test/material/export-test.lammps.in"));
  fs::remove_all(study.parent_path());
}

TEST(MaterialExport, WithoutACalibrationOrWithAnotherFormatItIsRefused) {
  const fs::path dir = testing::fresh_dir("export", "refused");
  testing::spit(dir / "study.toml", study_text("cdt", ""));
  MaterialExportOptions o;
  o.study = dir / "study.toml";
  o.output_dir = dir / "out";
  o.to = "liggghts";
  try {
    export_material_card(o);
    ADD_FAILURE() << "exported without a calibration";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("run `demcal calibrate` on the study first"),
              std::string::npos)
        << e.what();
  }
  o.to = "yade";
  EXPECT_THROW(export_material_card(o), config::ConfigError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace demcal::study
