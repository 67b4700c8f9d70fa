#include "calibrate/report/gnuplot.hpp"

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>

namespace demcal::calibrate {

std::string gnuplot_quote(const std::string& text) {
  std::string q = "'";
  for (char c : text) {
    if (c == '\'') q += "''";
    else q += c;
  }
  return q + "'";
}

std::string svg_preamble(const std::string& name, int width_px, int height_px) {
  std::ostringstream s;
  s << "set terminal svg size " << width_px << "," << height_px
    << " dynamic noenhanced font 'Helvetica,12' background rgb 'white'\n"
    << "set output " << gnuplot_quote(name + ".svg") << "\n"
    << "set datafile separator ','\n"
    << "set key noautotitle\n"
    << "set grid lc rgb '#dddddd'\n"
    << "set border lc rgb '#444444'\n";
  return s.str();
}

std::string render_svg_with_gnuplot(const std::filesystem::path& directory, const std::string& name,
                                    const std::string& script) {
  std::filesystem::create_directories(directory);
  const auto script_path = directory / (name + ".gp");
  {
    std::ofstream f(script_path);
    if (!f) throw std::runtime_error("cannot write " + script_path.string());
    f << script;
  }
  const auto svg_path = directory / (name + ".svg");
  std::filesystem::remove(svg_path);
  // cd into the directory so the script's data file names are relative: the
  // script beside the CSVs can be rerun by hand as it is.
  const std::string command = "cd " + gnuplot_quote(directory.string()) + " && gnuplot " +
                              gnuplot_quote(name + ".gp") + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot start gnuplot (is the gnuplot-nox package installed?)");
  std::string messages;
  std::array<char, 512> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe)) messages += buffer.data();
  const int status = pclose(pipe);
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code == 127)
    throw std::runtime_error("gnuplot not found: install the gnuplot-nox package (figures are drawn with it)");
  if (code != 0 || !std::filesystem::exists(svg_path))
    throw std::runtime_error("gnuplot failed on " + script_path.string() + ": " + messages);
  std::ifstream in(svg_path);
  std::ostringstream svg;
  svg << in.rdbuf();
  return svg.str();
}

}  // namespace demcal::calibrate
