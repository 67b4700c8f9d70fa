// Poured piles of ~2000 spheres: the same seed and thread count repeat bit for
// bit, the slope steepens with sliding and with rolling friction, and a pile
// copied across the periodic axis into a thicker slab (the benchmark's larger
// case) moves as the original does.
#include "dem/apparatus/poured_slab_pile.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <iterator>
#include <numbers>

namespace demcal::dem {
namespace {

// A crude slope: the surface max(z + r) in bins of 1.5 d, lines fitted on each
// side between 15 % and 85 % of the height (the peer tool's rule). The full AoR
// measurement, with its own tests, belongs to the apparatus work.
double mean_slope_deg(const Particles& p, double d) {
  const double bin = 1.5 * d;
  double lo = 1e9, hi = -1e9;
  for (const auto& x : p.position_m) {
    lo = std::min(lo, x.x);
    hi = std::max(hi, x.x);
  }
  const int nb = static_cast<int>(std::ceil((hi - lo) / bin)) + 1;
  std::vector<double> h(nb, 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int b = std::clamp(static_cast<int>((p.position_m[i].x - lo) / bin), 0, nb - 1);
    h[b] = std::max(h[b], p.position_m[i].z + p.radius_m[i]);
  }
  const int peak = static_cast<int>(std::max_element(h.begin(), h.end()) - h.begin());
  const double hmax = h[peak];
  auto fit = [&](int from, int to) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (int b = from; b <= to; ++b) {
      if (h[b] < 0.15 * hmax || h[b] > 0.85 * hmax) continue;
      const double x = b * bin;
      sx += x;
      sy += h[b];
      sxx += x * x;
      sxy += x * h[b];
      ++n;
    }
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    return std::atan(std::abs(slope)) * 180.0 / std::numbers::pi;
  };
  return 0.5 * (fit(0, peak) + fit(peak, nb - 1));
}

PouredSlabPileOptions small_pile(double mu_s, double mu_r) {
  PouredSlabPileOptions o;
  o.particles = 2000;
  o.box_length_m = 0.09;
  o.sliding_friction = mu_s;
  o.rolling_friction = mu_r;
  return o;
}

double pile_slope(double mu_s, double mu_r, std::uint64_t seed) {
  auto o = small_pile(mu_s, mu_r);
  o.seed = seed;
  auto sim = make_poured_slab_pile(o);
  EXPECT_TRUE(run_until_at_rest(*sim, 2e-3, 2.0)) << "pile did not come to rest";
  const double slope = mean_slope_deg(sim->particles(), 1e-3);
  std::cout << "mu_s " << mu_s << " mu_r " << mu_r << " seed " << seed << ": slope " << slope
            << " deg\n";
  return slope;
}

// The mean slope of one friction pair's piles over six seeds.
double mean_pile_slope(double mu_s, double mu_r) {
  double sum = 0.0;
  const std::uint64_t seeds[] = {4767, 1, 2, 3, 4, 5};
  for (std::uint64_t seed : seeds) sum += pile_slope(mu_s, mu_r, seed);
  return sum / static_cast<double>(std::size(seeds));
}

// One pile's slope is chaotic in its seed, and a change of the engine's rounding acts as a
// new seed, so the comparison is between means over six seeds with margins set by their
// scatter. Measured 2026-12-05, seeds 4767 and 1-5, as built and with the contact normal
// computed as d * (1 / |d|) (a one-ulp change, i.e. another six random streams); mean
// (sd of one pile) in degrees:
//   base (0.15, 0.1): 11.4 (1.5) and 13.0 (3.0); more sliding (0.6, 0.1): 21.8 (1.1) and
//   21.5 (1.1); more rolling at that sliding friction (0.6, 0.4): 24.0 (0.7) and 23.8 (1.0).
// Sliding - base: 10.3 and 8.6 (se about 1) against a margin of 4; rolling - sliding: 2.3
// both times (se 0.5) against a margin of 1, missed by a new set of seeds with a
// probability of about 1 %. Rolling friction is compared where grains do not slide: at
// mu_s = 0.15 (until then, one seed each) raising mu_r to 0.4 gave +4.8 and +0.1 degrees on
// the two sets, within one pile's scatter of 3-4 degrees.
TEST(PouredPile, SteeperWithMoreSlidingAndMoreRollingFriction) {
  const double base = mean_pile_slope(0.15, 0.1);
  const double more_sliding = mean_pile_slope(0.6, 0.1);
  const double more_rolling = mean_pile_slope(0.6, 0.4);
  EXPECT_GT(base, 5.0);
  EXPECT_GT(more_sliding, base + 4.0);
  EXPECT_GT(more_rolling, more_sliding + 1.0);
}

std::vector<Vec3> pour_positions(int threads) {
  auto o = small_pile(0.5, 0.1);
  o.particles = 400;
  o.threads = threads;
  auto sim = make_poured_slab_pile(o);
  sim->run_until(0.15);
  return sim->particles().position_m;
}

bool bitwise_equal(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z) return false;
  return true;
}

TEST(Determinism, SameSeedAndThreadCountRepeatBitForBit) {
  for (int threads : {1, 2}) {
    const auto first = pour_positions(threads);
    const auto second = pour_positions(threads);
    ASSERT_GT(first.size(), 300u);
    EXPECT_TRUE(bitwise_equal(first, second)) << threads << " threads";
  }
}

// The box without grains (particles = 0) is the benchmark's way to build its
// larger case: the same grains copied `tiles` times across the periodic slab.
// Each copy must then move exactly as the single slab does (its neighbours
// across the boundary are the next copy instead of an image of itself), up
// to the round-off of another summation order.
TEST(PouredPile, CopiesAcrossThePeriodicAxisMoveAsTheOriginal) {
  auto o = small_pile(0.5, 0.1);
  o.particles = 400;
  auto poured = make_poured_slab_pile(o);
  poured->run_until(0.15);
  const Particles& p = poured->particles();
  ASSERT_GT(p.size(), 300u);
  const double slab = o.slab_thickness_diameters * o.diameter_m;
  PouredSlabPileOptions empty = o;
  empty.particles = 0;
  EXPECT_EQ(make_poured_slab_pile(empty)->particles().size(), 0u);
  auto single = copy_across_slab(o, p, 1);
  EXPECT_EQ(single->walls().size(), 3u);
  auto tiled = copy_across_slab(o, p, 3);
  EXPECT_EQ(tiled->walls().size(), 3u);
  single->run_steps(2000);
  tiled->run_steps(2000);
  const std::size_t n = p.size();
  ASSERT_EQ(tiled->particles().size(), 3 * n);
  EXPECT_EQ(tiled->contact_count(), 3 * single->contact_count());
  double worst = 0.0, moved = 0.0;
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t i = 0; i < n; ++i) {
      Vec3 d = tiled->particles().position_m[k * n + i] - single->particles().position_m[i];
      d.y -= slab * std::round(d.y / slab);  // the copy's offset, and a wrap in one run only
      worst = std::max(worst, norm(d));
      moved = std::max(moved, norm(single->particles().position_m[i] - p.position_m[i]));
    }
  // Grains move by millimetres in 2000 steps (still pouring); copies agree to
  // round-off (4e-15 m when written; copies 0.1 % too close: 1e-4 m).
  EXPECT_GT(moved, 1e-4) << "m";
  EXPECT_LT(worst, 1e-9) << "m";
  std::cout << "3 copies of " << n << " grains, 2000 steps: largest difference " << worst
            << " m, largest move " << moved << " m\n";
}

}  // namespace
}  // namespace demcal::dem
