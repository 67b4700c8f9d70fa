#pragma once
// Snapshots for ParaView: VTK XML PolyData (.vtp, ASCII) of the particles and
// of the walls, and ParaView collection files (.pvd) that list the snapshots
// with their simulated times so ParaView plays them as a time series.
//
// Particles are points (one vertex cell each, so they show without a filter)
// with point data radius_m, velocity_m_s, omega_rad_s, id, material; in
// ParaView, Glyph with a sphere scaled by radius_m (scale factor 2) shows the
// true sizes. Walls are polygons with cell data `wall` (the wall's index).
// Every file is written atomically (temporary + rename).

#include "dem/particles.hpp"
#include "dem/wall/wall.hpp"

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace demcal::dem {

class Simulation;

void write_particles_vtp(const std::filesystem::path& file, const Particles& particles,
                         double time_s);

// The walls' surfaces at time t; unbounded walls are clipped to the box [lo, hi].
void write_walls_vtp(const std::filesystem::path& file,
                     const std::vector<std::unique_ptr<Wall>>& walls, double time_s,
                     const Vec3& lo_m, const Vec3& hi_m);

// One entry per snapshot: its time and its file name relative to the .pvd.
void write_pvd(const std::filesystem::path& file,
               const std::vector<std::pair<double, std::string>>& entries);

// A numbered series in one directory: <dir>/vtk/particles_NNNNNN.vtp and
// walls_NNNNNN.vtp, listed in <dir>/particles.pvd and <dir>/walls.pvd.
class VtkSeries {
 public:
  explicit VtkSeries(std::filesystem::path directory);

  // Writes the next snapshot and rewrites both collections, so that after a
  // crash they list exactly the snapshots that were completed.
  void write(const Simulation& sim);

  std::size_t snapshots() const { return times_.size(); }
  // Time of the last snapshot (negative before the first).
  double last_time_s() const { return times_.empty() ? -1.0 : times_.back(); }
  std::filesystem::path particles_pvd() const { return directory_ / "particles.pvd"; }
  std::filesystem::path walls_pvd() const { return directory_ / "walls.pvd"; }

 private:
  std::filesystem::path directory_;
  std::vector<double> times_;
};

}  // namespace demcal::dem
