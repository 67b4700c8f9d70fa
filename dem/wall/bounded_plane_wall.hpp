#pragma once
// Finite flat walls: gates, baffles, the bottom of a cylinder, lids. They are
// thin and two-sided: a particle is pushed away from the nearest point of the
// rectangle or disk, whichever side (or edge) it approaches from.

#include "dem/wall/wall.hpp"

#include <memory>

namespace demcal::dem {

// A rectangle centred on `centre_m` with sides along `axis_u` and
// v = normal × axis_u. `axis_u` is made perpendicular to the normal (so it
// need only be roughly in-plane) and both are normalized.
class RectangleWall final : public Wall {
 public:
  RectangleWall(const Vec3& centre_m, const Vec3& normal, const Vec3& axis_u,
                double half_length_u_m, double half_length_v_m);

  bool nearest_point(const Vec3& centre, double range_m, double t,
                     WallContactPoint& out) const override;
  std::string type_name() const override { return "rectangle"; }
  SurfaceMesh mesh(double t, const Vec3& lo, const Vec3& hi) const override;
  Vec3 reference_point(double t) const override;

  const Vec3& normal() const { return normal_; }
  const Vec3& axis_u() const { return axis_u_; }
  const Vec3& axis_v() const { return axis_v_; }

 private:
  Vec3 centre_m_;
  Vec3 normal_;
  Vec3 axis_u_;
  Vec3 axis_v_;
  double half_u_m_;
  double half_v_m_;
};

// A disk of radius `radius_m` centred on `centre_m`, perpendicular to `normal`.
class DiskWall final : public Wall {
 public:
  DiskWall(const Vec3& centre_m, const Vec3& normal, double radius_m);

  bool nearest_point(const Vec3& centre, double range_m, double t,
                     WallContactPoint& out) const override;
  std::string type_name() const override { return "disk"; }
  // A fan of 48 triangles.
  SurfaceMesh mesh(double t, const Vec3& lo, const Vec3& hi) const override;
  Vec3 reference_point(double t) const override;

  const Vec3& normal() const { return normal_; }
  double radius_m() const { return radius_m_; }

 private:
  Vec3 centre_m_;
  Vec3 normal_;
  double radius_m_;
};

// The rectangle between the points (x0_m, z0_m) and (x1_m, z1_m) of the
// xz-plane, spanning the slab 0 <= y <= depth_m: the side or hopper wall of a
// periodic slice. The normal is chosen so that v = n × u is +y.
std::unique_ptr<RectangleWall> make_slab_segment_wall(double x0_m, double z0_m, double x1_m,
                                                      double z1_m, double depth_m);

}  // namespace demcal::dem
