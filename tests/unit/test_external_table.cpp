// A design table made by another code (studies/external-table/): fit and
// calibrate read it in place of demcal's run store, and give the calibration
// the same runs give through demcal's own table (studies/sandglass-calibration/).
#include "cli/calibrate_command.hpp"
#include "cli/fit_command.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <string>

namespace demcal::cli {
namespace {

namespace fs = std::filesystem;

nlohmann::json calibrate_from(const fs::path& study, const fs::path& table, const fs::path& out) {
  FitOptions o;
  o.study = study;
  o.output_dir = out;
  o.doe_csv = table;
  o.quiet = true;
  std::ostringstream sink;
  const FitOutcome fitted = fit(o, sink, sink);
  EXPECT_EQ(fitted.files.size(), 2u) << "a surrogate per observable";
  const CalibrateOutcome c = calibrate_study(o, sink, sink);
  std::ifstream in(c.json);
  return nlohmann::json::parse(in);
}

TEST(ExternalTable, FitAndCalibrateReadATableAnyCodeCanWrite) {
  const fs::path out = testing::fresh_dir("external-table", "out");
  const fs::path studies = fs::path(DEMCAL_SOURCE_DIR) / "studies";
  const nlohmann::json external =
      calibrate_from(studies / "external-table" / "study.toml",
                     studies / "external-table" / "design_table.csv", out);
  const nlohmann::json& best = external.at("joint").at("minima").at(0).at("theta");
  ASSERT_EQ(best.size(), 2u);
  // Inside the design box.
  EXPECT_GE(best[0].get<double>(), 0.05);
  EXPECT_LE(best[0].get<double>(), 0.6);
  EXPECT_GE(best[1].get<double>(), 0.2);
  EXPECT_LE(best[1].get<double>(), 0.9);
  // The same runs through demcal's own table give the same calibration: the
  // seeds, run names and the empty flow-rate and density columns change nothing.
  // (Its verification run on the conical pile is left out: it would run DEM.)
  std::string text = testing::slurp(studies / "sandglass-calibration" / "study.toml");
  text.erase(text.find("verify = "),
             text.find('\n', text.find("verify = ")) - text.find("verify = "));
  testing::spit(out / "native" / "study.toml", text);
  testing::spit(out / "native" / "recordings.csv",
                testing::slurp(studies / "sandglass-calibration" / "recordings.csv"));
  const nlohmann::json native = calibrate_from(out / "native" / "study.toml",
                                               studies / "sandglass-calibration" / "doe.csv", out);
  const nlohmann::json& same = native.at("joint").at("minima").at(0).at("theta");
  EXPECT_NEAR(best[0].get<double>(), same[0].get<double>(), 1e-6);
  EXPECT_NEAR(best[1].get<double>(), same[1].get<double>(), 1e-6);
  fs::remove_all(out);
}

}  // namespace
}  // namespace demcal::cli
