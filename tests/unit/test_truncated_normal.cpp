// The bounded Gaussian that the discrepancy's parameter estimates are reported
// with (calibrate/detail/truncated_normal.hpp), against closed forms.
#include "calibrate/detail/truncated_normal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace demcal::calibrate::detail {
namespace {

TEST(TruncatedNormal, HalfNormalMeanAndMedian) {
  // N(0, 1) on [0, inf): mean sqrt(2/pi), median Phi^-1(3/4) = 0.67449.
  const TruncatedNormal t(0.0, 1.0, 0.0, 1e6);
  EXPECT_NEAR(t.mean(), std::sqrt(2.0 / std::numbers::pi), 1e-12);
  EXPECT_NEAR(t.quantile(0.5), 0.6744897501960817, 1e-9);
  EXPECT_DOUBLE_EQ(t.quantile(0.0), 0.0);
}

TEST(TruncatedNormal, WideBoundsAreTheGaussian) {
  const TruncatedNormal t(2.0, 0.5, -100.0, 100.0);
  EXPECT_NEAR(t.mean(), 2.0, 1e-12);
  EXPECT_NEAR(t.quantile(0.975), 2.0 + 0.5 * 1.959963984540054, 1e-9);
  EXPECT_NEAR(t.quantile(0.025), 2.0 - 0.5 * 1.959963984540054, 1e-9);
}

TEST(TruncatedNormal, UniformLimitOfAWideGaussian) {
  // sd >> the box: nearly uniform on [1, 2].
  const TruncatedNormal t(1.5, 1e4, 1.0, 2.0);
  EXPECT_NEAR(t.mean(), 1.5, 1e-6);
  EXPECT_NEAR(t.quantile(0.25), 1.25, 1e-6);
}

TEST(TruncatedNormal, AMeanFarAboveTheBoxStaysInsideAndNearTheUpperBound) {
  // Mean 1.65, sd 0.05, box [0.2, 1.1]: 11 sd above. The restricted mass sits at the
  // upper bound with an exponential tail of scale sd^2 / 0.55 = 0.0045.
  const TruncatedNormal t(1.65, 0.05, 0.2, 1.1);
  const double m = t.mean();
  EXPECT_LT(m, 1.1);
  EXPECT_NEAR(m, 1.1 - 0.05 * 0.05 / 0.55, 1e-3);
  EXPECT_LE(t.quantile(0.025), m);
  EXPECT_GE(t.quantile(0.975), m);
  EXPECT_LE(t.quantile(0.975), 1.1);
  EXPECT_GE(t.quantile(0.025), 0.2);
}

TEST(TruncatedNormal, MirrorSymmetry) {
  // Far below and far above give mirrored answers, including past where the tail
  // probabilities underflow (60 sd).
  for (const double k : {3.0, 11.0, 60.0}) {
    const TruncatedNormal above(1.0 + k, 1.0, 0.0, 1.0), below(-k, 1.0, 0.0, 1.0);
    EXPECT_NEAR(above.mean(), 1.0 - below.mean(), 1e-9) << k;
    EXPECT_NEAR(above.quantile(0.1), 1.0 - below.quantile(0.9), 1e-9) << k;
    EXPECT_GT(below.mean(), 0.0);
    EXPECT_LT(below.mean(), 1.0);
  }
}

TEST(TruncatedNormal, QuantilesIncreaseAndHoldTheMean) {
  for (const double mu : {-3.0, 0.1, 0.5, 0.9, 4.0}) {
    const TruncatedNormal t(mu, 0.3, 0.0, 1.0);
    double last = -1.0;
    for (int k = 0; k <= 20; ++k) {
      const double q = t.quantile(k / 20.0);
      EXPECT_GE(q, last) << mu;
      last = q;
    }
    EXPECT_GE(t.mean(), t.quantile(0.0));
    EXPECT_LE(t.mean(), t.quantile(1.0));
  }
}

TEST(TruncatedNormal, ZeroSdIsThePointClampedToTheBox) {
  EXPECT_DOUBLE_EQ(TruncatedNormal(3.0, 0.0, 0.0, 1.0).mean(), 1.0);
  EXPECT_DOUBLE_EQ(TruncatedNormal(0.4, 0.0, 0.0, 1.0).quantile(0.9), 0.4);
}

TEST(TruncatedNormal, RefusesBadArguments) {
  EXPECT_THROW(TruncatedNormal(0.0, -1.0, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(TruncatedNormal(0.0, 1.0, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(TruncatedNormal(NAN, 1.0, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(TruncatedNormal(0.0, 1.0, 0.0, 1.0).quantile(1.5), std::invalid_argument);
}

}  // namespace
}  // namespace demcal::calibrate::detail
