#pragma once
// Reads what an engine run writes: a LAMMPS/LIGGGHTS `custom` dump of the
// particles (id type x y z radius [vx vy vz], any order, other columns
// ignored) and the discharged-mass series m(t) a deck's fix print writes.
// Strict: anything unexpected throws DumpFormatError "<file>:<line>: <what>",
// never a guess; a truncated file is an error, not fewer particles.

#include "dem/vec3.hpp"

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace demcal::engines {

class DumpFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ParticleDump {
  std::int64_t timestep = 0;
  dem::Vec3 box_lower_m;
  dem::Vec3 box_upper_m;
  std::vector<std::int64_t> id;
  std::vector<int> type;
  std::vector<dem::Vec3> position_m;
  std::vector<double> radius_m;
  std::vector<dem::Vec3> velocity_m_s;  // zeros when the dump has no vx vy vz
  bool has_velocity = false;

  std::size_t size() const { return id.size(); }
};

// The last snapshot of the file (a write_dump has exactly one).
ParticleDump read_custom_dump(const std::filesystem::path& path);
// The same from text; `name` is what errors call the file.
ParticleDump parse_custom_dump(const std::string& text, const std::string& name);

// m(t) after opening: "# ..." comment lines, then rows
// "t_since_opening_s discharged_mass_kg mass_above_orifice_kg"; times strictly
// increasing, masses finite and >= 0.
struct MassSeries {
  std::vector<double> time_s;
  std::vector<double> discharged_kg;
  std::vector<double> above_orifice_kg;
  // The fill: discharged + above at the first row.
  double fill_mass_kg() const;
};

MassSeries read_mass_series(const std::filesystem::path& path);
MassSeries parse_mass_series(const std::string& text, const std::string& name);

}  // namespace demcal::engines
