// `demcal calibrate` on the checked-in recovery study (studies/sandglass-recovery:
// 100 quick-Sandglass runs, recordings of noise seed 1 made at (0.25, 0.45)):
// the report states where the known truth lies relative to both regions, and
// says it consistently with the regions' own thresholds.
#include "cli/calibrate_command.hpp"
#include "cli/fit_command.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace demcal::cli {
namespace {

using namespace demcal::config;
using namespace demcal::study;

namespace fs = std::filesystem;

TEST(CalibrateCommand, TheReferencePointsChiSquareAndRegionMembershipAreReported) {
  const fs::path out = fs::temp_directory_path() / ("demcal-calibrate-" + std::to_string(getpid()));
  fs::remove_all(out);
  FitOptions o;
  o.study = fs::path(DEMCAL_SOURCE_DIR) / "studies/sandglass-recovery/study.toml";
  o.doe_csv = fs::path(DEMCAL_SOURCE_DIR) / "studies/sandglass-recovery/doe.csv";
  o.output_dir = out;
  o.quiet = true;
  o.overrides = {"calibration.mcmc_samples=1000", "calibration.mcmc_burn_in=500",
                 "calibration.grid_points_per_axis=81"};
  std::ostringstream sink;
  fit(o, sink, sink);
  const CalibrateOutcome c = calibrate_study(o, sink, sink);
  std::ifstream in(c.json);
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_EQ(j["references"].size(), 1u);
  const auto& ref = j["references"][0];
  EXPECT_EQ(ref["label"], "truth (0.25, 0.45)");
  ASSERT_TRUE(ref["delta_chi_square_joint"].is_number());
  ASSERT_TRUE(ref["delta_chi_square_alone"].is_number());
  const double dj = ref["delta_chi_square_joint"], da = ref["delta_chi_square_alone"];
  // Measured from the grid's minimum, which the solver's minimum undercuts at most slightly.
  EXPECT_GT(dj, -1e-6);
  EXPECT_GT(da, -1e-6);
  // Membership as the region's own rule states it.
  const auto& rj = j["joint"]["region"];
  const auto& ra = j["alone"]["region"];
  EXPECT_EQ(ref["inside_joint"].get<bool>(),
            dj + rj["chi_squared_min"].get<double>() <= rj["threshold"].get<double>());
  EXPECT_EQ(ref["inside_alone"].get<bool>(),
            da + ra["chi_squared_min"].get<double>() <= ra["threshold"].get<double>());
  // Noise seed 1 of the recovery check: the truth is recovered by both (README: 2.8 joint).
  EXPECT_TRUE(ref["inside_joint"].get<bool>()) << dj;
  EXPECT_TRUE(ref["inside_alone"].get<bool>()) << da;
  EXPECT_LT(dj, 5.0);
  std::ifstream h(c.report);
  std::stringstream html;
  html << h.rdbuf();
  EXPECT_NE(html.str().find("truth (0.25, 0.45): chi² − chi²_min = "), std::string::npos);
  fs::remove_all(out);
}

}  // namespace
}  // namespace demcal::cli
