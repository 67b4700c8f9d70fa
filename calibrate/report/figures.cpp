#include "calibrate/report/figures.hpp"

#include "calibrate/report/gnuplot.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace demcal::calibrate {
namespace {

namespace fs = std::filesystem;

// Every table is written twice: <stem>.csv (comma-separated with a header, for
// readers and other tools) and <stem>.dat (whitespace, what the gnuplot
// script reads: gnuplot's own contour tables are whitespace-separated, and one
// plot command cannot mix separators).
void write_table(const fs::path& directory, const std::string& stem, const std::vector<std::string>& header,
                 const std::vector<std::vector<double>>& columns, std::size_t block = 0) {
  const std::size_t n = columns.empty() ? 0 : columns.front().size();
  for (const auto& c : columns)
    if (c.size() != n) throw std::invalid_argument("figure " + stem + ": columns of unequal length");
  std::ofstream csv(directory / (stem + ".csv"));
  std::ofstream dat(directory / (stem + ".dat"));
  if (!csv || !dat) throw std::runtime_error("cannot write the data of figure " + stem + " in " + directory.string());
  csv << std::setprecision(10);
  dat << std::setprecision(10);
  for (std::size_t j = 0; j < header.size(); ++j) csv << (j ? "," : "") << header[j];
  csv << "\n";
  dat << "#";
  for (const auto& h : header) dat << " " << h;
  dat << "\n";
  for (std::size_t i = 0; i < n; ++i) {
    // A blank line between grid scans: gnuplot's grid format for splot.
    if (block > 0 && i > 0 && i % block == 0) dat << "\n";
    for (std::size_t j = 0; j < columns.size(); ++j) {
      const double v = columns[j][i];
      csv << (j ? "," : "");
      dat << (j ? " " : "");
      if (std::isfinite(v)) {
        csv << v;
        dat << v;
      } else {
        dat << "NaN";  // gnuplot skips it; the CSV leaves the cell empty
      }
    }
    csv << "\n";
    dat << "\n";
  }
}

void write_grid(const fs::path& directory, const std::string& stem, const GridField& f,
                const std::string& value_name) {
  if (f.x.size() < 2 || f.y.size() < 2 || f.values.size() != f.x.size() * f.y.size())
    throw std::invalid_argument("figure " + stem + ": the grid needs >= 2 x 2 nodes and x.size() * y.size() values");
  std::vector<double> xs, ys, vs;
  for (std::size_t iy = 0; iy < f.y.size(); ++iy)
    for (std::size_t ix = 0; ix < f.x.size(); ++ix) {
      xs.push_back(f.x[ix]);
      ys.push_back(f.y[iy]);
      vs.push_back(f.values[iy * f.x.size() + ix]);
    }
  write_table(directory, stem, {"x", "y", value_name}, {xs, ys, vs}, f.x.size());
}

std::string q(const std::string& s) { return gnuplot_quote(s); }

std::string palette(const std::string& name) {
  if (name == "diverging")
    return "set palette defined (0 '#3b4cc0', 0.5 '#f2f2f2', 1 '#b40426')\n";
  return "set palette defined (0 '#440154', 0.25 '#3b528b', 0.5 '#21918c', 0.75 '#5ec962', 1 '#fde725')\n";
}

// Pins the plot area (margins at screen positions) and puts the legend in a band of its
// own under the x-axis title, one entry a line: the same layout in every figure, so a
// legend never covers data or an axis title (the HTML test checks it on the SVG).
// Returns the settings; `total_height` is plot_height plus the legend band.
constexpr int kKeyLine = 22;

std::string frame(int width, int plot_height, int key_entries, bool colorbox, int& total_height) {
  const int band = key_entries > 0 ? 16 + kKeyLine * key_entries : 0;
  total_height = plot_height + band;
  const double W = width, H = total_height;
  std::ostringstream s;
  s << std::setprecision(4) << "set lmargin at screen " << 78 / W << "\nset rmargin at screen "
    << 1 - (colorbox ? 120 : 24) / W << "\nset tmargin at screen " << 1 - 34 / H << "\nset bmargin at screen "
    << (band + 58) / H << "\n";
  if (key_entries > 0)
    s << "set key at screen " << 20 / W << "," << (band - 4) / H
      << " left top vertical Left reverse nobox samplen 3 spacing 1.2 maxrows " << key_entries << "\n";
  else
    s << "unset key\n";
  return s.str();
}

}  // namespace

RenderedFigure map_figure(const fs::path& directory, const std::string& name, const GridField& field,
                          const std::vector<ContourLine>& lines, const std::vector<PointSet>& points,
                          const MapFigureOptions& o) {
  fs::create_directories(directory);
  RenderedFigure out;
  write_grid(directory, name + "_map", field, o.value_label.empty() ? "value" : o.value_label);
  out.data_files.push_back(name + "_map.csv");
  std::size_t entries = 0;
  for (const auto& l : lines) entries += !l.label.empty();
  for (const auto& p : points) entries += !p.label.empty();
  int total_height = 0;
  const std::string layout = frame(o.width_px, o.height_px, static_cast<int>(entries), o.colorbox, total_height);
  std::ostringstream s;
  s << svg_preamble(name, o.width_px, total_height) << layout;
  s << "set datafile separator whitespace\n";
  // Contour tables first (gnuplot computes iso-lines only in splot).
  s << "set view map\nunset surface\nset contour base\n";
  if (o.contour_levels > 0) {
    s << "set cntrparam levels auto " << o.contour_levels << "\n"
      << "set table " << q(name + "_map_contours.tab") << "\nsplot " << q(name + "_map.dat")
      << " using 1:2:3 with lines\nunset table\n";
  }
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string stem = name + "_line" + std::to_string(i);
    write_grid(directory, stem, lines[i].field, "value");
    out.data_files.push_back(stem + ".csv");
    s << "set cntrparam levels discrete " << std::setprecision(12) << lines[i].level << "\n"
      << "set table " << q(stem + ".tab") << "\nsplot " << q(stem + ".dat")
      << " using 1:2:3 with lines\nunset table\n";
  }
  s << "unset contour\nset surface\n";
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string stem = name + "_points" + std::to_string(i);
    write_table(directory, stem, {"x", "y"}, {points[i].x, points[i].y});
    out.data_files.push_back(stem + ".csv");
  }
  s << (o.palette == "viridis" || o.palette == "diverging" ? palette(o.palette) : "set palette " + o.palette + "\n");
  if (!o.colorbox) s << "unset colorbox\n";
  if (o.value_max > o.value_min) s << "set cbrange [" << o.value_min << ":" << o.value_max << "]\n";
  // A label's text runs towards the middle of the plot, so that a label at either edge
  // (a region's part against a bound) stays inside the figure.
  const double x_middle = 0.5 * (field.x.front() + field.x.back());
  for (const auto& l : o.labels)
    s << "set label " << q(l.text) << " at " << l.x << "," << l.y
      << (l.x > x_middle ? " right" : " left") << " front font ',11' textcolor rgb '#222222'\n";
  s << "set title " << q(o.title) << "\nset xlabel " << q(o.x_label) << "\nset ylabel " << q(o.y_label)
    << "\nset cblabel " << q(o.value_label) << "\n";
  s << "set xrange [" << field.x.front() << ":" << field.x.back() << "]\nset yrange [" << field.y.front()
    << ":" << field.y.back() << "]\n";
  s << "plot " << q(name + "_map.dat") << " using 1:2:3 with image notitle";
  if (o.contour_levels > 0)
    s << ", " << q(name + "_map_contours.tab") << " using 1:2 with lines lc rgb '#ffffff' lw 0.6 notitle";
  for (std::size_t i = 0; i < lines.size(); ++i)
    s << ", " << q(name + "_line" + std::to_string(i) + ".tab") << " using 1:2 with lines lc rgb "
      << q(lines[i].color) << " lw " << lines[i].width << " dt " << lines[i].dash << " "
      << (lines[i].label.empty() ? "notitle" : "title " + q(lines[i].label));
  for (std::size_t i = 0; i < points.size(); ++i)
    s << ", " << q(name + "_points" + std::to_string(i) + ".dat") << " using 1:2 with " << points[i].style
      << " " << (points[i].label.empty() ? "notitle" : "title " + q(points[i].label));
  s << "\n";
  out.svg = render_svg_with_gnuplot(directory, name, s.str());
  return out;
}

RenderedFigure parity_figure(const fs::path& directory, const std::string& name,
                             const std::vector<double>& observed, const std::vector<double>& predicted,
                             const std::vector<double>& predicted_sd, const std::string& title,
                             const std::string& quantity_label) {
  fs::create_directories(directory);
  if (observed.size() != predicted.size() || (!predicted_sd.empty() && predicted_sd.size() != observed.size()))
    throw std::invalid_argument("parity figure " + name + ": observed, predicted and sd differ in length");
  RenderedFigure out;
  std::vector<double> sd2;
  for (double v : predicted_sd) sd2.push_back(2.0 * v);
  if (sd2.empty()) sd2.assign(observed.size(), 0.0);
  write_table(directory, name, {"observed", "predicted", "two_sd"}, {observed, predicted, sd2});
  out.data_files.push_back(name + ".csv");
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    lo = std::min({lo, observed[i], predicted[i] - sd2[i]});
    hi = std::max({hi, observed[i], predicted[i] + sd2[i]});
  }
  const double pad = 0.05 * (hi - lo + 1e-12);
  int total_height = 0;
  const std::string layout = frame(520, 470, 2, false, total_height);
  std::ostringstream s;
  s << svg_preamble(name, 520, total_height) << layout << "set datafile separator whitespace\n"
    << "set title " << q(title) << "\nset xlabel " << q("DEM run " + quantity_label)
    << "\nset ylabel " << q("surrogate without it " + quantity_label) << "\n"
    << "set xrange [" << lo - pad << ":" << hi + pad << "]\nset yrange [" << lo - pad << ":" << hi + pad
    << "]\n"
    << "plot x with lines lc rgb '#888888' dt 2 title 'y = x', " << q(name + ".dat")
    << " using 1:2:3 with yerrorbars pt 7 ps 0.7 lc rgb '#1f77b4' title 'leave-one-out prediction, bars ±2 sd'\n";
  out.svg = render_svg_with_gnuplot(directory, name, s.str());
  return out;
}

RenderedFigure residual_figure(const fs::path& directory, const std::string& name,
                               const std::vector<double>& predicted,
                               const std::vector<double>& standardized_residuals, const std::string& title,
                               const std::string& x_label) {
  fs::create_directories(directory);
  RenderedFigure out;
  write_table(directory, name, {"predicted", "standardized_residual"}, {predicted, standardized_residuals});
  out.data_files.push_back(name + ".csv");
  int total_height = 0;
  const std::string layout = frame(520, 400, 2, false, total_height);
  std::ostringstream s;
  s << svg_preamble(name, 520, total_height) << layout << "set datafile separator whitespace\n"
    << "set title " << q(title) << "\nset xlabel " << q(x_label)
    << "\nset ylabel 'standardized residual'\nset yrange [-1e9<*<-3:3<*<1e9]\n"
    << "plot 2 with lines lc rgb '#d62728' dt 2 title '±2 (95 % of points should lie between)', -2 with lines lc rgb '#d62728' dt 2 notitle, "
       "0 with lines lc rgb '#888888' notitle, "
    << q(name + ".dat") << " using 1:2 with points pt 7 ps 0.7 lc rgb '#1f77b4' title 'leave-one-out'\n";
  out.svg = render_svg_with_gnuplot(directory, name, s.str());
  return out;
}

namespace {

// The y range of a bar chart: from 0 up when every bar is positive (indices, shares); both
// ways, with the zero line drawn, when one is negative (residuals); fixed when no bar has a
// value at all, since gnuplot refuses to autoscale a plot without a single point ("all
// points y value undefined") and the report would be lost for want of a figure.
std::string bar_y_range(const std::vector<BarSeries>& series) {
  bool any = false, negative = false;
  for (const auto& b : series)
    for (std::size_t i = 0; i < b.values.size(); ++i) {
      if (!std::isfinite(b.values[i])) continue;
      any = true;
      const double e = i < b.errors.size() && std::isfinite(b.errors[i]) ? b.errors[i] : 0.0;
      negative = negative || b.values[i] - e < 0.0;
    }
  if (!any) return "set yrange [-1:1]\n";
  return negative ? "set yrange [*:*]\nset xzeroaxis\n" : "set yrange [0:*]\n";
}

}  // namespace

RenderedFigure bar_figure(const fs::path& directory, const std::string& name,
                          const std::vector<std::string>& labels, const std::vector<BarSeries>& series,
                          const std::string& title, const std::string& y_label) {
  fs::create_directories(directory);
  RenderedFigure out;
  // CSV: one row per label, columns index, then value and error per series.
  std::vector<std::string> header = {"index"};
  std::vector<std::vector<double>> cols(1);
  for (std::size_t i = 0; i < labels.size(); ++i) cols[0].push_back(static_cast<double>(i));
  for (const auto& b : series) {
    if (b.values.size() != labels.size() || (!b.errors.empty() && b.errors.size() != labels.size()))
      throw std::invalid_argument("bar figure " + name + ": series " + b.name + " does not match the labels");
    header.push_back(b.name);
    header.push_back(b.name + "_error");
    cols.push_back(b.values);
    cols.push_back(b.errors.empty() ? std::vector<double>(labels.size(), 0.0) : b.errors);
  }
  write_table(directory, name, header, cols);
  {
    std::ofstream f(directory / (name + "_labels.csv"));
    f << "index,label\n";
    for (std::size_t i = 0; i < labels.size(); ++i) f << i << "," << labels[i] << "\n";
  }
  out.data_files = {name + ".csv", name + "_labels.csv"};
  const double w = 0.8 / static_cast<double>(std::max<std::size_t>(1, series.size()));
  static const char* colors[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728"};
  int total_height = 0;
  const std::string layout = frame(520, 400, static_cast<int>(series.size()), false, total_height);
  std::ostringstream s;
  s << svg_preamble(name, 520, total_height) << layout << "set datafile separator whitespace\n"
    << "set title " << q(title) << "\nset ylabel " << q(y_label) << "\n" << bar_y_range(series)
    << "set xrange [-0.6:" << static_cast<double>(labels.size()) - 0.4 << "]\nset xtics (";
  for (std::size_t i = 0; i < labels.size(); ++i) s << (i ? ", " : "") << q(labels[i]) << " " << i;
  s << ")\nset style fill solid 0.8 border -1\nset boxwidth " << w << "\nplot ";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const double off = (static_cast<double>(k) - 0.5 * static_cast<double>(series.size() - 1)) * w;
    s << (k ? ", " : "") << q(name + ".dat") << " using ($1+" << off << "):" << 2 + 2 * k
      << " with boxes lc rgb " << q(colors[k % 4]) << " title " << q(series[k].name) << ", "
      << q(name + ".dat") << " using ($1+" << off << "):" << 2 + 2 * k << ":" << 3 + 2 * k
      << " with yerrorbars pt 7 ps 0 lc rgb '#222222' notitle";
  }
  s << "\n";
  out.svg = render_svg_with_gnuplot(directory, name, s.str());
  return out;
}

RenderedFigure line_figure(const fs::path& directory, const std::string& name,
                           const std::vector<LineSeries>& series, const std::string& title,
                           const std::string& x_label, const std::string& y_label) {
  fs::create_directories(directory);
  RenderedFigure out;
  std::size_t entries = 0;
  for (const auto& l : series) entries += !l.name.empty();
  int total_height = 0;
  const std::string layout = frame(520, 380, static_cast<int>(entries), false, total_height);
  std::ostringstream s;
  s << svg_preamble(name, 520, total_height) << layout << "set datafile separator whitespace\n"
    << "set title " << q(title) << "\nset xlabel " << q(x_label) << "\nset ylabel " << q(y_label)
    << "\nplot ";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const std::string stem = name + "_" + std::to_string(k);
    write_table(directory, stem, {"x", "y"}, {series[k].x, series[k].y});
    out.data_files.push_back(stem + ".csv");
    s << (k ? ", " : "") << q(stem + ".dat") << " using 1:2 with " << series[k].style << " "
      << (series[k].name.empty() ? "notitle" : "title " + q(series[k].name));
  }
  s << "\n";
  out.svg = render_svg_with_gnuplot(directory, name, s.str());
  return out;
}

}  // namespace demcal::calibrate
