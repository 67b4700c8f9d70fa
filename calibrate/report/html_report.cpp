#include "calibrate/report/html_report.hpp"

#include "io/atomic_file.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace demcal::calibrate {

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string format_number(double v, int precision) {
  if (!std::isfinite(v)) return "—";
  std::ostringstream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::heading(const std::string& text, int level) {
  // Appended piecewise: GCC 12 warns (-Wrestrict, a false positive) on the
  // chained operator+ of short strings here.
  const int h = std::clamp(level, 1, 4);
  body_.append("<h").append(std::to_string(h)).append(">");
  body_.append(html_escape(text));
  body_.append("</h").append(std::to_string(h)).append(">\n");
}

void HtmlReport::paragraph(const std::string& text) { body_ += "<p>" + html_escape(text) + "</p>\n"; }

void HtmlReport::raw_html(const std::string& html) { body_ += html + "\n"; }

void HtmlReport::warning(const std::string& text) {
  body_ += "<p class=\"warning\">" + html_escape(text) + "</p>\n";
}

void HtmlReport::table(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::string>>& rows, const std::string& caption) {
  std::ostringstream s;
  s << "<table>\n";
  if (!caption.empty()) s << "<caption>" << html_escape(caption) << "</caption>\n";
  s << "<tr>";
  for (const auto& h : header) s << "<th>" << html_escape(h) << "</th>";
  s << "</tr>\n";
  for (const auto& row : rows) {
    s << "<tr>";
    for (std::size_t i = 0; i < std::max(row.size(), header.size()); ++i)
      s << "<td>" << (i < row.size() ? html_escape(row[i]) : "") << "</td>";
    s << "</tr>\n";
  }
  s << "</table>\n";
  body_ += s.str();
}

void HtmlReport::figure(const std::string& svg, const std::string& caption,
                        const std::vector<std::string>& data_files) {
  // gnuplot's SVG starts with an XML declaration and a DOCTYPE, which are not
  // allowed inside an HTML body; the <svg> element itself is.
  const auto start = svg.find("<svg");
  std::ostringstream s;
  s << "<figure>\n" << (start == std::string::npos ? svg : svg.substr(start)) << "\n<figcaption>"
    << html_escape(caption);
  if (!data_files.empty()) {
    s << " <span class=\"data\">Data:";
    for (const auto& f : data_files) s << " <a href=\"" << html_escape(f) << "\">" << html_escape(f) << "</a>";
    s << "</span>";
  }
  s << "</figcaption>\n</figure>\n";
  body_ += s.str();
}

std::string HtmlReport::html() const {
  std::ostringstream s;
  s << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>"
    << html_escape(title_) << "</title>\n<style>\n"
    << "body{font-family:Helvetica,Arial,sans-serif;max-width:1240px;margin:2em auto;padding:0 1em;"
       "color:#222;line-height:1.45}\n"
    << "h1{border-bottom:2px solid #345;padding-bottom:.2em}h2{margin-top:1.8em;color:#345}\n"
    << "table{border-collapse:collapse;margin:1em 0;font-size:.92em}"
       "td,th{border:1px solid #bbb;padding:.25em .6em;text-align:right}"
       "th{background:#eef2f6}caption{caption-side:top;text-align:left;font-weight:bold;padding:.3em 0}\n"
    << "figure{display:inline-block;margin:.8em .6em;vertical-align:top;width:560px;max-width:100%}"
       "figure svg{width:100%;height:auto}"
       "figcaption{font-size:.9em;color:#333}\n"
    << ".headline{border:2px solid #345;background:#f6f9fc;padding:.3em 1em;margin:1em 0}"
       ".headline td{text-align:left}.headline caption{font-size:1.1em}\n"
    << ".warning{background:#fff3cd;border-left:4px solid #e0a800;padding:.5em .8em}"
       ".data{color:#666}code{background:#f3f3f3;padding:0 .2em}\n"
    << "</style>\n</head>\n<body>\n<h1>" << html_escape(title_) << "</h1>\n"
    << body_ << "</body>\n</html>\n";
  return s.str();
}

void write_text_atomically(const std::filesystem::path& path, const std::string& text) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  io::write_file_atomically(path, text);
}

void HtmlReport::write(const std::filesystem::path& path) const { write_text_atomically(path, html()); }

}  // namespace demcal::calibrate
