#pragma once
// The lateral surface of a conical frustum: funnels, hoppers, the converging
// section of a silo. Two-sided and open at both ends. Radii may reach zero at
// one end (a full cone with its apex there), not at both.

#include "dem/wall/wall.hpp"

namespace demcal::dem {

class ConeWall final : public Wall {
 public:
  // Axis from `base_m` along `axis` (normalized) for `length_m`; the radius
  // goes linearly from `radius_base_m` at the base to `radius_end_m` at the
  // far end.
  ConeWall(const Vec3& base_m, const Vec3& axis, double length_m, double radius_base_m,
           double radius_end_m);

  bool nearest_point(const Vec3& centre, double range_m, double t,
                     WallContactPoint& out) const override;
  std::string type_name() const override { return "cone"; }
  // 48 quads around (triangles meeting at an apex).
  SurfaceMesh mesh(double t, const Vec3& lo, const Vec3& hi) const override;
  // The base centre.
  Vec3 reference_point(double t) const override;

  const Vec3& axis() const { return axis_; }
  double length_m() const { return length_m_; }
  double radius_base_m() const { return radius_base_m_; }
  double radius_end_m() const { return radius_end_m_; }

 private:
  Vec3 base_m_;
  Vec3 axis_;
  double length_m_;
  double radius_base_m_;
  double radius_end_m_;
};

}  // namespace demcal::dem
