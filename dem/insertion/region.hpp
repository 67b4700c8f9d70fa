#pragma once
// Regions particles are inserted into.

#include "dem/random.hpp"
#include "dem/vec3.hpp"

#include <memory>
#include <string>

namespace demcal::dem {

class Region {
 public:
  virtual ~Region() = default;
  // A uniformly random point at least `margin_m` inside the region.
  virtual Vec3 sample(Random& rng, double margin_m) const = 0;
  // True when a sphere of radius margin_m at p lies wholly inside.
  virtual bool contains(const Vec3& p, double margin_m) const = 0;
  virtual double volume_m3() const = 0;
  virtual Vec3 lower_m() const = 0;  // bounding box
  virtual Vec3 upper_m() const = 0;
  virtual std::string describe() const = 0;
};

// Axis-aligned box [lower, upper].
std::unique_ptr<Region> make_box_region(const Vec3& lower_m, const Vec3& upper_m);
// Vertical (z-axis) cylinder: centre of its base, radius, height.
std::unique_ptr<Region> make_cylinder_region(const Vec3& base_centre_m, double radius_m,
                                             double height_m);

}  // namespace demcal::dem
