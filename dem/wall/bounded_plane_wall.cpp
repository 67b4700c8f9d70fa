#include "dem/wall/bounded_plane_wall.hpp"

#include "dem/wall/wall_checks.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace demcal::dem {

namespace {

constexpr int kSegments = 48;

using wall_checks::checked_point;
using wall_checks::checked_positive;
using wall_checks::checked_unit;
using wall_checks::fail;

// The in-plane axis with its normal component removed, so callers may pass a
// roughly in-plane direction.
Vec3 in_plane_axis(const char* where, const Vec3& axis_u, const Vec3& unit_normal) {
  const Vec3 u = checked_unit(where, axis_u, "axis_u");
  const Vec3 along = u - dot(u, unit_normal) * unit_normal;
  if (norm(along) < 1e-6) fail(where, "axis_u must not be parallel to normal");
  return normalized(along);
}

// Shared tail of the two-sided walls: the contact from the nearest point q
// (with motion undone), falling back on the face normal when the centre lies
// on the surface and the direction c - q is rounding noise.
bool two_sided_contact(const Vec3& c, const Vec3& q, const Vec3& face_normal, double tiny_m,
                       double range_m, const Vec3& shift, WallContactPoint& out) {
  const Vec3 diff = c - q;
  const double distance = norm(diff);
  if (!(distance < range_m)) return false;
  out.point_m = q + shift;
  out.normal = distance > tiny_m ? diff / distance : face_normal;
  out.distance_m = distance;
  return true;
}

}  // namespace

RectangleWall::RectangleWall(const Vec3& centre_m, const Vec3& normal, const Vec3& axis_u,
                             double half_length_u_m, double half_length_v_m) {
  const char* where = "rectangle wall";
  centre_m_ = checked_point(where, centre_m, "centre_m");
  normal_ = checked_unit(where, normal, "normal");
  axis_u_ = in_plane_axis(where, axis_u, normal_);
  axis_v_ = cross(normal_, axis_u_);
  half_u_m_ = checked_positive(where, half_length_u_m, "half_length_u_m");
  half_v_m_ = checked_positive(where, half_length_v_m, "half_length_v_m");
}

bool RectangleWall::nearest_point(const Vec3& centre, double range_m, double t,
                                  WallContactPoint& out) const {
  const Vec3 shift = motion_.displacement_m(t);
  const Vec3 c = centre - shift;
  const Vec3 r = c - centre_m_;
  // Clamping both in-plane coordinates gives the face, edge or corner point.
  const double a = std::clamp(dot(r, axis_u_), -half_u_m_, half_u_m_);
  const double b = std::clamp(dot(r, axis_v_), -half_v_m_, half_v_m_);
  const Vec3 q = centre_m_ + a * axis_u_ + b * axis_v_;
  const double tiny = 1e-12 * std::max(half_u_m_, half_v_m_);
  return two_sided_contact(c, q, normal_, tiny, range_m, shift, out);
}

SurfaceMesh RectangleWall::mesh(double t, const Vec3& /*lo*/, const Vec3& /*hi*/) const {
  const Vec3 c = centre_m_ + motion_.displacement_m(t);
  const Vec3 du = half_u_m_ * axis_u_;
  const Vec3 dv = half_v_m_ * axis_v_;
  SurfaceMesh mesh;
  mesh.points = {c - du - dv, c + du - dv, c + du + dv, c - du + dv};
  mesh.polygons = {{0, 1, 2, 3}};
  return mesh;
}

Vec3 RectangleWall::reference_point(double t) const {
  return centre_m_ + motion_.displacement_m(t);
}

DiskWall::DiskWall(const Vec3& centre_m, const Vec3& normal, double radius_m) {
  const char* where = "disk wall";
  centre_m_ = checked_point(where, centre_m, "centre_m");
  normal_ = checked_unit(where, normal, "normal");
  radius_m_ = checked_positive(where, radius_m, "radius_m");
}

bool DiskWall::nearest_point(const Vec3& centre, double range_m, double t,
                             WallContactPoint& out) const {
  const Vec3 shift = motion_.displacement_m(t);
  const Vec3 c = centre - shift;
  const Vec3 r = c - centre_m_;
  const Vec3 in_plane = r - dot(r, normal_) * normal_;
  const double rho = norm(in_plane);
  const Vec3 q = rho > radius_m_ ? centre_m_ + in_plane * (radius_m_ / rho) : centre_m_ + in_plane;
  return two_sided_contact(c, q, normal_, 1e-12 * radius_m_, range_m, shift, out);
}

SurfaceMesh DiskWall::mesh(double t, const Vec3& /*lo*/, const Vec3& /*hi*/) const {
  const Vec3 c = centre_m_ + motion_.displacement_m(t);
  const Vec3 u = any_perpendicular(normal_);
  const Vec3 v = cross(normal_, u);
  SurfaceMesh mesh;
  mesh.points.push_back(c);
  for (int k = 0; k < kSegments; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / kSegments;
    mesh.points.push_back(c + radius_m_ * (std::cos(phi) * u + std::sin(phi) * v));
  }
  for (int k = 0; k < kSegments; ++k)
    mesh.polygons.push_back({0, 1 + k, 1 + (k + 1) % kSegments});
  return mesh;
}

Vec3 DiskWall::reference_point(double t) const { return centre_m_ + motion_.displacement_m(t); }

std::unique_ptr<RectangleWall> make_slab_segment_wall(double x0_m, double z0_m, double x1_m,
                                                      double z1_m, double depth_m) {
  const double len = std::hypot(x1_m - x0_m, z1_m - z0_m);
  const Vec3 u{(x1_m - x0_m) / len, 0.0, (z1_m - z0_m) / len};
  const Vec3 n{-u.z, 0.0, u.x};  // so that v = n x u is +y
  return std::make_unique<RectangleWall>(
      Vec3{0.5 * (x0_m + x1_m), 0.5 * depth_m, 0.5 * (z0_m + z1_m)}, n, u, 0.5 * len, depth_m);
}

}  // namespace demcal::dem
