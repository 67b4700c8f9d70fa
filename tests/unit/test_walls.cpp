// Wall geometry against configurations whose nearest points are known in
// closed form.

#include "dem/wall/bounded_plane_wall.hpp"
#include "dem/wall/cone_wall.hpp"
#include "dem/wall/cylinder_wall.hpp"
#include "dem/wall/orifice_plate_wall.hpp"
#include "dem/wall/plane_wall.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

namespace demcal::dem {
namespace {

constexpr double kTol = 1e-12;
const double kInvSqrt2 = 1.0 / std::sqrt(2.0);

void expect_vec_near(const Vec3& actual, const Vec3& expected, double tol = kTol) {
  EXPECT_NEAR(actual.x, expected.x, tol);
  EXPECT_NEAR(actual.y, expected.y, tol);
  EXPECT_NEAR(actual.z, expected.z, tol);
}

// Queries with a generous range and checks all three results.
void expect_contact(const Wall& wall, const Vec3& centre, const Vec3& point, const Vec3& normal,
                    double distance, double t = 0.0) {
  WallContactPoint cp;
  ASSERT_TRUE(wall.nearest_point(centre, 10.0, t, cp));
  expect_vec_near(cp.point_m, point);
  expect_vec_near(cp.normal, normal);
  EXPECT_NEAR(cp.distance_m, distance, kTol);
}

void expect_throws_naming(const std::function<void()>& make, const std::string& param) {
  try {
    make();
    ADD_FAILURE() << "expected std::invalid_argument naming " << param;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(param), std::string::npos)
        << "message '" << e.what() << "' does not name " << param;
  }
}

void expect_valid_mesh(const SurfaceMesh& mesh) {
  ASSERT_FALSE(mesh.points.empty());
  ASSERT_FALSE(mesh.polygons.empty());
  for (const Vec3& p : mesh.points) EXPECT_TRUE(is_finite(p));
  const int n = static_cast<int>(mesh.points.size());
  for (const auto& polygon : mesh.polygons) {
    EXPECT_GE(polygon.size(), 3u);
    for (int id : polygon) {
      EXPECT_GE(id, 0);
      EXPECT_LT(id, n);
    }
  }
}

const Vec3 kLo{-1, -1, -1};
const Vec3 kHi{1, 1, 1};

// --- motion -----------------------------------------------------------------

TEST(WallMotion, DisplacementAndVelocityFollowTheSchedule) {
  WallMotion m{{0, 0, 2}, 1.0, 3.0};
  expect_vec_near(m.displacement_m(0.5), {0, 0, 0});
  expect_vec_near(m.displacement_m(2.0), {0, 0, 2});
  expect_vec_near(m.displacement_m(10.0), {0, 0, 4});
  expect_vec_near(m.velocity_at(0.5), {0, 0, 0});
  expect_vec_near(m.velocity_at(1.0), {0, 0, 2});
  expect_vec_near(m.velocity_at(3.0), {0, 0, 0});
  EXPECT_TRUE(m.moves());
  EXPECT_FALSE(WallMotion{}.moves());
  expect_vec_near(WallMotion{}.displacement_m(5.0), {0, 0, 0});
}

// --- plane ------------------------------------------------------------------

TEST(PlaneWall, NearestPointIsTheProjection) {
  const PlaneWall floor({0, 0, 1}, {0, 0, 5});  // normal normalized
  EXPECT_EQ(floor.type_name(), "plane");
  expect_contact(floor, {0.3, -0.2, 1.05}, {0.3, -0.2, 1}, {0, 0, 1}, 0.05);
}

TEST(PlaneWall, SunkParticleIsStillPushedOutAlongTheNormal) {
  const PlaneWall floor({0, 0, 0}, {0, 0, 1});
  expect_contact(floor, {1, 2, -0.3}, {1, 2, 0}, {0, 0, 1}, -0.3);
}

TEST(PlaneWall, RangeCutOff) {
  const PlaneWall wall({0, 0, 0}, {1, 0, 0});
  WallContactPoint cp;
  EXPECT_FALSE(wall.nearest_point({0.2, 0, 0}, 0.1, 0.0, cp));
  EXPECT_TRUE(wall.nearest_point({0.05, 0, 0}, 0.1, 0.0, cp));
}

TEST(PlaneWall, MovingPlaneCarriesItsContactPointAndVelocity) {
  PlaneWall piston({0, 0, 0}, {0, 0, 1});
  piston.set_motion({{0, 0, 0.5}, 1.0});
  // At t = 3 the plane has risen to z = 1.
  expect_contact(piston, {0.1, 0.1, 1.2}, {0.1, 0.1, 1.0}, {0, 0, 1}, 0.2, 3.0);
  expect_contact(piston, {0.1, 0.1, 1.2}, {0.1, 0.1, 0.0}, {0, 0, 1}, 1.2, 0.5);
  expect_vec_near(piston.velocity_at(3.0), {0, 0, 0.5});
  expect_vec_near(piston.velocity_at(0.5), {0, 0, 0});
  expect_vec_near(piston.reference_point(3.0), {0, 0, 1});
}

TEST(PlaneWall, InvalidInputThrows) {
  expect_throws_naming([] { PlaneWall({0, 0, 0}, {0, 0, 0}); }, "normal");
  expect_throws_naming([] { PlaneWall({0, NAN, 0}, {0, 0, 1}); }, "point_m");
}

TEST(PlaneWall, MeshOfAFaceOfTheBoxIsItsRectangle) {
  const PlaneWall floor({0, 0, -1}, {0, 0, 1});
  const SurfaceMesh mesh = floor.mesh(0.0, kLo, kHi);
  expect_valid_mesh(mesh);
  EXPECT_EQ(mesh.points.size(), 4u);
  for (const Vec3& p : mesh.points) EXPECT_NEAR(p.z, -1.0, kTol);
}

TEST(PlaneWall, ObliqueMeshIsAConvexHexagonOrderedAroundTheNormal) {
  const Vec3 n = normalized({1, 1, 1});
  const SurfaceMesh mesh = PlaneWall({0, 0, 0}, n).mesh(0.0, kLo, kHi);
  expect_valid_mesh(mesh);
  ASSERT_EQ(mesh.points.size(), 6u);
  ASSERT_EQ(mesh.polygons.size(), 1u);
  const auto& poly = mesh.polygons[0];
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Vec3& a = mesh.points[poly[k]];
    const Vec3& b = mesh.points[poly[(k + 1) % poly.size()]];
    const Vec3& c = mesh.points[poly[(k + 2) % poly.size()]];
    EXPECT_NEAR(dot(a, n), 0.0, 1e-12);
    EXPECT_GT(dot(cross(b - a, c - b), n), 0.0);  // every turn the same way
  }
}

TEST(PlaneWall, MeshIsEmptyWhenThePlaneMissesTheBox) {
  const SurfaceMesh mesh = PlaneWall({0, 0, 5}, {0, 0, 1}).mesh(0.0, kLo, kHi);
  EXPECT_TRUE(mesh.points.empty());
  EXPECT_TRUE(mesh.polygons.empty());
}

// --- rectangle and disk -----------------------------------------------------

// A 2 x 1 rectangle in z = 0: u = x (half 1), v = z × x = y (half 0.5).
RectangleWall make_rectangle() {
  return RectangleWall({0, 0, 0}, {0, 0, 1}, {1, 0, 0.3}, 1.0, 0.5);
}

TEST(RectangleWall, FaceFromEitherSide) {
  const RectangleWall r = make_rectangle();
  EXPECT_EQ(r.type_name(), "rectangle");
  expect_vec_near(r.axis_u(), {1, 0, 0});
  expect_vec_near(r.axis_v(), {0, 1, 0});
  expect_contact(r, {0.5, 0.2, 0.1}, {0.5, 0.2, 0}, {0, 0, 1}, 0.1);
  expect_contact(r, {0.5, 0.2, -0.1}, {0.5, 0.2, 0}, {0, 0, -1}, 0.1);
}

TEST(RectangleWall, EdgeAndCorner) {
  const RectangleWall r = make_rectangle();
  expect_contact(r, {1.1, 0.0, 0.1}, {1, 0, 0}, {kInvSqrt2, 0, kInvSqrt2}, 0.1 * std::sqrt(2.0));
  expect_contact(r, {1.3, 0.9, 0.0}, {1, 0.5, 0}, {0.6, 0.8, 0}, 0.5);
}

TEST(RectangleWall, RangeCutOff) {
  const RectangleWall r = make_rectangle();
  WallContactPoint cp;
  EXPECT_FALSE(r.nearest_point({1.3, 0.9, 0.0}, 0.49, 0.0, cp));
  EXPECT_TRUE(r.nearest_point({1.3, 0.9, 0.0}, 0.51, 0.0, cp));
}

TEST(RectangleWall, InvalidInputThrows) {
  expect_throws_naming([] { RectangleWall({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 0.0, 1.0); },
                       "half_length_u_m");
  expect_throws_naming([] { RectangleWall({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 1.0, -2.0); },
                       "half_length_v_m");
  expect_throws_naming([] { RectangleWall({0, 0, 0}, {0, 0, 1}, {0, 0, 2}, 1.0, 1.0); }, "axis_u");
  expect_throws_naming([] { RectangleWall({0, 0, 0}, {0, 0, 0}, {1, 0, 0}, 1.0, 1.0); }, "normal");
}

TEST(RectangleWall, Mesh) {
  const SurfaceMesh mesh = make_rectangle().mesh(0.0, kLo, kHi);
  expect_valid_mesh(mesh);
  EXPECT_EQ(mesh.points.size(), 4u);
}

TEST(DiskWall, FaceAndRim) {
  const DiskWall d({0, 0, 1}, {0, 0, 1}, 0.5);
  EXPECT_EQ(d.type_name(), "disk");
  expect_contact(d, {0.1, 0.2, 1.3}, {0.1, 0.2, 1}, {0, 0, 1}, 0.3);
  expect_contact(d, {0.1, 0.2, 0.7}, {0.1, 0.2, 1}, {0, 0, -1}, 0.3);
  expect_contact(d, {0, 0.9, 1.3}, {0, 0.5, 1}, {0, 0.8, 0.6}, 0.5);
  expect_throws_naming([] { DiskWall({0, 0, 0}, {0, 0, 1}, 0.0); }, "radius_m");
  expect_valid_mesh(d.mesh(0.0, kLo, kHi));
}

// --- cylinder ---------------------------------------------------------------

// Radius 0.5 around the z axis from z = 0 to z = 2.
CylinderWall make_cylinder() { return CylinderWall({0, 0, 0}, {0, 0, 3}, 2.0, 0.5); }

TEST(CylinderWall, InsideAndOutside) {
  const CylinderWall c = make_cylinder();
  EXPECT_EQ(c.type_name(), "cylinder");
  expect_contact(c, {0.4, 0, 1}, {0.5, 0, 1}, {-1, 0, 0}, 0.1);
  expect_contact(c, {0, 0.7, 1}, {0, 0.5, 1}, {0, 1, 0}, 0.2);
}

TEST(CylinderWall, CentreOnTheAxisPicksAFixedDirection) {
  const CylinderWall c = make_cylinder();
  WallContactPoint first;
  WallContactPoint second;
  ASSERT_TRUE(c.nearest_point({0, 0, 1}, 1.0, 0.0, first));
  ASSERT_TRUE(c.nearest_point({0, 0, 1}, 1.0, 0.0, second));
  EXPECT_NEAR(first.distance_m, 0.5, kTol);
  EXPECT_NEAR(first.point_m.z, 1.0, kTol);
  EXPECT_NEAR(std::hypot(first.point_m.x, first.point_m.y), 0.5, kTol);
  expect_vec_near(first.point_m, second.point_m, 0.0);
  expect_vec_near(first.normal, -2.0 * first.point_m + Vec3{0, 0, 2});  // towards the axis
}

TEST(CylinderWall, BeyondTheEndsTheRimIsNearest) {
  const CylinderWall c = make_cylinder();
  expect_contact(c, {0.2, 0, 2.4}, {0.5, 0, 2}, {-0.6, 0, 0.8}, 0.5);
  expect_contact(c, {0.5, 0, -0.1}, {0.5, 0, 0}, {0, 0, -1}, 0.1);
  WallContactPoint cp;
  EXPECT_FALSE(c.nearest_point({0, 0, 2.4}, 0.6, 0.0, cp));  // the open end
}

TEST(CylinderWall, LiftedCylinderMovesItsSurface) {
  CylinderWall c = make_cylinder();
  c.set_motion({{0, 0, 1}, 0.0});
  // Lifted by 1 at t = 1: the rim is at z = 1.
  expect_contact(c, {0.5, 0, 0.9}, {0.5, 0, 1}, {0, 0, -1}, 0.1, 1.0);
  expect_vec_near(c.reference_point(1.0), {0, 0, 1});
}

TEST(CylinderWall, InvalidInputThrows) {
  try {
    CylinderWall({0, 0, 0}, {0, 0, 1}, 1.0, -0.01);
    ADD_FAILURE() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "cylinder wall: radius_m must be > 0 (got -0.01)");
  }
  expect_throws_naming([] { CylinderWall({0, 0, 0}, {0, 0, 1}, 0.0, 1.0); }, "length_m");
  expect_throws_naming([] { CylinderWall({0, 0, 0}, {0, 0, 0}, 1.0, 1.0); }, "axis");
}

TEST(CylinderWall, Mesh) {
  const SurfaceMesh mesh = make_cylinder().mesh(0.0, kLo, kHi);
  expect_valid_mesh(mesh);
  EXPECT_EQ(mesh.polygons.size(), 48u);
  for (const Vec3& p : mesh.points) EXPECT_NEAR(std::hypot(p.x, p.y), 0.5, 1e-12);
}

// --- cone -------------------------------------------------------------------

// A 45° cone: apex at the origin, opening upwards to radius 1 at z = 1.
ConeWall make_cone() { return ConeWall({0, 0, 0}, {0, 0, 1}, 1.0, 0.0, 1.0); }

TEST(ConeWall, BothSides) {
  const ConeWall cone = make_cone();
  EXPECT_EQ(cone.type_name(), "cone");
  // Outside, below the surface.
  expect_contact(cone, {1, 0, 0}, {0.5, 0, 0.5}, {kInvSqrt2, 0, -kInvSqrt2}, kInvSqrt2);
  // Inside, above it.
  expect_contact(cone, {0, 0.2, 0.8}, {0, 0.5, 0.5}, {0, -kInvSqrt2, kInvSqrt2},
                 0.3 * std::sqrt(2.0));
}

TEST(ConeWall, ApexAndAxis) {
  const ConeWall cone = make_cone();
  expect_contact(cone, {0, 0, -0.5}, {0, 0, 0}, {0, 0, -1}, 0.5);
  expect_contact(cone, {0.1, 0, -1}, {0, 0, 0}, normalized({0.1, 0, -1}), std::sqrt(1.01));
  // On the axis a ring is equally near; the answer is one point of it.
  WallContactPoint cp;
  ASSERT_TRUE(cone.nearest_point({0, 0, 1}, 1.0, 0.0, cp));
  EXPECT_NEAR(cp.distance_m, kInvSqrt2, kTol);
  EXPECT_NEAR(cp.point_m.z, 0.5, kTol);
  EXPECT_NEAR(std::hypot(cp.point_m.x, cp.point_m.y), 0.5, kTol);
}

TEST(ConeWall, HopperFrustumAndRange) {
  // Narrowing from radius 1 at z = 1 to 0.5 at z = 2: a hopper pointing up.
  const ConeWall hopper({0, 0, 1}, {0, 0, 1}, 1.0, 1.0, 0.5);
  // The lateral surface direction is (-0.5, 1); its outward normal (1, 0.5)/|.|.
  const Vec3 n = normalized({1, 0, 0.5});
  const Vec3 on_surface{0.75, 0, 1.5};
  expect_contact(hopper, on_surface + 0.2 * n, on_surface, n, 0.2);
  expect_contact(hopper, on_surface - 0.2 * n, on_surface, -n, 0.2);
  WallContactPoint cp;
  EXPECT_FALSE(hopper.nearest_point(on_surface + 0.2 * n, 0.19, 0.0, cp));
  EXPECT_TRUE(hopper.nearest_point(on_surface + 0.2 * n, 0.21, 0.0, cp));
}

TEST(ConeWall, InvalidInputThrows) {
  expect_throws_naming([] { ConeWall({0, 0, 0}, {0, 0, 1}, 1.0, 0.0, 0.0); }, "radius_end_m");
  expect_throws_naming([] { ConeWall({0, 0, 0}, {0, 0, 1}, 1.0, -0.1, 1.0); }, "radius_base_m");
  expect_throws_naming([] { ConeWall({0, 0, 0}, {0, 0, 1}, -1.0, 0.1, 1.0); }, "length_m");
  expect_throws_naming([] { ConeWall({0, 0, 0}, {0, 0, 0}, 1.0, 0.1, 1.0); }, "axis");
}

TEST(ConeWall, Mesh) {
  const SurfaceMesh apex_mesh = make_cone().mesh(0.0, kLo, kHi);
  expect_valid_mesh(apex_mesh);
  EXPECT_EQ(apex_mesh.points.size(), 49u);
  EXPECT_EQ(apex_mesh.polygons.size(), 48u);
  const SurfaceMesh frustum = ConeWall({0, 0, 0}, {0, 0, 1}, 1.0, 1.0, 0.5).mesh(0.0, kLo, kHi);
  expect_valid_mesh(frustum);
  EXPECT_EQ(frustum.points.size(), 96u);
}

// --- orifice plate ----------------------------------------------------------

// A plate in z = 0 with a hole of diameter 0.2 opening at t = 1.
OrificePlateWall make_orifice() {
  return OrificePlateWall::circular({0, 0, 0}, {0, 0, 1}, 0.2, 1.0);
}

TEST(OrificePlateWall, ClosedPlateIsAPlaneFromBothSides) {
  const OrificePlateWall plate = make_orifice();
  EXPECT_EQ(plate.type_name(), "orifice_plate");
  EXPECT_FALSE(plate.is_open(0.5));
  expect_contact(plate, {0, 0, 0.05}, {0, 0, 0}, {0, 0, 1}, 0.05, 0.5);
  expect_contact(plate, {0.05, 0, -0.05}, {0.05, 0, 0}, {0, 0, -1}, 0.05, 0.5);
  ASSERT_EQ(plate.change_times_s().size(), 1u);
  EXPECT_EQ(plate.change_times_s()[0], 1.0);
}

TEST(OrificePlateWall, OpenCircularHole) {
  const OrificePlateWall plate = make_orifice();
  const double t = 1.0;
  // Over the hole's centre: a point of the rim.
  WallContactPoint cp;
  ASSERT_TRUE(plate.nearest_point({0, 0, 0.05}, 1.0, t, cp));
  EXPECT_NEAR(cp.point_m.z, 0.0, kTol);
  EXPECT_NEAR(std::hypot(cp.point_m.x, cp.point_m.y), 0.1, kTol);
  EXPECT_NEAR(cp.distance_m, std::sqrt(0.01 + 0.0025), kTol);
  EXPECT_FALSE(plate.nearest_point({0, 0, 0.05}, 0.1, t, cp));  // falls through freely
  // Over the rim, inside the hole, and over the plate beyond it.
  expect_contact(plate, {0.1, 0, 0.03}, {0.1, 0, 0}, {0, 0, 1}, 0.03, t);
  expect_contact(plate, {0, 0.06, 0.03}, {0, 0.1, 0}, {0, -0.8, 0.6}, 0.05, t);
  expect_contact(plate, {0.15, 0, 0.03}, {0.15, 0, 0}, {0, 0, 1}, 0.03, t);
}

TEST(OrificePlateWall, BoundedPlateEndsAtItsOuterRadius) {
  const OrificePlateWall plate = OrificePlateWall::circular({0, 0, 0}, {0, 0, 1}, 0.2, 0.0, 0.5);
  expect_contact(plate, {0.7, 0, 0}, {0.5, 0, 0}, {1, 0, 0}, 0.2, 0.0);
  expect_contact(plate, {0.7, 0, 0}, {0.5, 0, 0}, {1, 0, 0}, 0.2, -1.0);
}

TEST(OrificePlateWall, UnboundedSlot) {
  // Slot 0.1 wide across x, running along y, open from the start.
  const OrificePlateWall slot = OrificePlateWall::slot({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 0.1, 0.0);
  expect_contact(slot, {0.02, 5, 0.03}, {0.05, 5, 0}, {-kInvSqrt2, 0, kInvSqrt2},
                 0.03 * std::sqrt(2.0));
  expect_contact(slot, {-0.01, 0, 0.03}, {-0.05, 0, 0}, {0.8, 0, 0.6}, 0.05);
  expect_contact(slot, {0.2, -3, 0.02}, {0.2, -3, 0}, {0, 0, 1}, 0.02);
  expect_contact(slot, {0.2, -3, 0.02}, {0.2, -3, 0}, {0, 0, 1}, 0.02, -1.0);  // not yet open
}

TEST(OrificePlateWall, BoundedSlotCorner) {
  const OrificePlateWall slot =
      OrificePlateWall::slot({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 0.2, 0.0, 0.5);
  const double corner_b = std::sqrt(0.25 - 0.01);
  const Vec3 corner{0.1, corner_b, 0};
  expect_contact(slot, {0.0, 0.6, 0.0}, corner, normalized(Vec3{0.0, 0.6, 0} - corner),
                 norm(Vec3{0.0, 0.6, 0} - corner));
  expect_contact(slot, {-0.6, 0, 0.0}, {-0.5, 0, 0}, {-1, 0, 0}, 0.1);
}

TEST(OrificePlateWall, InvalidInputThrows) {
  expect_throws_naming([] { OrificePlateWall::circular({0, 0, 0}, {0, 0, 1}, 0.0, 1.0); },
                       "diameter_m");
  expect_throws_naming(
      [] { OrificePlateWall::slot({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, -0.1, 1.0); }, "width_m");
  expect_throws_naming([] { OrificePlateWall::slot({0, 0, 0}, {0, 0, 1}, {0, 0, 0}, 0.1, 1.0); },
                       "axis_u");
  expect_throws_naming([] { OrificePlateWall::circular({0, 0, 0}, {0, 0, 1}, 0.2, 1.0, 0.05); },
                       "outer_radius_m");
  expect_throws_naming([] { OrificePlateWall::circular({0, 0, 0}, {0, 0, 1}, 0.2, NAN); },
                       "open_time_s");
}

TEST(OrificePlateWall, MeshBeforeAndAfterOpening) {
  const OrificePlateWall plate = make_orifice();
  const SurfaceMesh closed = plate.mesh(0.0, kLo, kHi);
  expect_valid_mesh(closed);
  EXPECT_EQ(closed.points.size(), 4u);  // the plane's section of the box
  const SurfaceMesh annulus = plate.mesh(2.0, kLo, kHi);
  expect_valid_mesh(annulus);
  EXPECT_EQ(annulus.polygons.size(), 48u);
  for (const Vec3& p : annulus.points) EXPECT_GE(std::hypot(p.x, p.y), 0.1 - 1e-12);

  const SurfaceMesh slot =
      OrificePlateWall::slot({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 0.1, 0.0).mesh(0.0, kLo, kHi);
  expect_valid_mesh(slot);
  EXPECT_EQ(slot.polygons.size(), 2u);
  for (const Vec3& p : slot.points) EXPECT_GE(std::abs(p.x), 0.05 - 1e-12);

  const SurfaceMesh bounded_slot =
      OrificePlateWall::slot({0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 0.2, 0.0, 0.5).mesh(0.0, kLo, kHi);
  expect_valid_mesh(bounded_slot);
  EXPECT_EQ(bounded_slot.polygons.size(), 2u);
  expect_valid_mesh(OrificePlateWall::circular({0, 0, 0}, {0, 0, 1}, 0.2, 1.0, 0.5)
                        .mesh(0.0, kLo, kHi));
}

}  // namespace
}  // namespace demcal::dem
