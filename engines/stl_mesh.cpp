#include "engines/stl_mesh.hpp"

#include "engines/deck.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <vector>

namespace demcal::engines {
namespace {

struct Point {
  double x, y, z;
};

std::string n(double v) { return deck_number(v); }

// One solid; each facet's normal from its vertices' order (right hand).
class StlSolid {
 public:
  explicit StlSolid(const std::string& name) { s_ << "solid " << name << "\n"; }

  void triangle(Point a, Point b, Point c) {
    const Point u{b.x - a.x, b.y - a.y, b.z - a.z}, v{c.x - a.x, c.y - a.y, c.z - a.z};
    Point nrm{u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
    const double len = std::sqrt(nrm.x * nrm.x + nrm.y * nrm.y + nrm.z * nrm.z);
    if (len == 0.0) return;  // a degenerate facet (a cone's apex): nothing to meet
    write(a, b, c, {nrm.x / len, nrm.y / len, nrm.z / len});
  }
  void quad(Point a, Point b, Point c, Point d) {
    triangle(a, b, c);
    triangle(a, c, d);
  }
  // With a stated normal (axis-aligned faces: exact zeros in the file).
  void write(Point a, Point b, Point c, Point nrm) {
    s_ << "  facet normal " << n(nrm.x) << " " << n(nrm.y) << " " << n(nrm.z)
       << "\n    outer loop\n";
    for (const Point& p : {a, b, c})
      s_ << "      vertex " << n(p.x) << " " << n(p.y) << " " << n(p.z) << "\n";
    s_ << "    endloop\n  endfacet\n";
  }
  std::string finish(const std::string& name) {
    s_ << "endsolid " << name << "\n";
    return s_.str();
  }

 private:
  std::ostringstream s_;
};

Point on_circle(double r, double z, int i, int segments) {
  const double phi = 2.0 * std::numbers::pi * static_cast<double>(i) / segments;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace

std::string block_stl(const SolidBlock& b) {
  const double x0 = b.lower_m.x, x1 = b.upper_m.x, y0 = b.lower_m.y, y1 = b.upper_m.y,
               z0 = b.lower_m.z, z1 = b.upper_m.z;
  StlSolid s(b.name);
  auto quad = [&](Point a, Point c, Point d, Point e, Point nrm) {
    s.write(a, c, d, nrm);
    s.write(a, d, e, nrm);
  };
  quad({x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}, {0, 0, 1});   // top
  quad({x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}, {0, 0, -1});  // bottom
  quad({x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0}, {-1, 0, 0});  // -x
  quad({x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}, {1, 0, 0});   // +x
  return s.finish(b.name);
}

std::string slanted_plate_stl(const SlantedPlate& p, double y0, double y1) {
  const double xa = p.x_lower_m, xb = p.x_upper_m, za = p.z_lower_m, zb = p.z_upper_m,
               t = p.tilt_x_m;
  StlSolid s(p.name);
  // Outward normals by vertex order: top +z, bottom -z, the sides outwards in x.
  s.quad({xa + t, y0, zb}, {xb + t, y0, zb}, {xb + t, y1, zb}, {xa + t, y1, zb});  // top
  s.quad({xa, y0, za}, {xa, y1, za}, {xb, y1, za}, {xb, y0, za});                  // bottom
  s.quad({xa, y0, za}, {xa + t, y0, zb}, {xa + t, y1, zb}, {xa, y1, za});          // lower-x side
  s.quad({xb, y0, za}, {xb, y1, za}, {xb + t, y1, zb}, {xb + t, y0, zb});          // upper-x side
  return s.finish(p.name);
}

std::string axial_shell_stl(const AxialShell& sh, int segments) {
  StlSolid s(sh.name);
  for (int i = 0; i < segments; ++i) {
    const Point a = on_circle(sh.radius_lower_m, sh.z_lower_m, i, segments);
    const Point b = on_circle(sh.radius_lower_m, sh.z_lower_m, i + 1, segments);
    const Point c = on_circle(sh.radius_upper_m, sh.z_upper_m, i + 1, segments);
    const Point d = on_circle(sh.radius_upper_m, sh.z_upper_m, i, segments);
    s.quad(a, b, c, d);  // normal outwards, away from the axis
  }
  return s.finish(sh.name);
}

std::string axial_disc_stl(const AxialDisc& d, int segments) {
  StlSolid s(d.name);
  const Point top{0, 0, d.z_upper_m}, bottom{0, 0, d.z_lower_m};
  for (int i = 0; i < segments; ++i) {
    const Point t0 = on_circle(d.radius_m, d.z_upper_m, i, segments);
    const Point t1 = on_circle(d.radius_m, d.z_upper_m, i + 1, segments);
    const Point b0 = on_circle(d.radius_m, d.z_lower_m, i, segments);
    const Point b1 = on_circle(d.radius_m, d.z_lower_m, i + 1, segments);
    s.triangle(top, t0, t1);     // +z
    s.triangle(bottom, b1, b0);  // -z
    s.quad(b0, b1, t1, t0);      // the rim, outwards
  }
  return s.finish(d.name);
}

std::string axial_annulus_stl(const AxialAnnulus& a, int segments) {
  StlSolid s(a.name);
  const double ri = a.inner_radius_m, ro = a.outer_radius_m, z0 = a.z_lower_m, z1 = a.z_upper_m;
  for (int i = 0; i < segments; ++i) {
    const Point ti0 = on_circle(ri, z1, i, segments), ti1 = on_circle(ri, z1, i + 1, segments);
    const Point to0 = on_circle(ro, z1, i, segments), to1 = on_circle(ro, z1, i + 1, segments);
    const Point bi0 = on_circle(ri, z0, i, segments), bi1 = on_circle(ri, z0, i + 1, segments);
    const Point bo0 = on_circle(ro, z0, i, segments), bo1 = on_circle(ro, z0, i + 1, segments);
    s.quad(ti0, to0, to1, ti1);  // top ring, +z
    s.quad(bi0, bi1, bo1, bo0);  // bottom ring, -z
    s.quad(bo0, bo1, to1, to0);  // outer rim, away from the axis
    s.quad(bi0, ti0, ti1, bi1);  // the hole's wall, towards the axis
  }
  return s.finish(a.name);
}

int polygon_segments(double radius_m, double max_sagitta_m) {
  if (!(radius_m > 0.0) || !(max_sagitta_m > 0.0) || max_sagitta_m >= radius_m) return 24;
  const double half_angle = std::acos(1.0 - max_sagitta_m / radius_m);
  return std::max(24, static_cast<int>(std::ceil(std::numbers::pi / half_angle)));
}

}  // namespace demcal::engines
