#include "engines/deck.hpp"

#include "engines/apparatus_layout.hpp"

#include <fstream>
#include <iomanip>
#include <locale>
#include <sstream>
#include <stdexcept>

namespace demcal::engines {

std::string deck_number(double v) {
  // The shortest precision that reads back exactly: golden files stay readable
  // and the engine gets the mapped value to the last bit.
  for (int p = 6; p <= 17; ++p) {
    std::ostringstream s;
    s.imbue(std::locale::classic());
    s << std::setprecision(p) << v;
    std::istringstream back(s.str());
    back.imbue(std::locale::classic());
    double r = 0.0;
    back >> r;
    if (r == v || p == 17) return s.str();
  }
  return "";
}

std::string lattice_fill_region_command(const LatticeFill& f, const std::string& name,
                                        double z_lower_m) {
  const auto n = deck_number;
  if (f.cylinder_radius_m > 0.0)
    return "region          " + name + " cylinder z 0 0 " + n(f.cylinder_radius_m) + " " +
           n(z_lower_m) + " " + n(f.region.upper_m.z) + " units box\n";
  return "region          " + name + " block " + n(f.region.lower_m.x) + " " +
         n(f.region.upper_m.x) + " " + n(f.region.lower_m.y) + " " + n(f.region.upper_m.y) + " " +
         n(z_lower_m) + " " + n(f.region.upper_m.z) + " units box\n";
}

void write_deck_files(const Deck& deck, const std::filesystem::path& directory) {
  std::filesystem::create_directories(directory);
  auto put = [&](const std::string& name, const std::string& text) {
    std::ofstream out(directory / name, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + (directory / name).string());
  };
  put(deck.script_name, deck.script);
  for (const auto& [name, text] : deck.files) put(name, text);
}

int deck_revision(const std::string& engine) { return engine == "liggghts" ? 2 : 1; }

}  // namespace demcal::engines
