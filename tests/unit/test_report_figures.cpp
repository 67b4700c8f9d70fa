// The report's building blocks: gnuplot figures (SVG + the CSV behind them)
// and the self-contained HTML page.

#include "calibrate/report/figures.hpp"
#include "calibrate/report/html_report.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace demcal::calibrate {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("demcal_report_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

GridField paraboloid() {
  GridField f;
  for (int i = 0; i <= 20; ++i) f.x.push_back(i / 20.0);
  for (int i = 0; i <= 10; ++i) f.y.push_back(i / 10.0);
  for (double y : f.y)
    for (double x : f.x) f.values.push_back((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5));
  return f;
}

TEST(ReportFigures, MapWithIsoLineAndPointsWritesSvgAndTheDataBehindIt) {
  const fs::path dir = fresh_dir("map");
  ContourLine circle{"r = 0.3", paraboloid(), 0.09};
  PointSet pts{"design", {0.1, 0.9}, {0.2, 0.8}};
  const RenderedFigure fig = map_figure(dir, "aor_map", paraboloid(), {circle}, {pts},
                                        MapFigureOptions{"AoR", "mu_r", "mu_s", "AoR (deg)"});
  EXPECT_NE(fig.svg.find("<svg"), std::string::npos);
  EXPECT_NE(fig.svg.find("r = 0.3"), std::string::npos);  // the legend names the iso-line
  ASSERT_EQ(fig.data_files.size(), 3u);
  for (const auto& f : fig.data_files) EXPECT_TRUE(fs::exists(dir / f)) << f;
  // The iso-line gnuplot traced lies on the circle of radius 0.3.
  std::ifstream tab(dir / "aor_map_line0.tab");
  std::string line;
  int on_circle = 0, points = 0;
  while (std::getline(tab, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    double x = 0, y = 0;
    if (!(s >> x >> y)) continue;
    ++points;
    if (std::abs(std::hypot(x - 0.5, y - 0.5) - 0.3) < 0.01) ++on_circle;
  }
  EXPECT_GT(points, 20);
  EXPECT_GT(on_circle, 0.9 * points);
  // The CSV has a header and one row per grid node.
  const std::string csv = slurp(dir / "aor_map_map.csv");
  EXPECT_EQ(csv.rfind("x,y,AoR (deg)\n", 0), 0u);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 21 * 11);
  fs::remove_all(dir);
}

TEST(ReportFigures, ParityResidualBarAndLineFiguresRender) {
  const fs::path dir = fresh_dir("kinds");
  EXPECT_NE(parity_figure(dir, "parity", {1, 2, 3}, {1.1, 1.9, 3.2}, {0.1, 0.1, 0.2}, "t", "(s)").svg.find("<svg"),
            std::string::npos);
  EXPECT_NE(residual_figure(dir, "res", {1, 2, 3}, {0.5, -1.0, 2.5}, "t", "x").svg.find("<svg"),
            std::string::npos);
  EXPECT_NE(bar_figure(dir, "sobol", {"mu_r", "mu_s"}, {{"first", {0.3, 0.6}, {0.01, 0.02}}, {"total", {0.35, 0.7}, {}}},
                       "Sobol", "index")
                .svg.find("<svg"),
            std::string::npos);
  EXPECT_NE(line_figure(dir, "lines", {{"a", {0, 1}, {0, 1}}}, "t", "x", "y").svg.find("<svg"), std::string::npos);
  EXPECT_THROW(parity_figure(dir, "bad", {1, 2}, {1}, {}, "t", ""), std::invalid_argument);
  fs::remove_all(dir);
}

// Standardized residuals are as often negative as positive: a bar chart of them shows the
// bars below zero (it drew from 0 up and clipped them), and one whose every bar is
// negative, or has no value at all, still renders (gnuplot refused it, "all points y value
// undefined", and the diagnosis of a reproduced study failed on its report).
TEST(ReportFigures, BarFiguresShowNegativeBarsAndSurviveEmptyOnes) {
  const fs::path dir = fresh_dir("bars");
  const auto below = bar_figure(dir, "below", {"a", "b"}, {{"base", {-1.5, -0.2}, {}}}, "t", "r");
  EXPECT_NE(below.svg.find("<svg"), std::string::npos);
  const std::string script = slurp(dir / "below.gp");
  EXPECT_EQ(script.find("[0:*]"), std::string::npos) << script;
  EXPECT_NE(script.find("xzeroaxis"), std::string::npos) << script;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(bar_figure(dir, "none", {"a", "b"}, {{"base", {nan, nan}, {}}}, "t", "r").svg.find("<svg"),
            std::string::npos);
  // Positive bars (indices) still start at 0.
  bar_figure(dir, "above", {"a"}, {{"first", {0.4}, {0.1}}}, "t", "i");
  EXPECT_NE(slurp(dir / "above.gp").find("set yrange [0:*]"), std::string::npos);
  fs::remove_all(dir);
}

TEST(ReportFigures, GnuplotErrorsAreReportedWithTheScript) {
  const fs::path dir = fresh_dir("err");
  GridField bad = paraboloid();
  bad.values.pop_back();
  EXPECT_THROW(map_figure(dir, "m", bad, {}, {}, {}), std::invalid_argument);
  fs::remove_all(dir);
}

TEST(HtmlReport, EscapesTextAndEmbedsSvgWithoutItsXmlProlog) {
  HtmlReport r("Report <1>");
  r.paragraph("a < b & c");
  r.table({"name", "value"}, {{"mu_r", "0.3"}, {"<x>"}});
  r.figure("<?xml version=\"1.0\"?>\n<!DOCTYPE svg>\n<svg width=\"1\"></svg>", "caption", {"data.csv"});
  const std::string h = r.html();
  EXPECT_NE(h.find("<title>Report &lt;1&gt;</title>"), std::string::npos);
  EXPECT_NE(h.find("a &lt; b &amp; c"), std::string::npos);
  EXPECT_EQ(h.find("<?xml"), std::string::npos);
  EXPECT_NE(h.find("<svg width=\"1\"></svg>"), std::string::npos);
  EXPECT_NE(h.find("<a href=\"data.csv\">"), std::string::npos);
  EXPECT_EQ(h.find("<script"), std::string::npos);  // self-contained, no scripts
}

}  // namespace
}  // namespace demcal::calibrate
