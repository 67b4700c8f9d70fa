#pragma once
// Maximin Latin hypercube design: n points in d bounded parameters such that
// each parameter's range, cut into n equal strata, holds exactly one point per
// stratum, spread so that the closest two points (in the unit cube, each range
// scaled to [0, 1]) are as far apart as the search finds.
//
// Search: the best of `candidates` random Latin hypercubes by minimum pairwise
// distance, then `swap_iterations` random swaps (two points exchange their
// coordinate in one parameter, which keeps the Latin property), each kept when
// it raises the minimum distance, or keeps it and lowers the Morris–Mitchell
// criterion phi_p (p = 50, the sum of inverse distances to the p-th power, a
// tie-break that counts the pairs near the minimum). Large designs get fewer
// candidates and swaps (a budget of 5e7 pair distances each, no swaps above
// 2000 points), fixed by the sizes, so a seed still fixes the design. The
// random numbers are GSL's MT19937 seeded with `seed`, so a seed gives the
// same design on every platform (GSL's uniform variate is specified by the
// generator's bits).

#include "surrogate/full_factorial_design.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace demcal::surrogate {

struct LatinHypercubeOptions {
  std::size_t points = 10;           // n >= 1
  std::uint64_t seed = 1;            // GSL MT19937 seed
  std::size_t candidates = 100;      // random hypercubes tried; >= 1
  std::size_t swap_iterations = 2000;  // 0 = best-of-candidates only
  // Each point at its stratum's centre instead of uniformly inside it.
  bool centred = false;
};

// The design in the unit cube: rows are points, columns parameters; each value
// in [0, 1). Throws std::invalid_argument when points, dimensions or candidates is 0.
std::vector<std::vector<double>> latin_hypercube_unit(std::size_t dimensions,
                                                      const LatinHypercubeOptions& options);

// The unit design scaled to `ranges` (ParameterRange::levels is not used).
// Throws std::invalid_argument naming the parameter when a range is empty.
std::vector<std::vector<double>> latin_hypercube_design(const std::vector<ParameterRange>& ranges,
                                                        const LatinHypercubeOptions& options);

// The smallest Euclidean distance between two rows (infinity for fewer than 2).
double min_pairwise_distance(const std::vector<std::vector<double>>& points);

// Row values mapped from the unit cube to `ranges`, and back.
std::vector<std::vector<double>> scale_to_ranges(const std::vector<std::vector<double>>& unit,
                                                 const std::vector<ParameterRange>& ranges);
std::vector<std::vector<double>> scale_to_unit(const std::vector<std::vector<double>>& points,
                                               const std::vector<ParameterRange>& ranges);

// Throws std::invalid_argument naming the parameter unless lower < upper, both finite.
void check_ranges(const std::vector<ParameterRange>& ranges, const char* design_name);

}  // namespace demcal::surrogate
