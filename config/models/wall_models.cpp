// The wall types of [[wall]]: a section per type (its reader and its
// declaration), then the registry that lists them.

#include "config/models/wall_models.hpp"

#include "dem/wall/bounded_plane_wall.hpp"
#include "dem/wall/cone_wall.hpp"
#include "dem/wall/cylinder_wall.hpp"
#include "dem/wall/orifice_plate_wall.hpp"
#include "dem/wall/plane_wall.hpp"

namespace demcal::config {

namespace {

using reader::Table;
using reader::Vec3;
using reader::above;
using reader::any_number;
using reader::at_least;
using reader::guarded;

const std::string kPoint = "[x, y, z]";
const std::string kDirection = "non-zero [x, y, z]";
const std::string kPositive = range_of(above(0));

// ---------------------------------------------------------------- plane

std::unique_ptr<dem::Wall> read_plane(Table& w) {
  const Vec3 p = w.vec3("point_m");
  const Vec3 n = w.direction("normal");
  return guarded(w, [&] { return std::make_unique<dem::PlaneWall>(p, n); });
}

ModelInfo plane_info() {
  return {"plane",
          "an infinite plane; particles stay on the side its normal points to",
          {{"point_m", "m", "required", kPoint, "a point on the plane"},
           {"normal", "1", "required", kDirection, "the side particles are on"}}};
}

// ---------------------------------------------------------------- rectangle

std::unique_ptr<dem::Wall> read_rectangle(Table& w) {
  const Vec3 c = w.vec3("centre_m");
  const Vec3 n = w.direction("normal");
  const Vec3 u = w.direction("axis_u");
  const double hu = w.number("half_length_u_m", above(0));
  const double hv = w.number("half_length_v_m", above(0));
  return guarded(w, [&] { return std::make_unique<dem::RectangleWall>(c, n, u, hu, hv); });
}

ModelInfo rectangle_info() {
  return {"rectangle",
          "a bounded rectangle, two-sided",
          {{"centre_m", "m", "required", kPoint, "the rectangle's centre"},
           {"normal", "1", "required", kDirection, "the rectangle's normal"},
           {"axis_u", "1", "required", kDirection, "the direction of its first side"},
           {"half_length_u_m", "m", "required", kPositive, "half its length along axis_u"},
           {"half_length_v_m", "m", "required", kPositive,
            "half its length along v = normal x axis_u"}}};
}

// ---------------------------------------------------------------- disk

std::unique_ptr<dem::Wall> read_disk(Table& w) {
  const Vec3 c = w.vec3("centre_m");
  const Vec3 n = w.direction("normal");
  const double r = w.number("radius_m", above(0));
  return guarded(w, [&] { return std::make_unique<dem::DiskWall>(c, n, r); });
}

ModelInfo disk_info() {
  return {"disk",
          "a bounded disk, two-sided",
          {{"centre_m", "m", "required", kPoint, "the disk's centre"},
           {"normal", "1", "required", kDirection, "the disk's normal"},
           {"radius_m", "m", "required", kPositive, "the disk's radius"}}};
}

// ---------------------------------------------------------------- cylinder

std::unique_ptr<dem::Wall> read_cylinder(Table& w) {
  const Vec3 b = w.vec3("base_m");
  const Vec3 a = w.direction("axis");
  const double len = w.number("length_m", above(0));
  const double r = w.number("radius_m", above(0));
  return guarded(w, [&] { return std::make_unique<dem::CylinderWall>(b, a, len, r); });
}

ModelInfo cylinder_info() {
  return {"cylinder",
          "a finite cylinder's lateral surface, two-sided, open at both ends",
          {{"base_m", "m", "required", kPoint, "the centre of its base"},
           {"axis", "1", "required", kDirection, "from the base along the cylinder"},
           {"length_m", "m", "required", kPositive, "its length along the axis"},
           {"radius_m", "m", "required", kPositive, "its radius"}}};
}

// ---------------------------------------------------------------- cone

std::unique_ptr<dem::Wall> read_cone(Table& w) {
  const Vec3 b = w.vec3("base_m");
  const Vec3 a = w.direction("axis");
  const double len = w.number("length_m", above(0));
  const double r0 = w.number("radius_base_m", at_least(0));
  const double r1 = w.number("radius_end_m", at_least(0));
  if (r0 == 0.0 && r1 == 0.0)
    w.fail("radius_end_m", "radius_base_m and radius_end_m cannot both be 0");
  return guarded(w, [&] { return std::make_unique<dem::ConeWall>(b, a, len, r0, r1); });
}

ModelInfo cone_info() {
  return {"cone",
          "a conical frustum's lateral surface (a hopper, a funnel), two-sided, open at both ends",
          {{"base_m", "m", "required", kPoint, "the centre of its base"},
           {"axis", "1", "required", kDirection, "from the base along the cone"},
           {"length_m", "m", "required", kPositive, "its length along the axis"},
           {"radius_base_m", "m", "required", range_of(at_least(0)), "its radius at the base"},
           {"radius_end_m", "m", "required", range_of(at_least(0)) + "; not both radii 0",
            "its radius at the other end"}}};
}

// ---------------------------------------------------------------- orifice_plate

std::unique_ptr<dem::Wall> read_orifice_plate(Table& w) {
  const Vec3 c = w.vec3("centre_m");
  const Vec3 n = w.direction("normal");
  const double open_s = w.number("open_time_s", any_number());
  const bool circle = w.has("diameter_m");
  const bool slot = w.has("width_m");
  if (circle && slot)
    w.fail("width_m", "give diameter_m (a circular hole) or width_m (a slot), not both");
  if (!circle && !slot)
    w.fail(
        "diameter_m",
        "missing required key; expected diameter_m (a circular hole) or width_m + axis_u (a slot)");
  const double opening = w.number(circle ? "diameter_m" : "width_m", above(0));
  const Vec3 u = slot ? w.direction("axis_u") : w.vec3_or("axis_u", Vec3{});
  const double outer = w.number_or("outer_radius_m", 0.0, at_least(0));
  const auto shape = circle ? dem::OrificeShape::circle : dem::OrificeShape::slot;
  return guarded(w, [&] {
    return std::make_unique<dem::OrificePlateWall>(c, n, u, shape, opening, open_s, outer);
  });
}

ModelInfo orifice_plate_info() {
  return {"orifice_plate",
          "a two-sided plate, solid until open_time_s, then with a hole: a circle, or a slot unbounded along normal x axis_u",
          {{"centre_m", "m", "required", kPoint, "the hole's centre"},
           {"normal", "1", "required", kDirection, "the plate's normal"},
           {"open_time_s", "s", "required", range_of(any_number()), "when the hole opens"},
           {"diameter_m", "m", "diameter_m or width_m", kPositive, "a circular hole's diameter"},
           {"width_m", "m", "diameter_m or width_m", kPositive, "a slot's width"},
           {"axis_u", "1", "[0, 0, 0] (required with width_m)", kDirection,
            "the direction the slot's width is across (for a circle it only orients the mesh)"},
           {"outer_radius_m", "m", "0", range_of(at_least(0)),
            "the plate's outer radius; 0: an unbounded plate"}}};
}

}  // namespace

const WallRegistry& wall_models() {
  // Registration order is the order messages list the types in.
  static const WallRegistry registry = [] {
    WallRegistry r({"wall", "", "[[wall]] type = \"<name>\""});
    r.add(plane_info(), &read_plane);
    r.add(rectangle_info(), &read_rectangle);
    r.add(disk_info(), &read_disk);
    r.add(cylinder_info(), &read_cylinder);
    r.add(cone_info(), &read_cone);
    r.add(orifice_plate_info(), &read_orifice_plate);
    return r;
  }();
  return registry;
}

}  // namespace demcal::config
