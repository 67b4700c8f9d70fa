// The Verlet list against brute force: every pair closer than the skin, and no
// other, in a polydisperse bed (radius ratio 2.5) with a periodic axis.
#include "dem/neighbor_list.hpp"
#include "dem/random.hpp"

#include <gtest/gtest.h>

#include <cmath>
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

}  // namespace
}  // namespace demcal::dem
