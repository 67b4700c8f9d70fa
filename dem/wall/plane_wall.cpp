#include "dem/wall/plane_wall.hpp"

#include "dem/wall/wall_checks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace demcal::dem {

namespace {

constexpr char kWhere[] = "plane wall";

}  // namespace

PlaneWall::PlaneWall(const Vec3& point_m, const Vec3& normal)
    : point_m_(wall_checks::checked_point(kWhere, point_m, "point_m")),
      normal_(wall_checks::checked_unit(kWhere, normal, "normal")) {}

bool PlaneWall::nearest_point(const Vec3& centre, double range_m, double t,
                              WallContactPoint& out) const {
  const Vec3 shift = motion_.displacement_m(t);
  const Vec3 c = centre - shift;
  const double s = dot(c - point_m_, normal_);
  if (!(s < range_m)) return false;
  out.point_m = c - s * normal_ + shift;
  out.normal = normal_;
  out.distance_m = s;
  return true;
}

SurfaceMesh PlaneWall::mesh(double t, const Vec3& lo, const Vec3& hi) const {
  return plane_box_section(point_m_ + motion_.displacement_m(t), normal_, lo, hi);
}

Vec3 PlaneWall::reference_point(double t) const { return point_m_ + motion_.displacement_m(t); }

SurfaceMesh plane_box_section(const Vec3& point_m, const Vec3& normal, const Vec3& lo,
                              const Vec3& hi) {
  SurfaceMesh mesh;
  if (!is_finite(lo) || !is_finite(hi) || hi.x < lo.x || hi.y < lo.y || hi.z < lo.z) return mesh;

  std::array<Vec3, 8> corner;
  std::array<double, 8> side;  // signed distance of each corner from the plane
  for (int k = 0; k < 8; ++k) {
    corner[k] = {(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
    side[k] = dot(corner[k] - point_m, normal);
  }
  // A relative tolerance lets a plane lying exactly on a box face (the usual
  // case: floors and side walls) count its corners as on the plane instead of
  // losing them to rounding.
  const double diagonal = norm(hi - lo);
  const double tol = 1e-9 * (diagonal > 0.0 ? diagonal : 1.0);
  auto on_plane = [&](int k) { return std::abs(side[k]) <= tol; };

  std::vector<Vec3> cut;
  for (int k = 0; k < 8; ++k)
    if (on_plane(k)) cut.push_back(corner[k]);
  // The 12 edges join corners differing in exactly one index bit.
  for (int a = 0; a < 8; ++a) {
    for (int bit = 1; bit < 8; bit <<= 1) {
      const int b = a | bit;
      if (b == a || on_plane(a) || on_plane(b)) continue;
      if ((side[a] < 0.0) == (side[b] < 0.0)) continue;
      const double f = side[a] / (side[a] - side[b]);
      cut.push_back(corner[a] + f * (corner[b] - corner[a]));
    }
  }

  // Corner and edge points can coincide only within rounding; drop repeats.
  std::vector<Vec3> unique;
  for (const Vec3& p : cut) {
    const bool seen = std::any_of(unique.begin(), unique.end(),
                                  [&](const Vec3& q) { return norm(p - q) <= tol; });
    if (!seen) unique.push_back(p);
  }
  if (unique.size() < 3) return mesh;

  Vec3 centroid;
  for (const Vec3& p : unique) centroid += p;
  centroid = centroid / static_cast<double>(unique.size());
  const Vec3 u = any_perpendicular(normal);
  const Vec3 v = cross(normal, u);
  std::vector<std::pair<double, Vec3>> by_angle;
  by_angle.reserve(unique.size());
  for (const Vec3& p : unique) {
    const Vec3 r = p - centroid;
    by_angle.emplace_back(std::atan2(dot(r, v), dot(r, u)), p);
  }
  std::sort(by_angle.begin(), by_angle.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });

  std::vector<int> polygon;
  for (const auto& [angle, p] : by_angle) {
    polygon.push_back(static_cast<int>(mesh.points.size()));
    mesh.points.push_back(p);
  }
  mesh.polygons.push_back(std::move(polygon));
  return mesh;
}

}  // namespace demcal::dem
