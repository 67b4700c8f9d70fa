#pragma once
// A flat plate that is solid until `open_time_s` and then has a hole: the
// orifice of a silo or hopper discharge test, held shut while the fill
// settles. The hole is either a circle of `diameter_m` or a slot of `width_m`
// across the in-plane axis u and unbounded along v = normal × u (the orifice
// of a periodic slice). The plate is two-sided and either unbounded
// (outer_radius_m = 0) or a disk of outer_radius_m around the centre.

#include "dem/wall/wall.hpp"

namespace demcal::dem {

enum class OrificeShape { circle, slot };

class OrificePlateWall final : public Wall {
 public:
  // `opening_m` is the diameter of a circle or the width of a slot. `axis_u`
  // sets the slot's direction; for a circle it only orients the mesh and may
  // be the zero vector. Vectors are normalized (axis_u made perpendicular to
  // the normal). Throws std::invalid_argument naming the bad parameter.
  OrificePlateWall(const Vec3& centre_m, const Vec3& normal, const Vec3& axis_u,
                   OrificeShape shape, double opening_m, double open_time_s,
                   double outer_radius_m = 0.0);

  static OrificePlateWall circular(const Vec3& centre_m, const Vec3& normal, double diameter_m,
                                   double open_time_s, double outer_radius_m = 0.0);
  static OrificePlateWall slot(const Vec3& centre_m, const Vec3& normal, const Vec3& axis_u,
                               double width_m, double open_time_s, double outer_radius_m = 0.0);

  // Before opening the nearest point is the projection onto the plate; after,
  // a centre over the hole is pushed from the nearest point of the hole's rim.
  bool nearest_point(const Vec3& centre, double range_m, double t,
                     WallContactPoint& out) const override;
  std::string type_name() const override { return "orifice_plate"; }
  // Closed: the plate (disk, or the plane clipped to the box). Open: an
  // annulus of 48 quads (circle) or two rectangles (slot), reaching the outer
  // radius or, for an unbounded plate, past the box.
  SurfaceMesh mesh(double t, const Vec3& lo, const Vec3& hi) const override;
  Vec3 reference_point(double t) const override;
  // The opening time, so candidate lists are rebuilt when the hole appears.
  std::vector<double> change_times_s() const override;

  bool is_open(double t) const { return t >= open_time_s_; }
  // Opens (or re-schedules) the orifice; a protocol opens it once the fill is
  // at rest, a time not known when the plate is built.
  void set_open_time(double open_time_s);
  OrificeShape shape() const { return shape_; }
  double opening_m() const { return opening_m_; }
  double open_time_s() const { return open_time_s_; }
  double outer_radius_m() const { return outer_radius_m_; }
  const Vec3& normal() const { return normal_; }
  const Vec3& axis_u() const { return axis_u_; }

 private:
  struct InPlane {
    double a;  // along axis_u
    double b;  // along axis_v
  };
  // The nearest point of the solid part of the plate, in plate coordinates.
  InPlane nearest_solid(InPlane p, bool open) const;

  Vec3 centre_m_;
  Vec3 normal_;
  Vec3 axis_u_;
  Vec3 axis_v_;
  OrificeShape shape_;
  double opening_m_;
  double open_time_s_;
  double outer_radius_m_;  // 0: unbounded
};

}  // namespace demcal::dem
