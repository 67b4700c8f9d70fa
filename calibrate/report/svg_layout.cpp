#include "calibrate/report/svg_layout.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <regex>

namespace demcal::calibrate {
namespace {

std::size_t utf8_length(const std::string& s) {
  std::size_t n = 0;
  for (unsigned char c : s) n += (c & 0xC0) != 0x80;
  return n;
}

std::string attribute(const std::string& tag, const std::string& name) {
  const auto k = tag.find(name + "=\"");
  if (k == std::string::npos) return "";
  const auto start = k + name.size() + 2;
  return tag.substr(start, tag.find('"', start) - start);
}

bool overlap(const SvgTextBox& a, const SvgTextBox& b) {
  return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

// Each plot element's group, <g id="..._plot_N"> up to its matching </g>: legend entries
// and the element's own drawing sit inside.
std::vector<std::pair<std::size_t, std::size_t>> plot_group_spans(const std::string& svg) {
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  for (std::size_t g = svg.find("<g id=\""); g != std::string::npos;
       g = svg.find("<g id=\"", g + 1)) {
    const auto id_end = svg.find('"', g + 7);
    if (svg.substr(g + 7, id_end - g - 7).find("_plot_") == std::string::npos) continue;
    int depth = 0;
    std::size_t end = svg.size();
    for (std::size_t i = g; i < svg.size(); ++i) {
      if (svg.compare(i, 2, "<g") == 0 && i + 2 < svg.size() &&
          (svg[i + 2] == ' ' || svg[i + 2] == '>')) {
        ++depth;
      } else if (svg.compare(i, 4, "</g>") == 0 && --depth == 0) {
        end = i;
        break;
      }
    }
    spans.push_back({g, end});
  }
  return spans;
}

}  // namespace

std::vector<SvgTextBox> svg_text_boxes(const std::string& svg) {
  std::vector<SvgTextBox> out;
  const auto plot_groups = plot_group_spans(svg);
  static const std::regex translate(
      R"(translate\(([-0-9.]+),([-0-9.]+)\)( rotate\(([-0-9.]+)\))?)");
  for (std::size_t k = svg.find("<g transform=\"translate("); k != std::string::npos;
       k = svg.find("<g transform=\"translate(", k + 1)) {
    const auto end_tag = svg.find('>', k);
    const std::string tag = svg.substr(k, end_tag - k);
    const auto t0 = svg.find("<text>", end_tag);
    const auto close = svg.find("</g>", end_tag);
    if (t0 == std::string::npos || t0 > close) continue;
    const auto t1 = svg.find("</text>", t0);
    std::string text = svg.substr(t0 + 6, t1 - t0 - 6);
    // Strip inner markup (tspans).
    text = std::regex_replace(text, std::regex("<[^>]*>"), "");
    const auto first = text.find_first_not_of(' ');
    if (first == std::string::npos) continue;
    text = text.substr(first);
    std::smatch m;
    if (!std::regex_search(tag, m, translate)) continue;
    const double x = std::stod(m[1]), y = std::stod(m[2]);
    const bool rotated = m[4].matched && std::abs(std::stod(m[4])) > 1;
    double size = 12;
    if (const auto fs = attribute(tag, "font-size"); !fs.empty()) size = std::stod(fs);
    const std::string anchor = attribute(tag, "text-anchor");
    // Helvetica averages about 0.55 em a character; ascent 0.75 em, descent 0.25 em.
    const double w = 0.55 * size * static_cast<double>(utf8_length(text));
    double a0 = 0, a1 = w;
    if (anchor == "middle") a0 = -w / 2, a1 = w / 2;
    if (anchor == "end") a0 = -w, a1 = 0;
    SvgTextBox b;
    b.text = text;
    if (!rotated) {
      b.x0 = x + a0, b.x1 = x + a1, b.y0 = y - 0.75 * size, b.y1 = y + 0.25 * size;
    } else {  // rotate(270): the text runs upwards from (x, y)
      b.x0 = x - 0.75 * size, b.x1 = x + 0.25 * size, b.y0 = y - a1, b.y1 = y - a0;
    }
    for (const auto& [g0, g1] : plot_groups) b.legend = b.legend || (k > g0 && k < g1);
    out.push_back(b);
  }
  return out;
}

std::vector<std::string> svg_layout_problems(const std::string& svg) {
  std::vector<std::string> problems;
  if (svg.find("<svg") == std::string::npos) return {"no <svg> element"};
  const auto boxes = svg_text_boxes(svg);
  // Text cut off at the figure's edge.
  static const std::regex view_box(R"re(viewBox="([-0-9.]+) ([-0-9.]+) ([-0-9.]+) ([-0-9.]+)")re");
  std::smatch vb;
  if (std::regex_search(svg, vb, view_box)) {
    const double w = std::stod(vb[3]), h = std::stod(vb[4]);
    for (const auto& b : boxes)
      if (b.x0 < -1 || b.y0 < -1 || b.x1 > w + 1 || b.y1 > h + 1)
        problems.push_back("text \"" + b.text + "\" runs off the figure");
  }
  for (std::size_t i = 0; i < boxes.size(); ++i)
    for (std::size_t j = i + 1; j < boxes.size(); ++j)
      if (overlap(boxes[i], boxes[j]))
        problems.push_back("text \"" + boxes[i].text + "\" overlaps \"" + boxes[j].text + "\"");
  // The plot area: gnuplot's border, a closed path of four corners.
  static const std::regex border(
      R"(d='M([-0-9.]+),([-0-9.]+) L([-0-9.]+),([-0-9.]+) L([-0-9.]+),([-0-9.]+) L([-0-9.]+),([-0-9.]+) L([-0-9.]+),([-0-9.]+) Z)");
  std::vector<std::array<double, 4>> areas;
  for (std::sregex_iterator it(svg.begin(), svg.end(), border), end; it != end; ++it) {
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    for (int c = 0; c < 5; ++c) {
      x0 = std::min(x0, std::stod((*it)[1 + 2 * c])),
      x1 = std::max(x1, std::stod((*it)[1 + 2 * c]));
      y0 = std::min(y0, std::stod((*it)[2 + 2 * c])),
      y1 = std::max(y1, std::stod((*it)[2 + 2 * c]));
    }
    if (x1 - x0 > 40 && y1 - y0 > 40) areas.push_back({x0, y0, x1, y1});
  }
  if (areas.empty()) problems.push_back("no plot border found");
  for (const auto& b : boxes) {
    if (!b.legend) continue;
    for (const auto& a : areas)
      if (b.x0 < a[2] && a[0] < b.x1 && b.y0 < a[3] && a[1] < b.y1)
        problems.push_back("legend entry \"" + b.text + "\" lies inside the plot area");
  }
  // Something drawn: a plot element with a path of at least two points, or an image.
  bool drawn = svg.find("<image") != std::string::npos;
  for (const auto& [g0, g1] : plot_group_spans(svg)) {
    const auto seg = svg.substr(g0, g1 - g0);
    // Points are <use> elements (a key sample is one more); a line is a path of three or
    // more points (a key sample has two).
    std::size_t uses = 0;
    for (std::size_t u = seg.find("<use"); u != std::string::npos; u = seg.find("<use", u + 1))
      ++uses;
    drawn = drawn || uses >= 2;
    for (std::size_t d = seg.find("d='M"); !drawn && d != std::string::npos;
         d = seg.find("d='M", d + 1)) {
      const auto e = seg.find('\'', d + 4);
      const auto path = seg.substr(d, e - d);
      drawn = std::count(path.begin(), path.end(), ',') >= 3;
    }
  }
  if (!drawn) problems.push_back("nothing is drawn in the plot");
  return problems;
}

std::vector<std::string> svgs_in_html(const std::string& html) {
  std::vector<std::string> out;
  for (std::size_t k = html.find("<svg"); k != std::string::npos; k = html.find("<svg", k + 1)) {
    const auto e = html.find("</svg>", k);
    if (e == std::string::npos) break;
    out.push_back(html.substr(k, e + 6 - k));
  }
  return out;
}

}  // namespace demcal::calibrate
