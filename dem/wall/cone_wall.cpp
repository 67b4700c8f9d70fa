#include "dem/wall/cone_wall.hpp"

#include "dem/wall/wall_checks.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace demcal::dem {

namespace {

constexpr int kSegments = 48;
// A literal, so walls built during static initialization can still throw.
constexpr char kWhere[] = "cone wall";

}  // namespace

ConeWall::ConeWall(const Vec3& base_m, const Vec3& axis, double length_m, double radius_base_m,
                   double radius_end_m)
    : base_m_(wall_checks::checked_point(kWhere, base_m, "base_m")),
      axis_(wall_checks::checked_unit(kWhere, axis, "axis")),
      length_m_(wall_checks::checked_positive(kWhere, length_m, "length_m")),
      radius_base_m_(wall_checks::checked_non_negative(kWhere, radius_base_m, "radius_base_m")),
      radius_end_m_(wall_checks::checked_non_negative(kWhere, radius_end_m, "radius_end_m")) {
  if (radius_base_m_ == 0.0 && radius_end_m_ == 0.0)
    wall_checks::fail(kWhere, "radius_base_m and radius_end_m must not both be 0");
}

bool ConeWall::nearest_point(const Vec3& centre, double range_m, double t,
                             WallContactPoint& out) const {
  const Vec3 shift = motion_.displacement_m(t);
  const Vec3 c = centre - shift;
  const Vec3 r = c - base_m_;
  const double s = dot(r, axis_);
  const Vec3 radial = r - s * axis_;
  const double rho = norm(radial);
  const double tiny = 1e-12 * std::max({length_m_, radius_base_m_, radius_end_m_});
  // On the axis a whole ring is equally near; any fixed direction keeps the
  // result reproducible.
  const Vec3 e = rho > tiny ? radial / rho : any_perpendicular(axis_);

  // By symmetry the nearest point lies in the centre's meridional half-plane
  // (rho >= 0), where the surface is the segment (r0, 0)-(r1, L).
  const double d_rho = radius_end_m_ - radius_base_m_;
  const double f = std::clamp(((rho - radius_base_m_) * d_rho + s * length_m_) /
                                  (d_rho * d_rho + length_m_ * length_m_),
                              0.0, 1.0);
  const double q_rho = radius_base_m_ + f * d_rho;
  const double q_s = f * length_m_;
  const Vec3 q = base_m_ + q_s * axis_ + q_rho * e;

  const Vec3 diff = c - q;
  const double distance = norm(diff);
  if (!(distance < range_m)) return false;
  out.point_m = q + shift;
  if (distance > tiny) {
    out.normal = diff / distance;
  } else {
    // The segment's outward normal in the half-plane, (L, -(r1 - r0)).
    out.normal = normalized(length_m_ * e - d_rho * axis_);
  }
  out.distance_m = distance;
  return true;
}

SurfaceMesh ConeWall::mesh(double t, const Vec3& /*lo*/, const Vec3& /*hi*/) const {
  const Vec3 base = base_m_ + motion_.displacement_m(t);
  const Vec3 end = base + length_m_ * axis_;
  const Vec3 u = any_perpendicular(axis_);
  const Vec3 v = cross(axis_, u);
  SurfaceMesh mesh;
  // A zero-radius end is a single apex point, so the mesh has no degenerate
  // quads there.
  auto ring = [&](const Vec3& c, double radius) {
    const int first = static_cast<int>(mesh.points.size());
    if (radius == 0.0) {
      mesh.points.push_back(c);
      return std::vector<int>(kSegments, first);
    }
    std::vector<int> ids;
    for (int k = 0; k < kSegments; ++k) {
      const double phi = 2.0 * std::numbers::pi * k / kSegments;
      ids.push_back(static_cast<int>(mesh.points.size()));
      mesh.points.push_back(c + radius * (std::cos(phi) * u + std::sin(phi) * v));
    }
    return ids;
  };
  const std::vector<int> lower = ring(base, radius_base_m_);
  const std::vector<int> upper = ring(end, radius_end_m_);
  for (int k = 0; k < kSegments; ++k) {
    const int next = (k + 1) % kSegments;
    if (radius_base_m_ == 0.0)
      mesh.polygons.push_back({lower[k], upper[next], upper[k]});
    else if (radius_end_m_ == 0.0)
      mesh.polygons.push_back({lower[k], lower[next], upper[k]});
    else
      mesh.polygons.push_back({lower[k], lower[next], upper[next], upper[k]});
  }
  return mesh;
}

Vec3 ConeWall::reference_point(double t) const { return base_m_ + motion_.displacement_m(t); }

}  // namespace demcal::dem
