#pragma once
// The simulation box. Along a periodic axis particles leaving one face enter
// through the opposite one and contacts act across it; along a bounded axis a
// particle outside the box is an error (it escaped the walls; the integrator's
// stability check, dem/verlet_kicks.hpp, tests each step against these bounds).

#include "dem/vec3.hpp"

#include <array>

namespace demcal::dem {

struct Domain {
  Vec3 lower_m{0, 0, 0};
  Vec3 upper_m{1, 1, 1};
  std::array<bool, 3> periodic{false, false, false};

  Vec3 length_m() const { return upper_m - lower_m; }
  // Throws std::invalid_argument when the box is empty or not finite.
  void validate() const;
};

}  // namespace demcal::dem
