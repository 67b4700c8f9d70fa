#include "dem/wall/orifice_plate_wall.hpp"

#include "dem/wall/plane_wall.hpp"
#include "dem/wall/wall_checks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace demcal::dem {

namespace {

constexpr int kSegments = 48;
// A literal, so walls built during static initialization can still throw.
constexpr char kWhere[] = "orifice plate wall";

const char* opening_name(OrificeShape shape) {
  return shape == OrificeShape::circle ? "diameter_m" : "width_m";
}

double checked_opening(double x, OrificeShape shape) {
  if (!(x > 0.0) || !std::isfinite(x)) {
    std::ostringstream msg;
    msg << opening_name(shape) << " must be > 0 (got " << x << ")";
    wall_checks::fail(kWhere, msg.str());
  }
  return x;
}

double checked_outer_radius(double x, double opening_m, OrificeShape shape) {
  std::ostringstream msg;
  if (!(x >= 0.0) || !std::isfinite(x)) {
    msg << "outer_radius_m must be >= 0, 0 meaning unbounded (got " << x << ")";
    wall_checks::fail(kWhere, msg.str());
  }
  // An outer radius inside the hole would leave no plate once it opens.
  if (x > 0.0 && !(x > 0.5 * opening_m)) {
    msg << "outer_radius_m (" << x << ") must exceed half the " << opening_name(shape) << " ("
        << opening_m << ")";
    wall_checks::fail(kWhere, msg.str());
  }
  return x;
}

double checked_time(double x) {
  if (std::isnan(x)) wall_checks::fail(kWhere, "open_time_s must be a number (got nan)");
  return x;
}

}  // namespace

OrificePlateWall::OrificePlateWall(const Vec3& centre_m, const Vec3& normal, const Vec3& axis_u,
                                   OrificeShape shape, double opening_m, double open_time_s,
                                   double outer_radius_m)
    : centre_m_(wall_checks::checked_point(kWhere, centre_m, "centre_m")),
      normal_(wall_checks::checked_unit(kWhere, normal, "normal")),
      shape_(shape),
      opening_m_(checked_opening(opening_m, shape)),
      open_time_s_(checked_time(open_time_s)),
      outer_radius_m_(checked_outer_radius(outer_radius_m, opening_m, shape)) {
  if (shape == OrificeShape::circle && norm2(axis_u) == 0.0) {
    axis_u_ = any_perpendicular(normal_);
  } else {
    const Vec3 u = wall_checks::checked_unit(kWhere, axis_u, "axis_u");
    const Vec3 along = u - dot(u, normal_) * normal_;
    if (norm(along) < 1e-6) wall_checks::fail(kWhere, "axis_u must not be parallel to normal");
    axis_u_ = normalized(along);
  }
  axis_v_ = cross(normal_, axis_u_);
}

OrificePlateWall OrificePlateWall::circular(const Vec3& centre_m, const Vec3& normal,
                                            double diameter_m, double open_time_s,
                                            double outer_radius_m) {
  return OrificePlateWall(centre_m, normal, Vec3{}, OrificeShape::circle, diameter_m, open_time_s,
                          outer_radius_m);
}

OrificePlateWall OrificePlateWall::slot(const Vec3& centre_m, const Vec3& normal,
                                        const Vec3& axis_u, double width_m, double open_time_s,
                                        double outer_radius_m) {
  return OrificePlateWall(centre_m, normal, axis_u, OrificeShape::slot, width_m, open_time_s,
                          outer_radius_m);
}

OrificePlateWall::InPlane OrificePlateWall::nearest_solid(InPlane p, bool open) const {
  const bool bounded = outer_radius_m_ > 0.0;
  const double ro = outer_radius_m_;
  const double rho = std::hypot(p.a, p.b);
  const double tiny = 1e-12 * opening_m_;

  if (!open) {
    if (!bounded || rho <= ro) return p;
    return {p.a * ro / rho, p.b * ro / rho};
  }

  if (shape_ == OrificeShape::circle) {
    const double inner = 0.5 * opening_m_;
    const double target = bounded ? std::clamp(rho, inner, ro) : std::max(rho, inner);
    if (target == rho) return p;
    // Over the hole's centre the whole rim is equally near; take the u side
    // so the choice is reproducible.
    if (rho <= tiny) return {target, 0.0};
    return {p.a * target / rho, p.b * target / rho};
  }

  const double half_w = 0.5 * opening_m_;
  if (!bounded) {
    if (std::abs(p.a) >= half_w) return p;
    return {p.a >= 0.0 ? half_w : -half_w, p.b};
  }

  // A bounded slotted plate is two disjoint convex pieces, disk ∩ {±a >= w/2};
  // the nearest point of each is its radial projection onto the disk when that
  // stays in the piece, else the nearest point of its straight edge (the
  // chord), whose ends are the corners.
  const double half_chord = std::sqrt(ro * ro - half_w * half_w);
  const InPlane on_disk = rho > ro ? InPlane{p.a * ro / rho, p.b * ro / rho} : p;
  InPlane best{};
  double best_d2 = std::numeric_limits<double>::infinity();
  auto consider = [&](InPlane q) {
    const double d2 = (q.a - p.a) * (q.a - p.a) + (q.b - p.b) * (q.b - p.b);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = q;
    }
  };
  for (const double side : {1.0, -1.0}) {
    if (side * on_disk.a >= half_w) consider(on_disk);
    consider({side * half_w, std::clamp(p.b, -half_chord, half_chord)});
  }
  return best;
}

bool OrificePlateWall::nearest_point(const Vec3& centre, double range_m, double t,
                                     WallContactPoint& out) const {
  const Vec3 shift = motion_.displacement_m(t);
  const Vec3 c = centre - shift;
  const Vec3 r = c - centre_m_;
  const InPlane q2 = nearest_solid({dot(r, axis_u_), dot(r, axis_v_)}, is_open(t));
  const Vec3 q = centre_m_ + q2.a * axis_u_ + q2.b * axis_v_;

  const Vec3 diff = c - q;
  const double distance = norm(diff);
  if (!(distance < range_m)) return false;
  out.point_m = q + shift;
  out.normal = distance > 1e-12 * opening_m_ ? diff / distance : normal_;
  out.distance_m = distance;
  return true;
}

SurfaceMesh OrificePlateWall::mesh(double t, const Vec3& lo, const Vec3& hi) const {
  const Vec3 c = centre_m_ + motion_.displacement_m(t);
  const bool bounded = outer_radius_m_ > 0.0;
  SurfaceMesh mesh;
  auto add = [&](double a, double b) {
    mesh.points.push_back(c + a * axis_u_ + b * axis_v_);
    return static_cast<int>(mesh.points.size()) - 1;
  };
  auto angle = [](int k) { return 2.0 * std::numbers::pi * k / kSegments; };

  if (!is_open(t) && !bounded) return plane_box_section(c, normal_, lo, hi);

  // How far an unbounded plate must reach to cover the box: the largest
  // in-plane distance of a box corner, and never less than the hole itself.
  double extent = outer_radius_m_;
  if (!bounded) {
    extent = opening_m_;
    for (int k = 0; k < 8; ++k) {
      const Vec3 corner{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
      const Vec3 r = corner - c;
      if (is_finite(r)) extent = std::max(extent, std::hypot(dot(r, axis_u_), dot(r, axis_v_)));
    }
  }

  if (!is_open(t)) {
    const int centre_id = add(0.0, 0.0);
    for (int k = 0; k < kSegments; ++k)
      add(extent * std::cos(angle(k)), extent * std::sin(angle(k)));
    for (int k = 0; k < kSegments; ++k)
      mesh.polygons.push_back({centre_id, centre_id + 1 + k, centre_id + 1 + (k + 1) % kSegments});
    return mesh;
  }

  if (shape_ == OrificeShape::circle) {
    const double inner = 0.5 * opening_m_;
    for (int k = 0; k < kSegments; ++k) {
      add(inner * std::cos(angle(k)), inner * std::sin(angle(k)));  // index 2k
      add(extent * std::cos(angle(k)), extent * std::sin(angle(k)));  // index 2k + 1
    }
    for (int k = 0; k < kSegments; ++k) {
      const int next = (k + 1) % kSegments;
      mesh.polygons.push_back({2 * k, 2 * k + 1, 2 * next + 1, 2 * next});
    }
    return mesh;
  }

  const double half_w = 0.5 * opening_m_;
  if (!bounded) {
    for (const double side : {1.0, -1.0}) {
      const int first = add(side * half_w, -extent);
      add(side * extent, -extent);
      add(side * extent, extent);
      add(side * half_w, extent);
      mesh.polygons.push_back({first, first + 1, first + 2, first + 3});
    }
    return mesh;
  }

  // Each half of a bounded slotted plate is a circular segment: the arc
  // between the chord's ends, closed by the chord.
  const double theta = std::acos(half_w / outer_radius_m_);
  const int arc_points = kSegments / 2 + 1;
  for (const double side : {1.0, -1.0}) {
    std::vector<int> polygon;
    const double mid = side > 0.0 ? 0.0 : std::numbers::pi;
    for (int k = 0; k < arc_points; ++k) {
      const double phi = mid - theta + 2.0 * theta * k / (arc_points - 1);
      polygon.push_back(add(outer_radius_m_ * std::cos(phi), outer_radius_m_ * std::sin(phi)));
    }
    mesh.polygons.push_back(std::move(polygon));
  }
  return mesh;
}

Vec3 OrificePlateWall::reference_point(double t) const {
  return centre_m_ + motion_.displacement_m(t);
}

std::vector<double> OrificePlateWall::change_times_s() const {
  if (!std::isfinite(open_time_s_)) return {};
  return {open_time_s_};
}

void OrificePlateWall::set_open_time(double open_time_s) {
  if (std::isnan(open_time_s))
    wall_checks::fail(kWhere, "open_time_s must not be NaN");
  open_time_s_ = open_time_s;
}

}  // namespace demcal::dem
