// What a reader sees for an identifier or a number: one table of labels with units, and
// numbers as people write them.
#include "calibrate/report/labels.hpp"
#include "cli/console.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace demcal {
namespace {

TEST(ReportLabels, ObservablesHaveHumanLabelsWithUnits) {
  using namespace calibrate;
  EXPECT_EQ(observable_label("angle_of_repose_deg"), "angle of repose (°)");
  EXPECT_EQ(observable_label("discharge_time_s"), "discharge time (s)");
  EXPECT_EQ(observable_label("discharge_t50_s"), "time to 50 % discharged (s)");
  EXPECT_EQ(observable_label("bulk_density_kg_m3"), "bulk density (kg/m³)");
  EXPECT_EQ(observable_label("something_else"), "something_else");
  EXPECT_EQ(observable_value("angle_of_repose_deg", 30.9607), "30.96°");
  EXPECT_EQ(observable_value("discharge_time_s", 0.5542), "0.5542 s");
  EXPECT_EQ(humanize_identifiers("surrogate for 'angle_of_repose_deg': bad"),
            "surrogate for angle of repose (°): bad");
}

TEST(ReportLabels, NumbersAreWrittenAsPeopleWriteThem) {
  using calibrate::human_number;
  EXPECT_EQ(human_number(0.7249999999999999), "0.725");
  EXPECT_EQ(human_number(6.21e-29), "0");
  EXPECT_EQ(human_number(-3e-15), "0");
  EXPECT_EQ(human_number(4.3e-4), "0.00043");
  EXPECT_EQ(human_number(12345.678, 4), "1.235e+04");
  EXPECT_EQ(human_number(std::nan("")), "—");
  EXPECT_EQ(calibrate::humanize_sentence(
                "One minimum: chi^2 = 1.39e-27 at (mu_r = 0.2 +/- 0.01), e 4.3e-4"),
            "One minimum: chi² = 0 at (mu_r = 0.2 ± 0.01), e 4.3e-4");
}

TEST(ConsoleOutput, AWarningIsPrintedOnceAndTablesAlignByCharacters) {
  std::ostringstream log;
  cli::warn_once(log, "the surrogate is worse than rerunning the DEM (test-only text 1)");
  cli::warn_once(log, "the surrogate is worse than rerunning the DEM (test-only text 1)");
  EXPECT_EQ(log.str(),
            "warning: the surrogate is worse than rerunning the DEM (test-only text 1)\n");
  EXPECT_EQ(cli::aligned_table({{"a", "b"}, {"±±", "c"}}, ""), "a   b\n±±  c\n");
}

}  // namespace
}  // namespace demcal
