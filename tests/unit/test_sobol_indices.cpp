// Sobol sensitivity indices against the Ishigami function's analytic values, bootstrap
// intervals, a surrogate's indices, and input checks.
#include "surrogate/polynomial_surface.hpp"
#include "surrogate/sobol_indices.hpp"
#include "tests/support/invalid_argument_message.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>

namespace {

using namespace demcal::surrogate;

constexpr double kPi = std::numbers::pi;

// Ishigami (a = 7, b = 0.1) on [-pi, pi]³.
double ishigami(std::span<const double> x) {
  return std::sin(x[0]) + 7.0 * std::pow(std::sin(x[1]), 2) + 0.1 * std::pow(x[2], 4) * std::sin(x[0]);
}

// Analytic values: V = a²/8 + b pi⁴/5 + b² pi⁸/18 + 1/2, V1 = (1 + b pi⁴/5)² / 2,
// V2 = a²/8, V13 = b² pi⁸ (1/18 - 1/50).
struct Analytic {
  double s[3], st[3];
};
Analytic ishigami_indices() {
  const double a = 7.0, b = 0.1, pi4 = std::pow(kPi, 4), pi8 = pi4 * pi4;
  const double v = a * a / 8 + b * pi4 / 5 + b * b * pi8 / 18 + 0.5;
  const double v1 = 0.5 * std::pow(1 + b * pi4 / 5, 2), v2 = a * a / 8;
  const double v13 = b * b * pi8 * (1.0 / 18 - 1.0 / 50);
  return {{v1 / v, v2 / v, 0.0}, {(v1 + v13) / v, v2 / v, v13 / v}};
}

const std::vector<double> kLo = {-kPi, -kPi, -kPi};
const std::vector<double> kHi = {kPi, kPi, kPi};

TEST(SobolIndices, AnalyticIshigamiValuesAreTheOnesQuoted) {
  const Analytic a = ishigami_indices();
  EXPECT_NEAR(a.s[0], 0.3139, 1e-4);
  EXPECT_NEAR(a.s[1], 0.4424, 1e-4);
  EXPECT_NEAR(a.st[0], 0.5576, 1e-4);
  EXPECT_NEAR(a.st[2], 0.2437, 1e-4);
}

TEST(SobolIndices, IshigamiWithTheSobolSequenceWithinFivePercent) {
  SobolOptions opt;
  opt.base_samples = 1 << 14;
  const SobolIndices s = sobol_indices(ishigami, kLo, kHi, opt);
  const Analytic a = ishigami_indices();
  ASSERT_EQ(s.first_order.size(), 3u);
  EXPECT_EQ(s.evaluations, (1u << 14) * 5u);
  for (int i = 0; i < 3; ++i) {
    const double tol_s = a.s[i] > 0 ? 0.05 * a.s[i] : 0.02;
    EXPECT_NEAR(s.first_order[static_cast<std::size_t>(i)], a.s[i], tol_s) << "S" << i + 1;
    EXPECT_NEAR(s.total[static_cast<std::size_t>(i)], a.st[i], 0.05 * a.st[i]) << "ST" << i + 1;
  }
  EXPECT_NEAR(s.mean, 3.5, 0.02);  // a / 2
  EXPECT_TRUE(s.first_order_lower.empty());
}

TEST(SobolIndices, PseudoRandomBootstrapIntervalsCoverTheAnalyticValues) {
  SobolOptions opt;
  opt.base_samples = 1 << 12;
  opt.sampling = SobolSampling::pseudo_random;
  opt.seed = 2024;
  opt.bootstrap_resamples = 100;
  opt.confidence_level = 0.99;
  const SobolIndices s = sobol_indices(ishigami, kLo, kHi, opt);
  const Analytic a = ishigami_indices();
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_LE(s.first_order_lower[i], a.s[i]) << "S" << i + 1;
    EXPECT_GE(s.first_order_upper[i], a.s[i]) << "S" << i + 1;
    EXPECT_LE(s.total_lower[i], a.st[i]) << "ST" << i + 1;
    EXPECT_GE(s.total_upper[i], a.st[i]) << "ST" << i + 1;
    EXPECT_LT(s.first_order_upper[i] - s.first_order_lower[i], 0.2);  // informative intervals
    EXPECT_LT(s.total_upper[i] - s.total_lower[i], 0.15);
    EXPECT_LE(s.first_order_lower[i], s.first_order[i]);
    EXPECT_GE(s.first_order_upper[i], s.first_order[i]);
  }
  // Deterministic for a seed, different for another.
  const SobolIndices again = sobol_indices(ishigami, kLo, kHi, opt);
  EXPECT_EQ(again.first_order, s.first_order);
  EXPECT_EQ(again.total_upper, s.total_upper);
  opt.seed = 2025;
  EXPECT_NE(sobol_indices(ishigami, kLo, kHi, opt).first_order, s.first_order);
}

TEST(SobolIndices, OfASurrogateWithAnAdditiveLinearResponse) {
  // y = 3 x0 + x1 on [0, 1] x [0, 2]: variances 9/12 and 4/12, no interaction.
  std::mt19937_64 rng(5);
  Eigen::MatrixXd x(12, 2);
  for (Eigen::Index i = 0; i < 12; ++i)
    x.row(i) << static_cast<double>(rng() >> 11) * 0x1.0p-53, 2.0 * static_cast<double>(rng() >> 11) * 0x1.0p-53;
  const Eigen::VectorXd y = 3.0 * x.col(0) + x.col(1);
  PolynomialOptions popt;
  popt.degree = 1;
  const auto surface = PolynomialSurface::fit(x, y, popt);
  SobolOptions opt;
  opt.base_samples = 4096;
  const SobolIndices s = sobol_indices(surface, {0.0, 0.0}, {1.0, 2.0}, opt);
  EXPECT_NEAR(s.first_order[0], 9.0 / 13.0, 0.01);
  EXPECT_NEAR(s.first_order[1], 4.0 / 13.0, 0.01);
  EXPECT_NEAR(s.total[0], 9.0 / 13.0, 0.01);
  EXPECT_NEAR(s.total[1], 4.0 / 13.0, 0.01);
  EXPECT_NEAR(s.variance, 13.0 / 12.0, 0.01);
}

using demcal::testing::invalid_argument_message;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST(SobolIndices, RejectsBadInputNamingTheProblem) {
  EXPECT_TRUE(contains(invalid_argument_message([] { sobol_indices(ishigami, {0, 0}, {1, 1, 1}); }),
                       "lower has 2 entries but upper has 3"));
  EXPECT_TRUE(contains(invalid_argument_message([] { sobol_indices(ishigami, {0, 1, 0}, {1, 1, 1}); }),
                       "upper[1] must exceed lower[1]"));
  SobolOptions opt;
  opt.base_samples = 4;
  EXPECT_TRUE(contains(invalid_argument_message([&] { sobol_indices(ishigami, kLo, kHi, opt); }),
                       "base_samples"));
  const std::vector<double> lo21(21, 0.0), hi21(21, 1.0);
  EXPECT_TRUE(contains(invalid_argument_message([&] {
                         sobol_indices([](std::span<const double>) { return 1.0; }, lo21, hi21);
                       }),
                       "at most 20 inputs"));
  EXPECT_TRUE(contains(invalid_argument_message([] {
                         sobol_indices([](std::span<const double>) { return 2.0; }, {0.0}, {1.0});
                       }),
                       "constant"));
  EXPECT_TRUE(contains(invalid_argument_message([] {
                         sobol_indices([](std::span<const double> x) { return std::log(x[0] - 0.5); },
                                       {0.0}, {1.0});
                       }),
                       "not finite"));
}

}  // namespace
