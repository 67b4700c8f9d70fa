// A derived study (a probe or an extended design of `demcal diagnose`) keeps every key
// the base design ties to a parameter (issue 19: a probe of the lined quick study varied the
// grains' mu_s alone while the base design moved the walls' with it). Read from the quick
// study itself, written as the diagnosis writes it, read back as a study: the tie is there,
// and setting the design's point sets the tied key.
#include "config/design_config.hpp"
#include "config/study_config.hpp"
#include "study/derived_study.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace demcal::study {
namespace {

TEST(DerivedStudyTies, AProbeKeepsTheBaseDesignsAlsoSets) {
  const std::string quick = std::string(DEMCAL_SOURCE_DIR) + "/studies/quick/study.toml";
  const config::StudyConfig base = config::load_study_config(quick, {});
  ASSERT_TRUE(base.design);
  const std::vector<DerivedParameter> params = base_design_parameters(*base.design);
  ASSERT_EQ(params.size(), 2u);
  EXPECT_EQ(params[0].key, "mu_r");
  EXPECT_TRUE(params[0].also_sets.empty());
  EXPECT_EQ(params[1].key, "mu_s");
  EXPECT_EQ(params[1].also_sets,
            std::vector<std::string>{"interaction.particle_wall.sliding_friction"});
  EXPECT_EQ(params[1].lower, 0.2);
  EXPECT_EQ(params[1].upper, 0.9);

  // The study as the diagnosis writes a probe of it.
  config::ConfigDocument doc = config::read_config_file(quick);
  for (const char* k : {"design", "calibration", "diagnosis", "output"}) doc.table.erase(k);
  DerivedStudyFile file;
  file.header = {"A probe written by a test."};
  file.study = doc.table;
  file.design.kind = "list";
  file.design.replicates = 2;
  file.design.values = {{0.25, 0.65}};
  file.design.parameters = params;
  const auto dir = testing::fresh_dir("derived", "ties");
  testing::spit(dir / "study.toml", derived_study_text(file));

  const config::StudyConfig probe = config::load_study_config(dir / "study.toml", {});
  ASSERT_TRUE(probe.design);
  EXPECT_EQ(probe.design->tied_paths, base.design->tied_paths);
  EXPECT_EQ(probe.design->parameter_paths, base.design->parameter_paths);

  // The probe's point sets the walls' friction with the grains'.
  config::ConfigDocument point = config::read_config_file(dir / "study.toml");
  config::apply_design_values(point, *probe.design, {0.25, 0.65}, "probe point 0");
  EXPECT_EQ(point.table.at_path("interaction.particle_wall.sliding_friction").value<double>(),
            0.65);
  EXPECT_EQ(point.table.at_path("interaction.particle_particle.sliding_friction").value<double>(),
            0.65);
}

}  // namespace
}  // namespace demcal::study
