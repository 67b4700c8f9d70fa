#include "dem/wall/cylinder_wall.hpp"

#include "dem/wall/wall_checks.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace demcal::dem {

namespace {

constexpr int kSegments = 48;
// A literal, so walls built during static initialization can still throw.
constexpr char kWhere[] = "cylinder wall";

}  // namespace

CylinderWall::CylinderWall(const Vec3& base_m, const Vec3& axis, double length_m, double radius_m)
    : base_m_(wall_checks::checked_point(kWhere, base_m, "base_m")),
      axis_(wall_checks::checked_unit(kWhere, axis, "axis")),
      length_m_(wall_checks::checked_positive(kWhere, length_m, "length_m")),
      radius_m_(wall_checks::checked_positive(kWhere, radius_m, "radius_m")) {}

bool CylinderWall::nearest_point(const Vec3& centre, double range_m, double t,
                                 WallContactPoint& out) const {
  const Vec3 shift = motion_.displacement_m(t);
  const Vec3 c = centre - shift;
  const Vec3 r = c - base_m_;
  const double s = dot(r, axis_);
  const Vec3 radial = r - s * axis_;
  const double rho = norm(radial);
  const double tiny = 1e-12 * std::max(length_m_, radius_m_);
  // On the axis every rim direction is equally near; any fixed choice keeps
  // the result reproducible.
  const Vec3 e = rho > tiny ? radial / rho : any_perpendicular(axis_);
  const Vec3 q = base_m_ + std::clamp(s, 0.0, length_m_) * axis_ + radius_m_ * e;

  const Vec3 diff = c - q;
  const double distance = norm(diff);
  if (!(distance < range_m)) return false;
  out.point_m = q + shift;
  out.normal = distance > tiny ? diff / distance : e;
  out.distance_m = distance;
  return true;
}

SurfaceMesh CylinderWall::mesh(double t, const Vec3& /*lo*/, const Vec3& /*hi*/) const {
  const Vec3 base = base_m_ + motion_.displacement_m(t);
  const Vec3 top = base + length_m_ * axis_;
  const Vec3 u = any_perpendicular(axis_);
  const Vec3 v = cross(axis_, u);
  SurfaceMesh mesh;
  for (int k = 0; k < kSegments; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / kSegments;
    const Vec3 e = radius_m_ * (std::cos(phi) * u + std::sin(phi) * v);
    mesh.points.push_back(base + e);  // index 2k
    mesh.points.push_back(top + e);   // index 2k + 1
  }
  for (int k = 0; k < kSegments; ++k) {
    const int next = (k + 1) % kSegments;
    mesh.polygons.push_back({2 * k, 2 * next, 2 * next + 1, 2 * k + 1});
  }
  return mesh;
}

Vec3 CylinderWall::reference_point(double t) const { return base_m_ + motion_.displacement_m(t); }

}  // namespace demcal::dem
