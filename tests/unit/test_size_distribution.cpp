#include "dem/size_distribution.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace demcal::dem {
namespace {

constexpr int kDraws = 200'000;

struct SampleStats {
  double mean_m = 0.0;
  double variance_m2 = 0.0;
  double mean_d3_m3 = 0.0;
  double min_m = std::numeric_limits<double>::infinity();
  double max_m = -std::numeric_limits<double>::infinity();
};

SampleStats sample(const SizeDistribution& dist, std::uint64_t seed, int n = kDraws) {
  Random rng(seed);
  SampleStats s;
  // Welford, because the spread is tiny next to the mean (micrometres squared
  // against millimetres squared) and the naive formula would cancel.
  double m2 = 0.0;
  double sum_d3 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double d = dist.sample_diameter_m(rng);
    const double delta = d - s.mean_m;
    s.mean_m += delta / (i + 1);
    m2 += delta * (d - s.mean_m);
    sum_d3 += d * d * d;
    s.min_m = std::min(s.min_m, d);
    s.max_m = std::max(s.max_m, d);
  }
  s.variance_m2 = m2 / (n - 1);
  s.mean_d3_m3 = sum_d3 / n;
  return s;
}

// Five standard errors: a fixed seed makes the test deterministic, and this
// margin keeps it valid for any seed a future change might pick.
double mean_tolerance(double variance, int n = kDraws) { return 5.0 * std::sqrt(variance / n); }

double phi(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi); }
double cdf(double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); }

// Raw moments E[Z^k], k = 0..3, of a standard normal truncated to [alpha, beta],
// by the recurrence E[Z^k] = (k-1) E[Z^{k-2}] - [z^{k-1} phi(z)]_alpha^beta / P.
std::vector<double> truncated_standard_moments(double alpha, double beta) {
  const double p = cdf(beta) - cdf(alpha);
  std::vector<double> m(4);
  m[0] = 1.0;
  m[1] = -(phi(beta) - phi(alpha)) / p;
  for (int k = 2; k <= 3; ++k)
    m[k] = (k - 1) * m[k - 2] -
           (std::pow(beta, k - 1) * phi(beta) - std::pow(alpha, k - 1) * phi(alpha)) / p;
  return m;
}

std::string invalid_argument_message(const std::function<void()>& make) {
  try {
    make();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "<no std::invalid_argument thrown>";
}

// A macro rather than a function so the failure shows the offending call.
#define EXPECT_INVALID(call, fragment)                                          \
  do {                                                                          \
    const std::string message = invalid_argument_message([&] { (void)call; });  \
    EXPECT_NE(message.find(fragment), std::string::npos)                        \
        << #call << "\n  message: " << message << "\n  expected: " << fragment; \
  } while (false)

TEST(SizeDistribution, MonodisperseAlwaysDrawsItsDiameter) {
  const auto dist = make_monodisperse(5e-4);
  Random rng(1);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(dist->sample_diameter_m(rng), 5e-4);
  EXPECT_EQ(dist->min_diameter_m(), 5e-4);
  EXPECT_EQ(dist->max_diameter_m(), 5e-4);
  EXPECT_DOUBLE_EQ(dist->mean_diameter_cubed_m3(), 5e-4 * 5e-4 * 5e-4);
}

TEST(SizeDistribution, UniformMatchesAnalyticMoments) {
  const double a = 3e-4;
  const double b = 6e-4;
  const auto dist = make_uniform(a, b);
  const SampleStats s = sample(*dist, 11);
  const double variance = (b - a) * (b - a) / 12.0;
  EXPECT_NEAR(s.mean_m, 0.5 * (a + b), mean_tolerance(variance));
  EXPECT_NEAR(s.variance_m2, variance, 0.02 * variance);
  EXPECT_GE(s.min_m, a);
  EXPECT_LE(s.max_m, b);
  EXPECT_EQ(dist->min_diameter_m(), a);
  EXPECT_EQ(dist->max_diameter_m(), b);
  const double exact_d3 = (b * b * b * b - a * a * a * a) / (4.0 * (b - a));
  EXPECT_NEAR(dist->mean_diameter_cubed_m3(), exact_d3, 1e-12 * exact_d3);
  EXPECT_NEAR(s.mean_d3_m3, exact_d3, 0.01 * exact_d3);
}

TEST(SizeDistribution, UniformWithEqualBoundsIsMonodisperse) {
  const auto dist = make_uniform(4e-4, 4e-4);
  Random rng(3);
  EXPECT_EQ(dist->sample_diameter_m(rng), 4e-4);
  EXPECT_DOUBLE_EQ(dist->mean_diameter_cubed_m3(), 4e-4 * 4e-4 * 4e-4);
}

TEST(SizeDistribution, TruncatedNormalMatchesClosedFormMoments) {
  // Asymmetric truncation, so a sampler that clipped or ignored a bound would
  // shift the mean well beyond the tolerance.
  const double mu = 4.5e-4;
  const double sd = 1e-4;
  const double lo = 3e-4;
  const double hi = 5e-4;
  const auto dist = make_truncated_normal(mu, sd, lo, hi);
  const SampleStats s = sample(*dist, 12);

  const double alpha = (lo - mu) / sd;
  const double beta = (hi - mu) / sd;
  const std::vector<double> z = truncated_standard_moments(alpha, beta);
  const double mean = mu + sd * z[1];
  const double variance = sd * sd * (z[2] - z[1] * z[1]);

  EXPECT_NEAR(s.mean_m, mean, mean_tolerance(variance));
  EXPECT_NEAR(s.variance_m2, variance, 0.02 * variance);
  EXPECT_GE(s.min_m, lo);
  EXPECT_LE(s.max_m, hi);
  EXPECT_NEAR(s.mean_d3_m3, dist->mean_diameter_cubed_m3(), 0.01 * s.mean_d3_m3);
}

TEST(SizeDistribution, TruncatedNormalQuadratureMatchesClosedFormThirdMoment) {
  struct Case {
    double mu, sd, lo, hi;
  };
  // Wide, one-sided, and very narrow next to the interval (the quadrature
  // window must shrink to the spread, not the bounds).
  for (const Case c : {Case{4.5e-4, 1e-4, 3e-4, 5e-4}, Case{1e-3, 5e-4, 1e-4, 5e-3},
                       Case{1e-3, 1e-6, 1e-5, 1e-1}, Case{2e-4, 1e-3, 1e-4, 3e-4}}) {
    const auto dist = make_truncated_normal(c.mu, c.sd, c.lo, c.hi);
    const std::vector<double> z =
        truncated_standard_moments((c.lo - c.mu) / c.sd, (c.hi - c.mu) / c.sd);
    const double exact = c.mu * c.mu * c.mu + 3.0 * c.mu * c.mu * c.sd * z[1] +
                         3.0 * c.mu * c.sd * c.sd * z[2] + c.sd * c.sd * c.sd * z[3];
    EXPECT_NEAR(dist->mean_diameter_cubed_m3(), exact, 1e-8 * exact)
        << "mu " << c.mu << " sd " << c.sd << " [" << c.lo << ", " << c.hi << "]";
  }
}

TEST(SizeDistribution, LogNormalWideMatchesUntruncatedMoments) {
  const double median = 1e-3;
  const double s_ln = 0.3;
  // Bounds 15 sigma out on either side: the truncation removes nothing.
  const auto dist = make_log_normal(median, s_ln, median * std::exp(-15 * s_ln),
                                    median * std::exp(15 * s_ln));
  const SampleStats s = sample(*dist, 13);
  const double mu = std::log(median);
  const double mean = std::exp(mu + 0.5 * s_ln * s_ln);
  const double variance = (std::exp(s_ln * s_ln) - 1.0) * std::exp(2.0 * mu + s_ln * s_ln);
  EXPECT_NEAR(s.mean_m, mean, mean_tolerance(variance));
  // Log-normal tails are heavier than uniform or normal ones: a wider band.
  EXPECT_NEAR(s.variance_m2, variance, 0.03 * variance);
  const double exact_d3 = std::exp(3.0 * mu + 4.5 * s_ln * s_ln);
  EXPECT_NEAR(dist->mean_diameter_cubed_m3(), exact_d3, 1e-8 * exact_d3);
  EXPECT_NEAR(s.mean_d3_m3, exact_d3, 0.01 * exact_d3);
}

TEST(SizeDistribution, LogNormalTruncatedRespectsBoundsAndThirdMoment) {
  const double median = 1e-3;
  const double s_ln = 0.5;
  const double lo = 6e-4;
  const double hi = 2e-3;
  const auto dist = make_log_normal(median, s_ln, lo, hi);
  const SampleStats s = sample(*dist, 14);
  EXPECT_GE(s.min_m, lo);
  EXPECT_LE(s.max_m, hi);
  // e^{3t} times a Gaussian in t = ln d is the same Gaussian shifted by 3 s^2.
  const double mu = std::log(median);
  const double a = (std::log(lo) - mu) / s_ln;
  const double b = (std::log(hi) - mu) / s_ln;
  const double exact_d3 = std::exp(3.0 * mu + 4.5 * s_ln * s_ln) *
                          (cdf(b - 3.0 * s_ln) - cdf(a - 3.0 * s_ln)) / (cdf(b) - cdf(a));
  EXPECT_NEAR(dist->mean_diameter_cubed_m3(), exact_d3, 1e-8 * exact_d3);
  EXPECT_NEAR(s.mean_d3_m3, exact_d3, 0.01 * exact_d3);
}

TEST(SizeDistribution, SieveCurveReproducesCumulativeMassPassing) {
  // Includes an empty class (1.0-1.4 mm) and a steep coarse class.
  const std::vector<std::pair<double, double>> curve = {
      {0.5e-3, 0.0}, {1.0e-3, 0.2}, {1.4e-3, 0.2}, {2.0e-3, 0.7}, {4.0e-3, 1.0}};
  const auto dist = make_sieve_curve(curve);
  EXPECT_EQ(dist->min_diameter_m(), 0.5e-3);
  EXPECT_EQ(dist->max_diameter_m(), 4.0e-3);

  // Check at every opening and mid-class, where the linear-in-d mass spread
  // predicts the fraction passing by interpolation.
  std::vector<std::pair<double, double>> checks;
  for (std::size_t k = 0; k + 1 < curve.size(); ++k) {
    const auto [a, fa] = curve[k];
    const auto [b, fb] = curve[k + 1];
    checks.emplace_back(a, fa);
    checks.emplace_back(0.5 * (a + b), 0.5 * (fa + fb));
  }
  // Mass-weighted estimates are dominated by the few coarse particles (under
  // 2% of the count carry 30% of the mass here), so ten times the usual draws
  // are needed to keep the 1% tolerance several standard errors wide.
  constexpr int draws = 10 * kDraws;
  std::vector<double> mass_below(checks.size(), 0.0);
  double mass_total = 0.0;
  double smallest_m = std::numeric_limits<double>::infinity();
  double largest_m = 0.0;
  int in_empty_class = 0;
  Random rng(15);
  for (int i = 0; i < draws; ++i) {
    const double d = dist->sample_diameter_m(rng);
    smallest_m = std::min(smallest_m, d);
    largest_m = std::max(largest_m, d);
    if (d > 1.0e-3 && d < 1.4e-3) ++in_empty_class;
    const double m = d * d * d;
    mass_total += m;
    for (std::size_t j = 0; j < checks.size(); ++j)
      if (d < checks[j].first) mass_below[j] += m;
  }
  EXPECT_GE(smallest_m, 0.5e-3);
  EXPECT_LE(largest_m, 4.0e-3);
  EXPECT_EQ(in_empty_class, 0);
  for (std::size_t j = 0; j < checks.size(); ++j)
    EXPECT_NEAR(mass_below[j] / mass_total, checks[j].second, 0.01)
        << "below " << checks[j].first << " m";
  EXPECT_NEAR(mass_total / draws, dist->mean_diameter_cubed_m3(),
              0.01 * dist->mean_diameter_cubed_m3());
}

TEST(SizeDistribution, SieveCurveMeanDiameterCubedIsMassOverNumber) {
  // One class: density ~ d^-3 on [a, b], so E[d^3] = (b - a) / int d^-3 = 2 a^2 b^2 / (a + b).
  const double a = 1e-3;
  const double b = 3e-3;
  const auto dist = make_sieve_curve({{a, 0.0}, {b, 1.0}});
  EXPECT_NEAR(dist->mean_diameter_cubed_m3(), 2.0 * a * a * b * b / (a + b), 1e-15 * a * a * a);
}

TEST(SizeDistribution, SieveCurveSupportSkipsEmptyEndClasses) {
  const auto dist = make_sieve_curve(
      {{0.25e-3, 0.0}, {0.5e-3, 0.0}, {1e-3, 0.4}, {2e-3, 1.0}, {4e-3, 1.0}});
  EXPECT_EQ(dist->min_diameter_m(), 0.5e-3);
  EXPECT_EQ(dist->max_diameter_m(), 2e-3);
  Random rng(16);
  for (int i = 0; i < 20'000; ++i) {
    const double d = dist->sample_diameter_m(rng);
    ASSERT_GE(d, 0.5e-3);
    ASSERT_LE(d, 2e-3);
  }
}

TEST(SizeDistribution, SieveCurveAcceptsEndFractionsOffByRounding) {
  EXPECT_NO_THROW(make_sieve_curve({{1e-3, 1e-12}, {2e-3, 0.3}, {3e-3, 1.0 - 1e-12}}));
  EXPECT_NO_THROW(make_sieve_curve({{1e-3, 0.0}, {2e-3, 1.0 + 1e-12}, {3e-3, 1.0}}));
}

TEST(SizeDistribution, SameSeedGivesSameSequence) {
  std::vector<std::unique_ptr<SizeDistribution>> dists;
  dists.push_back(make_monodisperse(1e-3));
  dists.push_back(make_uniform(3e-4, 6e-4));
  dists.push_back(make_truncated_normal(4.5e-4, 1e-4, 3e-4, 5e-4));
  dists.push_back(make_log_normal(1e-3, 0.5, 6e-4, 2e-3));
  dists.push_back(make_sieve_curve({{0.5e-3, 0.0}, {1e-3, 0.3}, {2e-3, 1.0}}));
  for (const auto& dist : dists) {
    Random first(2024);
    Random second(2024);
    Random other(2025);
    bool any_differs = false;
    for (int i = 0; i < 1000; ++i) {
      const double d = dist->sample_diameter_m(first);
      ASSERT_EQ(d, dist->sample_diameter_m(second)) << dist->describe() << " draw " << i;
      any_differs = any_differs || d != dist->sample_diameter_m(other);
    }
    if (dist->min_diameter_m() < dist->max_diameter_m()) {
      EXPECT_TRUE(any_differs) << dist->describe() << ": the seed has no effect";
    }
  }
}

TEST(SizeDistribution, DescribeNamesKindAndRange) {
  EXPECT_EQ(make_monodisperse(5e-4)->describe(), "monodisperse 500 um");
  EXPECT_EQ(make_uniform(3e-4, 6e-4)->describe(), "uniform 300-600 um");
  EXPECT_EQ(make_truncated_normal(4.5e-4, 5e-5, 3e-4, 6e-4)->describe(),
            "truncated normal mean 450 um, sd 50 um, 300-600 um");
  EXPECT_EQ(make_log_normal(2e-3, 0.25, 1e-3, 5e-3)->describe(),
            "log-normal median 2 mm, sigma_ln 0.25, 1-5 mm");
  EXPECT_EQ(make_sieve_curve({{0.5e-3, 0.0}, {1e-3, 0.3}, {2e-3, 1.0}})->describe(),
            "sieve curve, 2 classes, 0.5-2 mm");
}

TEST(SizeDistribution, InvalidMonodisperseThrows) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_INVALID(make_monodisperse(0.0), "diameter_m (0) must be a positive");
  EXPECT_INVALID(make_monodisperse(-1e-3), "diameter_m");
  EXPECT_INVALID(make_monodisperse(nan), "diameter_m");
  EXPECT_INVALID(make_monodisperse(inf), "diameter_m");
}

TEST(SizeDistribution, InvalidUniformThrows) {
  EXPECT_EQ(invalid_argument_message([] { make_uniform(6e-4, 3e-4); }),
            "size distribution 'uniform': min_diameter_m (0.0006) must not exceed "
            "max_diameter_m (0.0003)");
  EXPECT_INVALID(make_uniform(0.0, 3e-4), "min_diameter_m");
  EXPECT_INVALID(make_uniform(-1e-4, 3e-4), "min_diameter_m");
  EXPECT_INVALID(make_uniform(1e-4, std::numeric_limits<double>::infinity()), "max_diameter_m");
  EXPECT_INVALID(make_uniform(1e-4, std::numeric_limits<double>::quiet_NaN()),
                 "max_diameter_m");
}

TEST(SizeDistribution, InvalidTruncatedNormalThrows) {
  EXPECT_INVALID(make_truncated_normal(0.0, 1e-4, 1e-4, 1e-3), "mean_diameter_m");
  EXPECT_INVALID(make_truncated_normal(5e-4, -1e-5, 1e-4, 1e-3), "std_dev_m");
  EXPECT_INVALID(make_truncated_normal(5e-4, std::numeric_limits<double>::quiet_NaN(), 1e-4,
                                       1e-3),
                 "std_dev_m");
  EXPECT_INVALID(make_truncated_normal(5e-4, 1e-4, 0.0, 1e-3), "min_diameter_m");
  EXPECT_INVALID(make_truncated_normal(5e-4, 1e-4, 1e-3, 1e-4), "must not exceed max_diameter_m");
  EXPECT_INVALID(make_truncated_normal(5e-4, 0.0, 6e-4, 1e-3), "mean_diameter_m");
  // The bounds start 3.2 sd above the mean: about 7e-4 of draws would be kept.
  EXPECT_INVALID(make_truncated_normal(1e-3, 1e-4, 1.32e-3, 2e-3), "at least 0.001");
  EXPECT_INVALID(make_truncated_normal(1e-3, 1e-4, 1.32e-3, 2e-3), "std_dev_m");
  // 3.0 sd keeps about 1.3e-3: slow but allowed.
  EXPECT_NO_THROW(make_truncated_normal(1e-3, 1e-4, 1.3e-3, 2e-3));
  EXPECT_NO_THROW(make_truncated_normal(5e-4, 0.0, 1e-4, 1e-3));
}

TEST(SizeDistribution, InvalidLogNormalThrows) {
  EXPECT_INVALID(make_log_normal(-1e-3, 0.3, 1e-4, 1e-2), "median_diameter_m");
  EXPECT_INVALID(make_log_normal(1e-3, -0.3, 1e-4, 1e-2), "sigma_ln");
  EXPECT_INVALID(make_log_normal(1e-3, std::numeric_limits<double>::infinity(), 1e-4, 1e-2),
                 "sigma_ln");
  EXPECT_INVALID(make_log_normal(1e-3, 0.3, 1e-2, 1e-4), "min_diameter_m (0.01)");
  EXPECT_INVALID(make_log_normal(1e-3, 0.3, -1e-4, 1e-2), "min_diameter_m");
  EXPECT_INVALID(make_log_normal(1e-3, 0.1, 3e-3, 1e-2), "at least 0.001");
  EXPECT_INVALID(make_log_normal(1e-3, 0.0, 3e-3, 1e-2), "median_diameter_m");
}

TEST(SizeDistribution, InvalidSieveCurveThrows) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_INVALID(make_sieve_curve({}), "at least 2 rows");
  EXPECT_INVALID(make_sieve_curve({{1e-3, 0.0}}), "at least 2 rows");
  EXPECT_INVALID(make_sieve_curve({{0.0, 0.0}, {1e-3, 1.0}}),
                 "opening_m_and_fraction_passing[0]: the sieve opening");
  EXPECT_INVALID(make_sieve_curve({{1e-3, 0.0}, {nan, 1.0}}),
                 "opening_m_and_fraction_passing[1]: the sieve opening");
  EXPECT_INVALID(make_sieve_curve({{1e-3, 0.0}, {2e-3, 0.5}, {1.5e-3, 1.0}}),
                 "opening_m_and_fraction_passing[2]: the sieve opening (0.0015) must be larger");
  EXPECT_INVALID(make_sieve_curve({{1e-3, 0.0}, {2e-3, 0.5}, {2e-3, 1.0}}),
                 "opening_m_and_fraction_passing[2]: the sieve opening");
  EXPECT_INVALID(make_sieve_curve({{1e-3, 0.0}, {2e-3, 0.6}, {3e-3, 0.5}, {4e-3, 1.0}}),
                 "opening_m_and_fraction_passing[2]: the fraction passing (0.5) must not be less");
  EXPECT_INVALID(make_sieve_curve({{1e-3, 0.0}, {2e-3, 1.5}, {3e-3, 1.0}}),
                 "opening_m_and_fraction_passing[1]: the fraction passing (1.5) must lie in [0, 1]");
  EXPECT_INVALID(make_sieve_curve({{1e-3, -0.1}, {2e-3, 1.0}}),
                 "opening_m_and_fraction_passing[0]: the fraction passing");
  EXPECT_INVALID(make_sieve_curve({{1e-3, nan}, {2e-3, 1.0}}),
                 "opening_m_and_fraction_passing[0]: the fraction passing");
  EXPECT_INVALID(make_sieve_curve({{1e-3, 0.1}, {2e-3, 1.0}}),
                 "opening_m_and_fraction_passing[0]: the fraction passing the finest sieve must be 0");
  EXPECT_INVALID(make_sieve_curve({{1e-3, 0.0}, {2e-3, 0.5}, {3e-3, 0.9}}),
                 "opening_m_and_fraction_passing[2]: the fraction passing the coarsest sieve must be 1");
}

}  // namespace
}  // namespace demcal::dem
