// The parts of a region on a grid, on shapes whose answer is known: two disjoint discs
// are two parts, a ring is one, a diagonal chain of nodes touching only at corners is
// not connected, and a part without a design point (not the best point's) is flagged.
#include "calibrate/region_components.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace demcal::calibrate {
namespace {

std::vector<double> axis(int n) {
  std::vector<double> a;
  for (int i = 0; i < n; ++i) a.push_back(static_cast<double>(i) / (n - 1));
  return a;
}

// inside(x, y) on an n x n grid over [0, 1]^2, first axis fastest.
template <class F>
std::vector<bool> mask(int n, F inside) {
  const auto a = axis(n);
  std::vector<bool> m;
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix) m.push_back(inside(a[ix], a[iy]));
  return m;
}

TEST(RegionComponents, TwoDisjointDiscsAreTwoPartsWithTheirAreas) {
  const int n = 201;
  const auto m = mask(n, [](double x, double y) {
    return std::hypot(x - 0.25, y - 0.25) < 0.15 || std::hypot(x - 0.7, y - 0.7) < 0.1;
  });
  Eigen::VectorXd best(2);
  best << 0.7, 0.7;
  const auto c = region_components({axis(n), axis(n)}, m, best);
  ASSERT_EQ(c.parts.size(), 2u);
  // The best point's part first, though it is the smaller disc.
  EXPECT_TRUE(c.parts[0].holds_best);
  EXPECT_NEAR(c.parts[0].area, M_PI * 0.01, 0.002);
  EXPECT_NEAR(c.parts[1].area, M_PI * 0.0225, 0.002);
  EXPECT_NEAR(c.parts[1].lower[0], 0.1, 0.01);
  EXPECT_NEAR(c.parts[1].upper[1], 0.4, 0.01);
  EXPECT_EQ(c.label.size(), m.size());
  EXPECT_EQ(c.label[100 * n + 100], -1);  // (0.5, 0.5): outside both
}

TEST(RegionComponents, ARingIsOnePartAndAnEmptyRegionHasNone) {
  const int n = 101;
  const auto ring = mask(n, [](double x, double y) {
    const double r = std::hypot(x - 0.5, y - 0.5);
    return r > 0.2 && r < 0.3;
  });
  EXPECT_EQ(region_components({axis(n), axis(n)}, ring).parts.size(), 1u);
  const auto none = mask(n, [](double, double) { return false; });
  const auto c = region_components({axis(n), axis(n)}, none);
  EXPECT_TRUE(c.parts.empty());
  EXPECT_EQ(describe_components(c, {"a", "b"}), "empty (no grid node inside)");
}

TEST(RegionComponents, NodesTouchingOnlyAtCornersAreSeparateParts) {
  const int n = 5;
  const auto diagonal = mask(n, [](double x, double y) { return std::abs(x - y) < 1e-9; });
  EXPECT_EQ(region_components({axis(n), axis(n)}, diagonal).parts.size(), 5u);
}

TEST(RegionComponents, AnIslandWithoutADesignPointIsFlaggedAndDescribed) {
  const int n = 101;
  // A main band holding the best point and two design points, and an island between
  // design points.
  const auto m = mask(n, [](double x, double y) {
    return (y > 0.4 && y < 0.6) || std::hypot(x - 0.15, y - 0.85) < 0.05;
  });
  Eigen::VectorXd best(2);
  best << 0.5, 0.5;
  Eigen::MatrixXd design(3, 2);
  design << 0.0, 0.5, 1.0, 0.5, 0.5, 1.0;
  const auto c = region_components({axis(n), axis(n)}, m, best, design);
  ASSERT_EQ(c.parts.size(), 2u);
  EXPECT_TRUE(c.parts[0].holds_best);
  EXPECT_EQ(c.parts[0].design_points, 2u);
  EXPECT_FALSE(c.parts[0].between_design_points);
  EXPECT_EQ(c.parts[1].design_points, 0u);
  EXPECT_TRUE(c.parts[1].between_design_points);
  const std::string text = describe_components(c, {"mu_r", "mu_s"});
  EXPECT_NE(text.find("2 separate parts"), std::string::npos) << text;
  EXPECT_NE(text.find("part 2 (mu_r 0.1"), std::string::npos) << text;
  EXPECT_NE(text.find("add design points there"), std::string::npos) << text;
  EXPECT_EQ(
      describe_components(
          region_components({axis(n), axis(n)}, mask(n, [](double, double y) { return y < 0.5; })),
          {"mu_r", "mu_s"}),
      "one connected part");
}

TEST(RegionComponents, ThreeDimensionsAndBadSizesAreHandled) {
  const int n = 21;
  std::vector<bool> m;
  const auto a = axis(n);
  for (int iz = 0; iz < n; ++iz)
    for (int iy = 0; iy < n; ++iy)
      for (int ix = 0; ix < n; ++ix)
        m.push_back(std::hypot(a[ix] - 0.2, a[iy] - 0.2, a[iz] - 0.2) < 0.15 ||
                    std::hypot(a[ix] - 0.8, a[iy] - 0.8, a[iz] - 0.8) < 0.15);
  EXPECT_EQ(region_components({a, a, a}, m).parts.size(), 2u);
  EXPECT_THROW(region_components({a, a}, m), std::invalid_argument);
}

}  // namespace
}  // namespace demcal::calibrate
