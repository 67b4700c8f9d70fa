#include "dem/measure/fill_bulk_density.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace demcal::dem {

double fill_surface_height_m(const std::vector<Vec3>& position_m,
                             const std::vector<double>& radius_m, const FillChamber& c) {
  const double ru = c.upper_radius_m;
  const double bin = c.bin_width_m;
  const int nb = std::max(1, static_cast<int>(1.6 * ru / bin));
  std::vector<double> top(static_cast<std::size_t>(nb), -1.0);
  for (std::size_t i = 0; i < position_m.size(); ++i) {
    const Vec3& x = position_m[i];
    if (x.z < c.orifice_plane_z_m) continue;
    const double s = c.slice ? x.x : std::copysign(std::hypot(x.x, x.y), x.x);
    const int b = static_cast<int>(std::floor((s + 0.8 * ru) / bin));
    if (b < 0 || b >= nb) continue;
    top[static_cast<std::size_t>(b)] =
        std::max(top[static_cast<std::size_t>(b)], x.z + radius_m[i]);
  }
  double sum = 0.0;
  int n = 0;
  for (double t : top)
    if (t > 0.0) {
      sum += t;
      ++n;
    }
  return n > 0 ? sum / n : c.orifice_plane_z_m;
}

double chamber_volume_below_m3(double height_m, const FillChamber& c) {
  const double ru = c.upper_radius_m, r0 = c.orifice_radius_m;
  const double z = height_m - c.orifice_plane_z_m;
  if (z <= 0.0) return 0.0;
  double v = 0.0;
  const double zc = std::min(z, c.hopper_height_m);
  if (zc > 0.0) {
    const double r1 = r0 + (ru - r0) * zc / c.hopper_height_m;
    v += c.slice ? (r0 + r1) * zc * c.slice_thickness_m
                 : std::numbers::pi * zc * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0;
  }
  if (z > c.hopper_height_m) {
    const double zz = z - c.hopper_height_m;
    v += c.slice ? 2.0 * ru * zz * c.slice_thickness_m : std::numbers::pi * ru * ru * zz;
  }
  return v;
}

}  // namespace demcal::dem
