// The probe sensitivities of the diagnosis (calibrate/probe_sensitivity.hpp): exact on a
// linear response, and their standard errors the spread of the estimate over repeated
// noisy probes (Monte Carlo, criterion fixed first: the sample sd of 4000 estimates within
// 5 % of the stated standard error, 5 % being ~4 sd of a sample sd from 4000 draws).
#include "calibrate/probe_sensitivity.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

namespace demcal::calibrate {
namespace {

TEST(ProbeSensitivity, ExactOnALinearResponse) {
  const auto response = [](double phi) { return 30.0 + 2.5 * phi; };
  const ProbeSensitivity secant =
      secant_sensitivity({0.8, response(0.8), 3}, {0.2, response(0.2), 2}, 0.0);
  EXPECT_NEAR(secant.value, 2.5, 1e-12);
  EXPECT_EQ(secant.standard_error, 0.0);
  const ProbeSensitivity one = sensitivity_against_prediction({0.8, response(0.8), 3}, 0.1,
                                                              response(0.1), 0.0, 0.0);
  EXPECT_NEAR(one.value, 2.5, 1e-12);
  EXPECT_EQ(one.standard_error, 0.0);
}

TEST(ProbeSensitivity, StandardErrorsAreTheSpreadOfRepeatedProbes) {
  constexpr int kDraws = 4000;
  const double sd = 0.7, slope = -1.2, pred_var = 0.04;
  std::mt19937_64 rng(17);
  std::normal_distribution<double> noise(0.0, 1.0);
  const auto probe_mean = [&](double phi, int runs) {
    double sum = 0.0;
    for (int r = 0; r < runs; ++r) sum += 10.0 + slope * phi + sd * noise(rng);
    return sum / runs;
  };
  double s1 = 0.0, s2 = 0.0, p1 = 0.0, p2 = 0.0, stated_secant = 0.0, stated_one = 0.0;
  for (int k = 0; k < kDraws; ++k) {
    const ProbeSensitivity a =
        secant_sensitivity({1.0, probe_mean(1.0, 3), 3}, {0.4, probe_mean(0.4, 2), 2}, sd);
    s1 += a.value;
    s2 += a.value * a.value;
    stated_secant = a.standard_error;
    // The surrogate's prediction at the base value is itself uncertain (variance pred_var).
    const double predicted = 10.0 + slope * 0.2 + std::sqrt(pred_var) * noise(rng);
    const ProbeSensitivity b =
        sensitivity_against_prediction({1.0, probe_mean(1.0, 2), 2}, 0.2, predicted, pred_var, sd);
    p1 += b.value;
    p2 += b.value * b.value;
    stated_one = b.standard_error;
  }
  const auto sample_sd = [&](double m1, double m2) {
    const double mean = m1 / kDraws;
    return std::sqrt((m2 / kDraws - mean * mean) * kDraws / (kDraws - 1.0));
  };
  EXPECT_NEAR(s1 / kDraws, slope, 4.0 * stated_secant / std::sqrt(kDraws));
  EXPECT_NEAR(sample_sd(s1, s2) / stated_secant, 1.0, 0.05);
  EXPECT_NEAR(p1 / kDraws, slope, 4.0 * stated_one / std::sqrt(kDraws));
  EXPECT_NEAR(sample_sd(p1, p2) / stated_one, 1.0, 0.05);
}

TEST(ProbeSensitivity, BadInputsAreRefusedByName) {
  EXPECT_THROW(secant_sensitivity({0.5, 1.0, 2}, {0.5, 2.0, 2}, 0.1), std::invalid_argument);
  EXPECT_THROW(secant_sensitivity({0.5, 1.0, 0}, {0.2, 2.0, 2}, 0.1), std::invalid_argument);
  EXPECT_THROW(secant_sensitivity({0.5, 1.0, 2}, {0.2, 2.0, 2}, -0.1), std::invalid_argument);
  EXPECT_THROW(sensitivity_against_prediction({0.5, 1.0, 2}, 0.5, 1.0, 0.0, 0.1),
               std::invalid_argument);
  EXPECT_THROW(sensitivity_against_prediction({0.5, 1.0, 2}, 0.1, 1.0, -1.0, 0.1),
               std::invalid_argument);
  EXPECT_THROW(sensitivity_against_prediction({0.5, NAN, 2}, 0.1, 1.0, 0.0, 0.1),
               std::invalid_argument);
}

}  // namespace
}  // namespace demcal::calibrate
