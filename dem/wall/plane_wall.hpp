#pragma once
// An infinite one-sided plane: floors, side walls of a box, the periodic
// slice's front and back. The normal points into the space where particles
// live; everything behind the plane is solid, so a particle that has sunk
// through it (negative distance) is still pushed back out along the normal.

#include "dem/wall/wall.hpp"

namespace demcal::dem {

class PlaneWall final : public Wall {
 public:
  // `normal` need not be unit length; it is normalized. Throws
  // std::invalid_argument for a zero or non-finite normal or point.
  PlaneWall(const Vec3& point_m, const Vec3& normal);

  // Candidate whenever the signed distance is below range_m, including any
  // negative distance (the plane is one-sided).
  bool nearest_point(const Vec3& centre, double range_m, double t,
                     WallContactPoint& out) const override;
  std::string type_name() const override { return "plane"; }
  // The plane clipped to the box [lo, hi]: one convex polygon (empty when the
  // plane misses the box).
  SurfaceMesh mesh(double t, const Vec3& lo, const Vec3& hi) const override;
  Vec3 reference_point(double t) const override;

  const Vec3& point_m() const { return point_m_; }
  const Vec3& normal() const { return normal_; }

 private:
  Vec3 point_m_;
  Vec3 normal_;
};

// The convex polygon where the plane through `point_m` with unit `normal`
// cuts the box [lo, hi], its vertices ordered counter-clockwise seen from the
// normal's side. Empty when the plane misses the box or touches it only in
// an edge or a corner. Shared by the walls that draw infinite planes.
SurfaceMesh plane_box_section(const Vec3& point_m, const Vec3& normal, const Vec3& lo,
                              const Vec3& hi);

}  // namespace demcal::dem
