#pragma once
// The lateral surface of a finite circular cylinder: the container of a
// column collapse (lifted to release the heap), a rotating drum's shell.
// Open at both ends (add disks for lids) and two-sided, so particles are held
// inside or kept off from outside alike.

#include "dem/wall/wall.hpp"

namespace demcal::dem {

class CylinderWall final : public Wall {
 public:
  // Axis from `base_m` along `axis` (normalized) for `length_m`.
  CylinderWall(const Vec3& base_m, const Vec3& axis, double length_m, double radius_m);

  bool nearest_point(const Vec3& centre, double range_m, double t,
                     WallContactPoint& out) const override;
  std::string type_name() const override { return "cylinder"; }
  // 48 quads around.
  SurfaceMesh mesh(double t, const Vec3& lo, const Vec3& hi) const override;
  // The base centre.
  Vec3 reference_point(double t) const override;

  const Vec3& axis() const { return axis_; }
  double length_m() const { return length_m_; }
  double radius_m() const { return radius_m_; }

 private:
  Vec3 base_m_;
  Vec3 axis_;
  double length_m_;
  double radius_m_;
};

}  // namespace demcal::dem
