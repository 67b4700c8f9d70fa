// The Verlet list against brute force: every pair closer than the skin, and no
// other, in a polydisperse bed (radius ratio 2.5) with a periodic axis.
#include "dem/neighbor_list.hpp"
#include "dem/random.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>

namespace demcal::dem {
namespace {

TEST(NeighborList, MatchesBruteForceInAPolydispersePeriodicBed) {
  Domain dom;
  dom.lower_m = {0, 0, 0};
  dom.upper_m = {0.02, 0.012, 0.03};
  dom.periodic = {true, true, false};
  Random rng(11);
  std::vector<Vec3> pos;
  std::vector<double> rad;
  for (int i = 0; i < 1500; ++i) {
    rad.push_back(rng.uniform(0.2e-3, 0.5e-3));
    pos.push_back({rng.uniform(0, 0.02), rng.uniform(0, 0.012), rng.uniform(0, 0.03)});
  }
  const double skin = 0.15e-3;
  NeighborList list;
  list.build(pos, rad, dom, skin);

  std::set<std::pair<std::uint32_t, std::uint32_t>> found;
  for (std::size_t i = 0; i < pos.size(); ++i)
    for (std::uint32_t p = list.first(i); p < list.first(i + 1); ++p) {
      const std::uint32_t j = list.partner(p);
      EXPECT_LT(i, j);
      // The stored image must be the one that brings j near i.
      const double gap = norm(pos[i] - (pos[j] + list.image_shift(p))) - rad[i] - rad[j];
      EXPECT_LT(gap, skin);
      found.insert({static_cast<std::uint32_t>(i), j});
    }
  std::size_t expected = 0;
  const Vec3 len = dom.length_m();
  for (std::size_t i = 0; i < pos.size(); ++i)
    for (std::size_t j = i + 1; j < pos.size(); ++j) {
      Vec3 d = pos[i] - pos[j];
      for (int k = 0; k < 2; ++k) d[k] -= len[k] * std::round(d[k] / len[k]);
      if (norm(d) - rad[i] - rad[j] < skin) {
        ++expected;
        EXPECT_TRUE(found.count({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)}))
            << "missing pair " << i << " " << j;
      }
    }
  EXPECT_EQ(found.size(), expected);
  EXPECT_EQ(list.pair_count(), expected);
  EXPECT_GT(expected, 100u);
}

TEST(NeighborList, AsksForARebuildOnceAParticleMovedHalfTheSkin) {
  Domain dom;
  dom.upper_m = {0.01, 0.01, 0.01};
  std::vector<Vec3> pos = {{0.002, 0.005, 0.005}, {0.004, 0.005, 0.005}};
  std::vector<double> rad = {0.5e-3, 0.5e-3};
  NeighborList list;
  list.build(pos, rad, dom, 0.2e-3);
  pos[0].x += 0.099e-3;
  EXPECT_FALSE(list.needs_rebuild(pos));
  pos[0].x += 0.002e-3;
  EXPECT_TRUE(list.needs_rebuild(pos));
}

TEST(NeighborList, CarriesTheHistoryOfTouchingPairsAcrossRebuilds) {
  Domain dom;
  dom.upper_m = {0.01, 0.01, 0.01};
  std::vector<Vec3> pos = {{0.004, 0.005, 0.005}, {0.00499, 0.005, 0.005}, {0.008, 0.005, 0.005}};
  std::vector<double> rad = {0.5e-3, 0.5e-3, 0.5e-3};
  NeighborList list;
  list.build(pos, rad, dom, 0.2e-3);
  ASSERT_EQ(list.pair_count(), 1u);
  list.touching(0) = 1;
  list.history(0).tangential_displacement_m = {0, 1e-6, 0};
  pos[2].x = 0.0059;  // a new neighbour for particle 1
  list.build(pos, rad, dom, 0.2e-3);
  ASSERT_EQ(list.pair_count(), 2u);
  EXPECT_EQ(list.partner(0), 1u);
  EXPECT_EQ(list.touching(0), 1);
  EXPECT_DOUBLE_EQ(list.history(0).tangential_displacement_m.y, 1e-6);
  EXPECT_EQ(list.touching(1), 0);
}

// A build and a renumber write into arrays kept from the list before last
// (issue 13: no allocation per build). Nothing of that older list may show:
// a pair that parted is not touching after later builds, and a list built
// again and again equals a list built once from the same positions.
TEST(NeighborList, RepeatedBuildsCarryNothingStale) {
  Domain dom;
  dom.upper_m = {0.02, 0.02, 0.02};
  dom.periodic = {true, false, false};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> pos(400);
  std::vector<double> rad(pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i) {
    pos[i] = {0.02 * u(rng), 0.02 * u(rng), 0.02 * u(rng)};
    rad[i] = 0.4e-3 + 0.3e-3 * u(rng);
  }
  NeighborList list;
  list.build(pos, rad, dom, 0.3e-3);
  for (std::size_t p = 0; p < list.pair_count(); ++p) {
    list.touching(p) = p % 2 == 0 ? 1 : 0;
    list.history(p).tangential_displacement_m = {1.0 + static_cast<double>(p), 0.0, 0.0};
  }
  std::vector<std::uint32_t> reversed(pos.size());
  for (std::size_t k = 0; k < 6; ++k) {
    for (auto& x : pos) x.z = std::min(0.0199, x.z + 0.05e-3 * u(rng));
    if (k == 2) {
      // Rename the particles (reversed order), as a spatial reorder does.
      for (std::size_t i = 0; i < pos.size(); ++i)
        reversed[i] = static_cast<std::uint32_t>(pos.size() - 1 - i);
      list.renumber(reversed);
      std::reverse(pos.begin(), pos.end());
      std::reverse(rad.begin(), rad.end());
    }
    list.build(pos, rad, dom, 0.3e-3);
    // Every pair parts now, except a few: their flags must not come back.
    for (std::size_t p = 0; p < list.pair_count(); ++p) list.touching(p) = p % 7 == 0 ? 1 : 0;
  }
  list.build(pos, rad, dom, 0.3e-3);
  NeighborList fresh;
  fresh.build(pos, rad, dom, 0.3e-3);
  ASSERT_EQ(list.pair_count(), fresh.pair_count());
  std::size_t touching = 0;
  for (std::size_t i = 0; i <= pos.size(); ++i) ASSERT_EQ(list.first(i), fresh.first(i)) << i;
  for (std::size_t p = 0; p < list.pair_count(); ++p) {
    ASSERT_EQ(list.partner(p), fresh.partner(p)) << p;
    ASSERT_EQ(list.image_shift(p).x, fresh.image_shift(p).x) << p;
    touching += list.touching(p);
  }
  // The last build saw the positions of the one before: the same pairs, and
  // exactly those flagged after it still touch.
  std::size_t flagged_last = 0;
  for (std::size_t p = 0; p < list.pair_count(); ++p) flagged_last += p % 7 == 0 ? 1 : 0;
  EXPECT_EQ(touching, flagged_last);
  EXPECT_GT(touching, 0u);
}

}  // namespace
}  // namespace demcal::dem
