// Designs of experiments: the maximin Latin hypercube keeps one point per
// stratum and spreads its points further than a random Latin hypercube; the
// Sobol design is GSL's sequence scaled; the full factorial grid is unchanged.
#include "surrogate/design.hpp"
#include "surrogate/full_factorial_design.hpp"
#include "surrogate/latin_hypercube_design.hpp"
#include "surrogate/sobol_design.hpp"

#include <gsl/gsl_qrng.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace demcal::surrogate {
namespace {

using Points = std::vector<std::vector<double>>;

// Every parameter's range in n strata holds exactly one point of each.
void expect_one_point_per_stratum(const Points& unit, std::size_t dims) {
  const std::size_t n = unit.size();
  for (std::size_t k = 0; k < dims; ++k) {
    std::vector<int> hits(n, 0);
    for (const auto& p : unit) {
      ASSERT_GE(p[k], 0.0);
      ASSERT_LT(p[k], 1.0);
      ++hits[static_cast<std::size_t>(std::floor(p[k] * static_cast<double>(n)))];
    }
    for (std::size_t s = 0; s < n; ++s) EXPECT_EQ(hits[s], 1) << "parameter " << k << " stratum " << s;
  }
}

TEST(LatinHypercubeDesign, OnePointPerStratumInEveryParameter) {
  for (std::size_t n : {1u, 2u, 7u, 25u}) {
    LatinHypercubeOptions o;
    o.points = n;
    o.seed = 11;
    const Points unit = latin_hypercube_unit(3, o);
    ASSERT_EQ(unit.size(), n);
    expect_one_point_per_stratum(unit, 3);
  }
  // Scaled to the ranges, the strata are those of each range.
  const std::vector<ParameterRange> ranges = {{"mu_r", 0.05, 0.6, 2}, {"mu_s", 0.2, 0.9, 2}};
  LatinHypercubeOptions o;
  o.points = 10;
  const Points scaled = latin_hypercube_design(ranges, o);
  for (const auto& p : scaled) {
    EXPECT_GE(p[0], 0.05);
    EXPECT_LT(p[0], 0.6);
    EXPECT_GE(p[1], 0.2);
    EXPECT_LT(p[1], 0.9);
  }
  expect_one_point_per_stratum(scale_to_unit(scaled, ranges), 2);
}

TEST(LatinHypercubeDesign, MaximinBeatsRandomLatinHypercubes) {
  LatinHypercubeOptions maximin;
  maximin.points = 20;
  maximin.seed = 1;
  const double optimized = min_pairwise_distance(latin_hypercube_unit(2, maximin));
  // Plain random Latin hypercubes: one candidate, no swaps.
  double best_random = 0.0, sum_random = 0.0;
  constexpr int kRandom = 20;
  for (int s = 1; s <= kRandom; ++s) {
    LatinHypercubeOptions random;
    random.points = 20;
    random.seed = static_cast<std::uint64_t>(100 + s);
    random.candidates = 1;
    random.swap_iterations = 0;
    const Points p = latin_hypercube_unit(2, random);
    expect_one_point_per_stratum(p, 2);
    const double d = min_pairwise_distance(p);
    best_random = std::max(best_random, d);
    sum_random += d;
  }
  EXPECT_GT(optimized, best_random) << "mean random " << sum_random / kRandom;
  EXPECT_GT(optimized, 2.0 * sum_random / kRandom);
  // The swap search improves on the best candidate alone.
  LatinHypercubeOptions no_swaps = maximin;
  no_swaps.swap_iterations = 0;
  EXPECT_GE(optimized, min_pairwise_distance(latin_hypercube_unit(2, no_swaps)));
}

TEST(LatinHypercubeDesign, DeterministicForASeed) {
  LatinHypercubeOptions o;
  o.points = 9;
  o.seed = 5;
  const Points a = latin_hypercube_unit(4, o);
  EXPECT_EQ(a, latin_hypercube_unit(4, o));
  o.seed = 6;
  EXPECT_NE(a, latin_hypercube_unit(4, o));
}

TEST(LatinHypercubeDesign, RefusesEmptyInputs) {
  LatinHypercubeOptions o;
  o.points = 0;
  EXPECT_THROW(latin_hypercube_unit(2, o), std::invalid_argument);
  o.points = 3;
  EXPECT_THROW(latin_hypercube_unit(0, o), std::invalid_argument);
  EXPECT_THROW(latin_hypercube_design({{"mu_r", 0.5, 0.5, 2}}, o), std::invalid_argument);
}

TEST(SobolDesign, MatchesGslsFirstPointsScaledToTheBounds) {
  const std::vector<ParameterRange> ranges = {
      {"a", 0.0, 1.0, 2}, {"b", -1.0, 3.0, 2}, {"c", 10.0, 20.0, 2}};
  const Points p = sobol_design(ranges, 8);
  gsl_qrng* q = gsl_qrng_alloc(gsl_qrng_sobol, 3);
  double v[3];
  for (std::size_t i = 0; i < 8; ++i) {
    gsl_qrng_get(q, v);
    EXPECT_DOUBLE_EQ(p[i][0], v[0]);
    EXPECT_DOUBLE_EQ(p[i][1], -1.0 + 4.0 * v[1]);
    EXPECT_DOUBLE_EQ(p[i][2], 10.0 + 10.0 * v[2]);
  }
  gsl_qrng_free(q);
  // GSL leaves out the zero point: the sequence starts at the centre.
  EXPECT_EQ(p[0][0], 0.5);
  EXPECT_EQ(p[1][0], 0.75);
  EXPECT_EQ(p[2][0], 0.25);
  EXPECT_EQ(p[1][1], -1.0 + 4.0 * 0.25);
  // skip continues the sequence.
  const Points later = sobol_design(ranges, 3, 5);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(later[i], p[5 + i]);
}

TEST(SobolDesign, RefusesWhatGslCannotMake) {
  std::vector<ParameterRange> many(kSobolMaxDimensions + 1, ParameterRange{"x", 0.0, 1.0, 2});
  EXPECT_THROW(sobol_design(many, 4), std::invalid_argument);
  EXPECT_THROW(sobol_design({{"x", 0.0, 1.0, 2}}, 0), std::invalid_argument);
}

TEST(FullFactorialDesign, GridIsUnchanged) {
  const Points p = full_factorial_design({{"mu_r", 0.1, 0.3, 3}, {"mu_s", 0.2, 0.6, 2}});
  const Points expected = {{0.1, 0.2}, {0.1, 0.6}, {0.2, 0.2}, {0.2, 0.6}, {0.3, 0.2}, {0.3, 0.6}};
  ASSERT_EQ(p.size(), expected.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_DOUBLE_EQ(p[i][0], expected[i][0]) << i;
    EXPECT_EQ(p[i][1], expected[i][1]) << i;  // bounds exact
  }
}

TEST(Design, GenerateDispatchesByKind) {
  DesignSpec spec;
  spec.parameters = {{"mu_r", 0.0, 1.0, 3}, {"mu_s", 0.0, 2.0, 2}};
  spec.kind = DesignKind::kFullFactorial;
  EXPECT_EQ(generate_design(spec).points, full_factorial_design(spec.parameters));
  spec.kind = DesignKind::kSobol;
  spec.points = 4;
  spec.skip = 1;
  EXPECT_EQ(generate_design(spec).points, sobol_design(spec.parameters, 4, 1));
  spec.kind = DesignKind::kLatinHypercube;
  spec.seed = 3;
  LatinHypercubeOptions o;
  o.points = 4;
  o.seed = 3;
  EXPECT_EQ(generate_design(spec).points, latin_hypercube_design(spec.parameters, o));
  spec.kind = DesignKind::kList;
  spec.values = {{0.5, 1.5}, {0.0, 2.0}};
  EXPECT_EQ(generate_design(spec).points, spec.values);
  spec.values = {{0.5, 2.5}};
  EXPECT_THROW(generate_design(spec), std::invalid_argument);  // outside mu_s's bounds
  spec.values = {{0.5}};
  EXPECT_THROW(generate_design(spec), std::invalid_argument);  // one value short
  for (const std::string& name : design_kind_names())
    EXPECT_EQ(design_kind_name(*design_kind_from_name(name)), name);
  EXPECT_FALSE(design_kind_from_name("random"));
}

}  // namespace
}  // namespace demcal::surrogate
