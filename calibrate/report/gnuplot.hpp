#pragma once
// Figures for the reports are drawn by gnuplot (a Debian package, like every
// dependency): demcal writes the data as CSV and a gnuplot script next to it,
// runs gnuplot, and embeds the SVG it writes in the HTML page. The CSV and the
// script stay beside the report, so every figure can be redrawn or re-plotted
// with other tools from exactly the numbers shown.

#include <filesystem>
#include <string>

namespace demcal::calibrate {

// Runs `gnuplot <name>.gp` in `directory` after writing `script` there; the
// script must `set output "<name>.svg"` (svg_preamble does). Returns the SVG
// text. Throws std::runtime_error with gnuplot's own message when gnuplot is
// missing or the script fails.
std::string render_svg_with_gnuplot(const std::filesystem::path& directory, const std::string& name,
                                    const std::string& script);

// "set terminal svg ...; set output '<name>.svg'" plus the report's common style.
std::string svg_preamble(const std::string& name, int width_px = 640, int height_px = 480);

// A string as a gnuplot single-quoted literal (quotes doubled).
std::string gnuplot_quote(const std::string& text);

}  // namespace demcal::calibrate
