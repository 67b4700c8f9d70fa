#pragma once
// One self-contained HTML page: headings, paragraphs, tables and inline SVG
// figures, with the links to the CSV/JSON files behind each figure. No
// scripts, no external style sheets or fonts: the page opens from a file, is
// archived as one file, and renders the same everywhere.

#include <filesystem>
#include <string>
#include <vector>

namespace demcal::calibrate {

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);

  void heading(const std::string& text, int level = 2);
  // Plain text, HTML-escaped.
  void paragraph(const std::string& text);
  // Already-formatted HTML (for emphasis, lists); the caller escapes its parts.
  void raw_html(const std::string& html);
  // A table; each cell is HTML-escaped. Rows shorter than the header are padded.
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
             const std::string& caption = "");
  // An inline SVG figure with a caption and links (relative paths) to its data.
  void figure(const std::string& svg, const std::string& caption,
              const std::vector<std::string>& data_files = {});
  // A highlighted remark (warnings: surrogate error above the DEM's scatter, ...).
  void warning(const std::string& text);

  std::string html() const;
  // Writes the page atomically (temporary file, then rename).
  void write(const std::filesystem::path& path) const;

 private:
  std::string title_;
  std::string body_;
};

std::string html_escape(const std::string& text);

// A number for a report's text and tables: `precision` significant digits,
// "—" when not finite.
std::string format_number(double v, int precision = 4);

// Creates the parent directories and writes `text` through demcal's one atomic
// writer (io/atomic_file.hpp): a reader never sees half a report.
void write_text_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace demcal::calibrate
