// The reports as a reader meets them: every figure of the inspection and the
// calibration report is drawn (not empty), ships its CSV, and no text in it overlaps
// another — the legend sits in its own band, clear of the axis titles and out of the
// plot area. Run on the quick study's surrogates fitted to the lined recovery study's
// checked-in table (no DEM). The checker itself is shown to catch a legend drawn over
// the x-axis title.
#include "calibrate/report/gnuplot.hpp"
#include "calibrate/report/svg_layout.hpp"
#include "cli/calibrate_command.hpp"
#include "cli/fit_command.hpp"

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

namespace demcal {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ReportLayout, TheCheckerCatchesALegendOverTheAxisTitleAndAnEmptyPlot) {
  const fs::path dir = fs::temp_directory_path() / ("demcal-layout-" + std::to_string(getpid()));
  fs::remove_all(dir);
  const std::string bad = calibrate::render_svg_with_gnuplot(
      dir, "bad",
      calibrate::svg_preamble("bad", 500, 400) +
          "set xlabel 'rolling friction mu_r'\nset key at graph 0.5,-0.08 center top\n"
          "plot x title 'a legend entry that is long'\n");
  const auto problems = calibrate::svg_layout_problems(bad);
  bool overlap = false;
  for (const auto& p : problems) overlap = overlap || p.find("overlaps") != std::string::npos;
  EXPECT_TRUE(overlap) << ::testing::PrintToString(problems);
  const std::string inside =
      calibrate::render_svg_with_gnuplot(dir, "inside",
                                         calibrate::svg_preamble("inside", 500, 400) +
                                             "set key top left\nplot x title 'in the plot'\n");
  bool in_plot = false;
  for (const auto& p : calibrate::svg_layout_problems(inside))
    in_plot = in_plot || p.find("inside the plot") != std::string::npos;
  EXPECT_TRUE(in_plot);
  const std::string empty = calibrate::render_svg_with_gnuplot(
      dir, "empty",
      calibrate::svg_preamble("empty", 500, 400) +
          "set xrange [0:1]\nset yrange [0:1]\nplot 5 notitle\n");
  bool nothing = false;
  for (const auto& p : calibrate::svg_layout_problems(empty))
    nothing = nothing || p.find("nothing is drawn") != std::string::npos;
  EXPECT_TRUE(nothing);
  fs::remove_all(dir);
}

TEST(ReportLayout, EveryFigureOfBothReportsIsDrawnShipsItsDataAndHasNoOverlappingText) {
  const fs::path out = fs::temp_directory_path() / ("demcal-reports-" + std::to_string(getpid()));
  fs::remove_all(out);
  cli::FitOptions o;
  o.study = fs::path(DEMCAL_SOURCE_DIR) / "studies/quick/study.toml";
  o.doe_csv = fs::path(DEMCAL_SOURCE_DIR) / "studies/quick/doe.csv";
  o.output_dir = out;
  o.quiet = true;
  o.overrides = {"calibration.mcmc_samples=2000", "calibration.mcmc_burn_in=500",
                 "calibration.grid_points_per_axis=61"};
  std::ostringstream sink;
  cli::fit(o, sink, sink);
  const fs::path inspection = cli::inspect(o, sink, sink);
  const cli::CalibrateOutcome c = cli::calibrate_study(o, sink, sink);
  for (const fs::path& page : {inspection, c.report}) {
    const std::string html = slurp(page);
    const auto svgs = calibrate::svgs_in_html(html);
    std::size_t figures = 0;
    for (auto k = html.find("<figure>"); k != std::string::npos; k = html.find("<figure>", k + 1))
      ++figures;
    EXPECT_GE(svgs.size(), 6u) << page;
    EXPECT_EQ(svgs.size(), figures) << page << ": a figure without its SVG";
    for (std::size_t i = 0; i < svgs.size(); ++i) {
      const auto problems = calibrate::svg_layout_problems(svgs[i]);
      EXPECT_TRUE(problems.empty())
          << page << " figure " << i + 1 << ": " << ::testing::PrintToString(problems);
    }
    // Every data link points at a file that is there.
    const std::regex link("<a href=\"([^\"]+\\.csv)\">");
    std::size_t links = 0;
    for (std::sregex_iterator it(html.begin(), html.end(), link), end; it != end; ++it, ++links)
      EXPECT_TRUE(fs::exists(page.parent_path() / (*it)[1].str())) << (*it)[1].str();
    EXPECT_GE(links, svgs.size()) << page;
  }
  // The calibration report opens with its headline, and the two panels are there.
  const std::string cal = slurp(c.report);
  const auto head = cal.find("class=\"headline\"");
  ASSERT_NE(head, std::string::npos);
  EXPECT_LT(head, cal.find("<figure>"));
  EXPECT_NE(cal.find("AoR = "), std::string::npos);
  EXPECT_NE(cal.find("° (measured"), std::string::npos);
  EXPECT_TRUE(fs::exists(c.report.parent_path() / "key_figure_alone.svg"));
  EXPECT_TRUE(fs::exists(c.report.parent_path() / "posterior_map.svg"));
  const std::string headline = cal.substr(head, cal.find("</div>", head) - head);
  EXPECT_EQ(headline.find("angle_of_repose_deg"), std::string::npos)
      << "a raw identifier in the headline";
  EXPECT_EQ(cal.find("measured angle_of_repose_deg"), std::string::npos);
  // The JSON carries the same headline.
  const auto j = nlohmann::json::parse(slurp(c.json));
  ASSERT_TRUE(j.contains("headline"));
  EXPECT_EQ(j["headline"]["rows"].size(), 2u);
  EXPECT_TRUE(j["region_parts"]["joint"].is_array());
  EXPECT_GE(j["region_parts"]["joint"].size(), 1u);
  fs::remove_all(out);
}

}  // namespace
}  // namespace demcal
