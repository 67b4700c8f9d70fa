#pragma once
// A wall is a rigid surface particles touch. Each wall type answers one
// question — the point of its surface nearest to a sphere centre — and the
// engine turns that into a contact with the same law as between particles,
// using the wall's material. Walls may move at a prescribed velocity.

#include "dem/vec3.hpp"

#include <limits>
#include <string>
#include <vector>

namespace demcal::dem {

// A prescribed rigid translation: at rest until start, then velocity until
// stop (gates, lifted cylinders). Times in seconds of simulated time.
struct WallMotion {
  Vec3 velocity_m_s;
  double start_s = 0.0;
  double stop_s = std::numeric_limits<double>::infinity();

  Vec3 displacement_m(double t) const;
  Vec3 velocity_at(double t) const;
  bool moves() const { return norm2(velocity_m_s) > 0.0; }
};

// A polygon mesh (convex polygons of any vertex count) approximating a wall's surface, for VTK snapshots.
struct SurfaceMesh {
  std::vector<Vec3> points;
  std::vector<std::vector<int>> polygons;  // indices into points
};

struct WallContactPoint {
  Vec3 point_m;      // nearest point of the surface
  Vec3 normal;       // unit, from the surface towards the sphere centre
  double distance_m; // centre to surface, along normal (may be negative for one-sided walls)
};

class Wall {
 public:
  virtual ~Wall() = default;

  // The nearest surface point to `centre` at time t, considering only surface
  // within `range_m` of it. Returns false when no surface is that near.
  // `centre` is in world coordinates; walls apply their own motion.
  virtual bool nearest_point(const Vec3& centre, double range_m, double t,
                             WallContactPoint& out) const = 0;

  // Type name as used in configs ("plane", "cylinder", ...).
  virtual std::string type_name() const = 0;
  // The surface at time t for drawing; infinite surfaces are clipped to the box [lo, hi].
  virtual SurfaceMesh mesh(double t, const Vec3& lo, const Vec3& hi) const = 0;
  // The point torques on this wall are taken about (world coordinates, time t).
  virtual Vec3 reference_point(double t) const = 0;

  const WallMotion& motion() const { return motion_; }
  void set_motion(const WallMotion& m) { motion_ = m; }
  Vec3 velocity_at(double t) const { return motion_.velocity_at(t); }

  // When the geometry changes by itself (an orifice opening), the engine must
  // refresh its candidate lists; walls report the times this happens.
  virtual std::vector<double> change_times_s() const { return {}; }

 protected:
  WallMotion motion_;
};

}  // namespace demcal::dem
