#include "surrogate/latin_hypercube_design.hpp"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>

namespace demcal::surrogate {
namespace {

using Matrix = std::vector<std::vector<double>>;

struct RngDeleter {
  void operator()(gsl_rng* r) const { gsl_rng_free(r); }
};
using Rng = std::unique_ptr<gsl_rng, RngDeleter>;

Rng make_rng(std::uint64_t seed) {
  Rng r(gsl_rng_alloc(gsl_rng_mt19937));
  if (!r) throw std::runtime_error("latin hypercube: cannot allocate a GSL random number generator");
  // GSL seeds take an unsigned long; MT19937 uses its low 32 bits.
  gsl_rng_set(r.get(), static_cast<unsigned long>(seed));
  return r;
}

double squared_distance(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double d = a[k] - b[k];
    s += d * d;
  }
  return s;
}

// The maximin objective: the smallest squared distance, and, as a tie-break,
// how crowded the design is near it: sum over pairs of (min / d^2)^25, that is
// Morris–Mitchell's phi_50 scaled by the minimum so it cannot overflow.
struct Score {
  double min_d2 = 0.0;
  double crowding = 0.0;
  bool better_than(const Score& o) const {
    return min_d2 > o.min_d2 || (min_d2 == o.min_d2 && crowding < o.crowding);
  }
};

Score score(const Matrix& d2) {
  const std::size_t n = d2.size();
  Score s;
  s.min_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) s.min_d2 = std::min(s.min_d2, d2[i][j]);
  if (!(s.min_d2 > 0.0) || !std::isfinite(s.min_d2)) {
    s.crowding = 0.0;
    return s;
  }
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double x = s.min_d2 / d2[i][j];
      const double x2 = x * x, x4 = x2 * x2, x8 = x4 * x4, x16 = x8 * x8;
      s.crowding += x16 * x8 * x;  // x^25
    }
  return s;
}

// The same score straight from the points, without an n x n matrix.
Score score_points(const Matrix& points) {
  const std::size_t n = points.size();
  Score s;
  s.min_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      s.min_d2 = std::min(s.min_d2, squared_distance(points[i], points[j]));
  if (!(s.min_d2 > 0.0) || !std::isfinite(s.min_d2)) return s;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double x = s.min_d2 / squared_distance(points[i], points[j]);
      const double x2 = x * x, x4 = x2 * x2, x8 = x4 * x4, x16 = x8 * x8;
      s.crowding += x16 * x8 * x;
    }
  return s;
}

// How many candidates and swaps fit a fixed budget of pair evaluations, so a
// large design costs seconds, not hours; a function of the sizes only, so the
// design stays a function of (points, dimensions, options).
constexpr double kPairBudget = 5e7;
constexpr std::size_t kMaxSwapPoints = 2000;  // the swap search keeps an n x n matrix

std::size_t within_budget(std::size_t wanted, double cost_each) {
  const double fits = std::floor(kPairBudget / std::max(cost_each, 1.0));
  return static_cast<std::size_t>(std::min(static_cast<double>(wanted), std::max(fits, 1.0)));
}

Matrix distance_matrix(const Matrix& points) {
  const std::size_t n = points.size();
  Matrix d2(n, std::vector<double>(n, 0.0));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) d2[i][j] = d2[j][i] = squared_distance(points[i], points[j]);
  return d2;
}

void update_row(Matrix& d2, const Matrix& points, std::size_t a) {
  for (std::size_t j = 0; j < points.size(); ++j)
    if (j != a) d2[a][j] = d2[j][a] = squared_distance(points[a], points[j]);
}

Matrix random_latin_hypercube(std::size_t n, std::size_t dims, bool centred, gsl_rng* rng) {
  Matrix points(n, std::vector<double>(dims));
  std::vector<std::size_t> strata(n);
  for (std::size_t k = 0; k < dims; ++k) {
    std::iota(strata.begin(), strata.end(), std::size_t{0});
    gsl_ran_shuffle(rng, strata.data(), n, sizeof(std::size_t));
    for (std::size_t i = 0; i < n; ++i) {
      const double offset = centred ? 0.5 : gsl_rng_uniform(rng);  // in [0, 1)
      points[i][k] = (static_cast<double>(strata[i]) + offset) / static_cast<double>(n);
    }
  }
  return points;
}

}  // namespace

void check_ranges(const std::vector<ParameterRange>& ranges, const char* design_name) {
  if (ranges.empty()) throw std::invalid_argument(std::string(design_name) + ": no parameters");
  for (const auto& r : ranges)
    if (!(r.upper > r.lower) || !std::isfinite(r.lower) || !std::isfinite(r.upper))
      throw std::invalid_argument("parameter '" + r.name + "': upper must exceed lower");
}

std::vector<std::vector<double>> latin_hypercube_unit(std::size_t dimensions,
                                                      const LatinHypercubeOptions& options) {
  const std::size_t n = options.points;
  if (n == 0) throw std::invalid_argument("latin hypercube: points must be >= 1");
  if (dimensions == 0) throw std::invalid_argument("latin hypercube: no parameters");
  if (options.candidates == 0) throw std::invalid_argument("latin hypercube: candidates must be >= 1");
  Rng rng = make_rng(options.seed);

  const double pairs = 0.5 * static_cast<double>(n) * static_cast<double>(n - 1);
  const std::size_t candidates =
      within_budget(options.candidates, pairs * static_cast<double>(dimensions));
  const std::size_t swaps = n > kMaxSwapPoints ? 0 : within_budget(options.swap_iterations, pairs);
  Matrix best;
  Score best_score;
  for (std::size_t c = 0; c < candidates; ++c) {
    Matrix candidate = random_latin_hypercube(n, dimensions, options.centred, rng.get());
    const Score s = score_points(candidate);
    if (c == 0 || s.better_than(best_score)) {
      best = std::move(candidate);
      best_score = s;
    }
  }
  if (n < 2 || swaps == 0) return best;

  // Swaps keep one point per stratum in every parameter.
  Matrix d2 = distance_matrix(best);
  for (std::size_t it = 0; it < swaps; ++it) {
    const std::size_t k = gsl_rng_uniform_int(rng.get(), static_cast<unsigned long>(dimensions));
    const std::size_t a = gsl_rng_uniform_int(rng.get(), static_cast<unsigned long>(n));
    std::size_t b = gsl_rng_uniform_int(rng.get(), static_cast<unsigned long>(n - 1));
    if (b >= a) ++b;
    std::swap(best[a][k], best[b][k]);
    const std::vector<double> row_a = d2[a], row_b = d2[b];
    update_row(d2, best, a);
    update_row(d2, best, b);
    const Score s = score(d2);
    if (s.better_than(best_score)) {
      best_score = s;
      continue;
    }
    std::swap(best[a][k], best[b][k]);  // undo
    for (std::size_t j = 0; j < n; ++j) {
      d2[a][j] = d2[j][a] = row_a[j];
      d2[b][j] = d2[j][b] = row_b[j];
    }
    d2[a][b] = d2[b][a] = row_a[b];
  }
  return best;
}

std::vector<std::vector<double>> latin_hypercube_design(const std::vector<ParameterRange>& ranges,
                                                        const LatinHypercubeOptions& options) {
  check_ranges(ranges, "latin hypercube");
  return scale_to_ranges(latin_hypercube_unit(ranges.size(), options), ranges);
}

double min_pairwise_distance(const std::vector<std::vector<double>>& points) {
  double m = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = i + 1; j < points.size(); ++j)
      m = std::min(m, squared_distance(points[i], points[j]));
  return std::sqrt(m);
}

std::vector<std::vector<double>> scale_to_ranges(const std::vector<std::vector<double>>& unit,
                                                 const std::vector<ParameterRange>& ranges) {
  std::vector<std::vector<double>> out = unit;
  for (auto& row : out)
    for (std::size_t k = 0; k < row.size() && k < ranges.size(); ++k)
      row[k] = ranges[k].lower + (ranges[k].upper - ranges[k].lower) * row[k];
  return out;
}

std::vector<std::vector<double>> scale_to_unit(const std::vector<std::vector<double>>& points,
                                               const std::vector<ParameterRange>& ranges) {
  std::vector<std::vector<double>> out = points;
  for (auto& row : out)
    for (std::size_t k = 0; k < row.size() && k < ranges.size(); ++k)
      row[k] = (row[k] - ranges[k].lower) / (ranges[k].upper - ranges[k].lower);
  return out;
}

}  // namespace demcal::surrogate
