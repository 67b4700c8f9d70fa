#pragma once
// The report's figure kinds, each drawn by gnuplot from CSV files written
// beside the report (<directory>/<name>*.csv): the figure and its numbers
// travel together. Each returns the SVG text and the CSV file names.

#include <filesystem>
#include <string>
#include <vector>

namespace demcal::calibrate {

struct RenderedFigure {
  std::string svg;
  std::vector<std::string> data_files;  // relative to the directory
};

// A scalar field over two inputs, sampled on a regular grid:
// values[iy * x.size() + ix] at (x[ix], y[iy]).
struct GridField {
  std::vector<double> x, y;
  std::vector<double> values;
};

struct PointSet {
  std::string label;
  std::vector<double> x, y;
  std::string style = "points pt 7 ps 0.6 lc rgb '#000000'";  // gnuplot "with" clause
};

struct ContourLine {
  std::string label;
  GridField field;   // the line is field == level
  double level = 0.0;
  std::string color = "#d62728";
  int dash = 1;      // gnuplot dashtype
  double width = 2.0;
};

// Text written into a map at (x, y), e.g. "part 2: no design point".
struct MapLabel {
  double x = 0, y = 0;
  std::string text;
};

struct MapFigureOptions {
  std::string title, x_label, y_label, value_label;
  int contour_levels = 10;  // of the colour map's own field (0: none)
  // "viridis" | "diverging" | a gnuplot palette definition ("defined (0 'white', 1 '#aec7e8')")
  std::string palette = "viridis";
  // The plot area and its labels; the legend gets a band of its own under the x-axis title
  // (the SVG is taller by it), so it never covers data or an axis title.
  int width_px = 600, height_px = 500;
  bool colorbox = true;
  double value_min = 0, value_max = 0;  // colour range; equal: from the data
  std::vector<MapLabel> labels = {};
};

// A colour map of `field` with its contour lines, overlaid lines (iso-lines
// of other fields at a level, e.g. a measured value or a region boundary) and
// point sets (design points, minima).
RenderedFigure map_figure(const std::filesystem::path& directory, const std::string& name,
                          const GridField& field, const std::vector<ContourLine>& lines,
                          const std::vector<PointSet>& points, const MapFigureOptions& options);

// Observed against predicted (with +-2 sd bars when sd is given) and y = x.
RenderedFigure parity_figure(const std::filesystem::path& directory, const std::string& name,
                             const std::vector<double>& observed, const std::vector<double>& predicted,
                             const std::vector<double>& predicted_sd, const std::string& title,
                             const std::string& quantity_label);

// Standardized residuals against the prediction, with the +-2 band.
RenderedFigure residual_figure(const std::filesystem::path& directory, const std::string& name,
                               const std::vector<double>& predicted,
                               const std::vector<double>& standardized_residuals,
                               const std::string& title, const std::string& x_label);

// Grouped bars: one group per label, one bar per series (e.g. first-order and
// total Sobol indices per parameter), with optional +- error bars.
struct BarSeries {
  std::string name;
  std::vector<double> values;
  std::vector<double> errors;  // empty: none
};
RenderedFigure bar_figure(const std::filesystem::path& directory, const std::string& name,
                          const std::vector<std::string>& labels, const std::vector<BarSeries>& series,
                          const std::string& title, const std::string& y_label);

// x-y lines (marginal densities, m(t), profiles): one CSV column pair per series.
struct LineSeries {
  std::string name;
  std::vector<double> x, y;
  std::string style = "lines lw 2";
};
RenderedFigure line_figure(const std::filesystem::path& directory, const std::string& name,
                           const std::vector<LineSeries>& series, const std::string& title,
                           const std::string& x_label, const std::string& y_label);

}  // namespace demcal::calibrate
