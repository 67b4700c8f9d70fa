// The STL surfaces LIGGGHTS decks take as walls (engines/stl_mesh.hpp): every
// vertex on the solid's true surface, every facet's normal pointing out of the
// solid (away from the axis for a shell), a closed disc watertight, and a
// polygon fine enough for the stated sagitta.
#include "engines/stl_mesh.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace demcal::engines {
namespace {

struct Facet {
  std::array<double, 3> normal;
  std::array<std::array<double, 3>, 3> vertices;
};

std::vector<Facet> parse(const std::string& stl) {
  std::vector<Facet> out;
  std::istringstream in(stl);
  std::string word;
  while (in >> word) {
    if (word == "facet") {
      Facet f{};
      in >> word >> f.normal[0] >> f.normal[1] >> f.normal[2];
      in >> word >> word;  // outer loop
      for (auto& v : f.vertices) in >> word >> v[0] >> v[1] >> v[2];
      out.push_back(f);
    }
  }
  return out;
}

std::array<double, 3> centroid(const Facet& f) {
  std::array<double, 3> c{};
  for (const auto& v : f.vertices)
    for (int k = 0; k < 3; ++k) c[k] += v[k] / 3.0;
  return c;
}

// A closed surface: every edge is shared by exactly two facets, once each way.
void expect_closed(const std::vector<Facet>& facets) {
  std::map<std::tuple<long, long, long, long, long, long>, int> edges;
  auto key = [](const std::array<double, 3>& a) {
    return std::array<long, 3>{std::lround(a[0] * 1e9), std::lround(a[1] * 1e9),
                               std::lround(a[2] * 1e9)};
  };
  for (const Facet& f : facets)
    for (int i = 0; i < 3; ++i) {
      const auto a = key(f.vertices[i]), b = key(f.vertices[(i + 1) % 3]);
      ++edges[{a[0], a[1], a[2], b[0], b[1], b[2]}];
    }
  for (const auto& [e, count] : edges) {
    EXPECT_EQ(count, 1);
    EXPECT_NE(edges.find({std::get<3>(e), std::get<4>(e), std::get<5>(e), std::get<0>(e),
                          std::get<1>(e), std::get<2>(e)}),
              edges.end());
  }
}

TEST(StlMesh, AShellsVerticesLieOnTheFrustumAndItsNormalsPointAwayFromTheAxis) {
  const AxialShell cone{"hopper", 0.004, 0.012, 0.03, 0.044};
  const auto facets = parse(axial_shell_stl(cone, 48));
  ASSERT_EQ(facets.size(), 96u);
  for (const Facet& f : facets) {
    for (const auto& v : f.vertices) {
      const double t = (v[2] - cone.z_lower_m) / (cone.z_upper_m - cone.z_lower_m);
      const double r = cone.radius_lower_m + t * (cone.radius_upper_m - cone.radius_lower_m);
      EXPECT_NEAR(std::hypot(v[0], v[1]), r, 1e-12);
    }
    const auto c = centroid(f);
    EXPECT_GT(f.normal[0] * c[0] + f.normal[1] * c[1], 0.0);
    // A cone opening upwards: its outward normal points down.
    EXPECT_LT(f.normal[2], 0.0);
  }
}

TEST(StlMesh, ADiscIsClosedWithOutwardNormals) {
  const AxialDisc disc{"orifice_shut", 0.005, 0.029, 0.030};
  const auto facets = parse(axial_disc_stl(disc, 32));
  ASSERT_EQ(facets.size(), 4u * 32u);
  expect_closed(facets);
  for (const Facet& f : facets) {
    const auto c = centroid(f);
    const std::array<double, 3> out{c[0], c[1], c[2] - 0.5 * (disc.z_lower_m + disc.z_upper_m)};
    EXPECT_GT(f.normal[0] * out[0] + f.normal[1] * out[1] + f.normal[2] * out[2], 0.0);
  }
}

TEST(StlMesh, APlateWithAHoleIsClosedWithOutwardNormalsAndItsRadii) {
  const AxialAnnulus plate{"orifice_plate", 0.004, 0.03, 0.026, 0.03, ""};
  const auto facets = parse(axial_annulus_stl(plate, 40));
  ASSERT_EQ(facets.size(), 8u * 40u);
  expect_closed(facets);
  const double mid_r = 0.5 * (plate.inner_radius_m + plate.outer_radius_m);
  const double mid_z = 0.5 * (plate.z_lower_m + plate.z_upper_m);
  for (const Facet& f : facets) {
    for (const auto& v : f.vertices) {
      const double r = std::hypot(v[0], v[1]);
      EXPECT_TRUE(std::abs(r - plate.inner_radius_m) < 1e-12 ||
                  std::abs(r - plate.outer_radius_m) < 1e-12)
          << r;
    }
    // Outward from the plate's mid-surface (the ring of radius mid_r at mid_z):
    // the hole's wall faces the axis, the rim away from it, the rings up and down.
    const auto c = centroid(f);
    const double r = std::hypot(c[0], c[1]);
    const std::array<double, 3> out{c[0] / r * (r - mid_r), c[1] / r * (r - mid_r), c[2] - mid_z};
    EXPECT_GT(f.normal[0] * out[0] + f.normal[1] * out[1] + f.normal[2] * out[2], 0.0);
  }
}

TEST(StlMesh, ASlantedPlatesFacesPointOutOfIt) {
  const SlantedPlate plate{"hopper_right", 0.004, 0.006, 0.03, 0.044, 0.008};
  const auto facets = parse(slanted_plate_stl(plate, 0.0, 0.006));
  ASSERT_EQ(facets.size(), 8u);
  for (const Facet& f : facets) {
    // The plate is convex: every point of a face lies on the outward side of
    // the plate's centre.
    const auto c = centroid(f);
    const double centre_x = 0.5 * (plate.x_lower_m + plate.x_upper_m + plate.tilt_x_m);
    const double centre_z = 0.5 * (plate.z_lower_m + plate.z_upper_m);
    const double outward = f.normal[0] * (c[0] - centre_x) + f.normal[2] * (c[2] - centre_z);
    EXPECT_GT(outward, 0.0) << c[0] << " " << c[2];
  }
}

TEST(StlMesh, PolygonsKeepTheStatedSagitta) {
  for (const double r : {0.004, 0.04, 0.1}) {
    const double sagitta = 3.6e-5;
    const int n = polygon_segments(r, sagitta);
    EXPECT_LE(r * (1.0 - std::cos(std::numbers::pi / n)), sagitta) << r;
    EXPECT_GT(r * (1.0 - std::cos(std::numbers::pi / (n - 1))), sagitta) << r;
  }
  EXPECT_EQ(polygon_segments(0.001, 0.5), 24);  // never coarser than 24 sides
}

}  // namespace
}  // namespace demcal::engines
