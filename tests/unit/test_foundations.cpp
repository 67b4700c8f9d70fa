// Small checks of the surrogate and calibrate foundations.
#include "calibrate/goodness_of_fit.hpp"
#include "surrogate/full_factorial_design.hpp"

#include <gtest/gtest.h>

#include <cmath>

using demcal::calibrate::goodness_of_fit;
using demcal::surrogate::full_factorial_design;
using demcal::surrogate::ParameterRange;

TEST(FullFactorialDesign, CoversEveryCombinationWithExactBounds) {
  const auto pts = full_factorial_design({{"mu_r", 0.05, 0.6, 3}, {"mu_s", 0.2, 0.9, 4}});
  ASSERT_EQ(pts.size(), 12u);
  EXPECT_DOUBLE_EQ(pts.front()[0], 0.05);
  EXPECT_DOUBLE_EQ(pts.front()[1], 0.2);
  EXPECT_DOUBLE_EQ(pts.back()[0], 0.6);
  EXPECT_DOUBLE_EQ(pts.back()[1], 0.9);
  EXPECT_NEAR(pts[1][1], 0.2 + 0.7 / 3.0, 1e-15);  // last parameter varies fastest
  EXPECT_NEAR(pts[4][0], 0.325, 1e-15);
}

TEST(FullFactorialDesign, RefusesEmptyRangesNamingTheParameter) {
  try {
    full_factorial_design({{"mu_s", 0.9, 0.2, 3}});
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mu_s"), std::string::npos);
  }
}

TEST(GoodnessOfFit, ChiSquareAndPValueMatchTables) {
  // chi2 = 3.84 with 1 dof is the 95 % point.
  const auto g = goodness_of_fit({std::sqrt(3.841458820694124), 0.0, 0.0}, 2);
  EXPECT_EQ(g.degrees_of_freedom, 1);
  EXPECT_NEAR(g.p_value, 0.05, 1e-9);
  EXPECT_THROW(goodness_of_fit({1.0}, 1), std::invalid_argument);
}
