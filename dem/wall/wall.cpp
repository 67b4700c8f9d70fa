#include "dem/wall/wall.hpp"

#include <algorithm>

namespace demcal::dem {

Vec3 WallMotion::displacement_m(double t) const {
  if (!(t > start_s)) return {};
  // Clamped at zero so a stop time before the start means "never moves"
  // rather than a backwards jump.
  const double moving_s = std::max(0.0, std::min(t, stop_s) - start_s);
  return moving_s > 0.0 ? velocity_m_s * moving_s : Vec3{};
}

Vec3 WallMotion::velocity_at(double t) const {
  return (start_s <= t && t < stop_s) ? velocity_m_s : Vec3{};
}

}  // namespace demcal::dem
