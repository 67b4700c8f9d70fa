// The derived studies of `demcal diagnose` are written by one serialiser; its
// text is the one the diagnosis wrote when it assembled them by hand (a
// resumed diagnosis compares the text to decide whether to rewrite the file).
#include "study/derived_study.hpp"

#include <gtest/gtest.h>

#include <sstream>

namespace demcal::study {
namespace {

std::string tables_text(const toml::table& t) {
  std::ostringstream s;
  s << toml::toml_formatter(t);
  return s.str();
}

DerivedStudyFile with_study() {
  DerivedStudyFile f;
  f.header = {"Written by a test.", "Second line."};
  f.study.insert("study", toml::table{{"name", "s--cohesion-probe"}, {"seed", 7}});
  return f;
}

TEST(DerivedStudy, AProbeListsItsPointsInTheOrderGiven) {
  DerivedStudyFile f = with_study();
  f.design.kind = "list";
  f.design.replicates = 2;
  f.design.values = {{0.125, 0.5, 2.5}, {0.125, 0.5, 0.25}};
  f.design.parameters = {
      {"mu_s", 0.1, 0.9, {}},
      {"contact.surface_energy_j_m2", 0.0, 0.5, {"wall.surface_energy_j_m2", "x"}}};
  EXPECT_EQ(derived_study_text(f),
            "# Written by a test.\n# Second line.\n" + tables_text(f.study) +
                "\n\n[design]\nkind = \"list\"\nreplicates = 2\n"
                "values = [[0.125, 0.5, 2.5], [0.125, 0.5, 0.25]]\n"
                "parameters = { mu_s = { lower = 0.1, upper = 0.9 }, "
                "\"contact.surface_energy_j_m2\" = { lower = 0, upper = 0.5, also_sets = "
                "[\"wall.surface_energy_j_m2\", \"x\"] } }\n");
}

TEST(DerivedStudy, AnExtendedDesignNamesItsSizeAndSeed) {
  DerivedStudyFile f = with_study();
  f.design.kind = "latin_hypercube";
  f.design.points = 16;
  f.design.replicates = 1;
  f.design.seed = 1;
  f.design.parameters = {{"mu_s", 0.1, 0.9, {}}, {"mu_w", 0.2, 0.8, {}}};
  EXPECT_EQ(derived_study_text(f),
            "# Written by a test.\n# Second line.\n" + tables_text(f.study) +
                "\n\n[design]\nkind = \"latin_hypercube\"\npoints = 16\nreplicates = 1\nseed = 1\n"
                "parameters = { mu_s = { lower = 0.1, upper = 0.9 }, mu_w = { lower = 0.2, upper = "
                "0.8 } }\n");
}

}  // namespace
}  // namespace demcal::study
