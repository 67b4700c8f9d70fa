#pragma once
// What a reader would see wrong in one of the report's gnuplot SVG figures, read
// off the SVG itself: text boxes (from each text's position, font size, anchor
// and length) that overlap — a legend over the axis title, tick labels on top of
// each other —, a legend entry inside the plot area (where it hides data), or a
// figure with nothing drawn in it. The HTML test runs it on every figure of both
// reports.

#include <string>
#include <vector>

namespace demcal::calibrate {

struct SvgTextBox {
  std::string text;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // estimated bounding box, SVG pixels
  bool legend = false;                    // inside a plot element's group: a key entry
};

std::vector<SvgTextBox> svg_text_boxes(const std::string& svg);

// Empty when the figure reads cleanly; otherwise one sentence per problem.
std::vector<std::string> svg_layout_problems(const std::string& svg);

// Every <svg>...</svg> inlined in an HTML page, in order.
std::vector<std::string> svgs_in_html(const std::string& html);

}  // namespace demcal::calibrate
