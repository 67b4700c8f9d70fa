// The pair loop's contact test (dem/pair_scan.hpp) against the loop it
// replaced in the force loop (dem/simulation.cpp at 5fac680): the same pairs
// taken in the same order with the same "touched before" flags, the same
// touching flags left in the list, and a scan cut by full batches that
// resumes exactly where it stopped.
#include "dem/pair_scan.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <tuple>
#include <vector>

namespace demcal::dem {
namespace {

// A neighbour list over random particles: partners j > i with random image
// codes, each placed to overlap i about half the time (a later pair may move
// it again), and particles without pairs.
struct RandomList {
  std::vector<Vec3> x;
  std::vector<double> r;
  std::vector<std::uint32_t> first{0}, partner;
  std::vector<std::uint8_t> code, touching;
  std::vector<Vec3> shift_table;
  std::vector<ContactHistory> history;

  NeighborList::Arrays arrays() {
    return {first.data(),       partner.data(), code.data(),
            shift_table.data(), history.data(), touching.data()};
  }
};

RandomList random_list(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  RandomList l;
  const Vec3 length{0.02, 0.013, 0.05};
  for (int oz = -1; oz <= 1; ++oz)
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox)
        l.shift_table.push_back(Vec3{ox * length.x, oy * length.y, oz * length.z});
  for (std::size_t i = 0; i < n; ++i) {
    l.x.push_back(Vec3{length.x * u(rng), length.y * u(rng), length.z * u(rng)});
    l.r.push_back(1e-3 * (0.5 + 0.5 * u(rng)));
  }
  for (std::size_t i = 0; i < n; ++i) {
    // Every seventh particle lists no pair; the others up to 9.
    const int pairs = i % 7 == 3 || i + 1 == n ? 0 : static_cast<int>(10 * u(rng));
    for (int k = 0; k < pairs; ++k) {
      const auto j =
          static_cast<std::uint32_t>(i + 1 + static_cast<std::size_t>(u(rng) * (n - i - 1)));
      const auto c = static_cast<std::uint8_t>(27 * u(rng));
      // Put j at a distance from i (through its image) that overlaps about
      // half the time: r_i + r_j times 0.8 to 1.2 along a random direction.
      const double rsum = l.r[i] + l.r[j];
      const double dist = rsum * (0.8 + 0.4 * u(rng));
      const double cz = 2.0 * u(rng) - 1.0, phi = 6.283185307179586 * u(rng);
      const double s = std::sqrt(1.0 - cz * cz);
      const Vec3 dir{s * std::cos(phi), s * std::sin(phi), cz};
      l.x[j] = l.x[i] - dist * dir - l.shift_table[c];
      l.partner.push_back(j);
      l.code.push_back(c);
      l.touching.push_back(u(rng) < 0.5 ? 1 : 0);
    }
    l.first.push_back(static_cast<std::uint32_t>(l.partner.size()));
  }
  l.history.resize(l.partner.size());
  return l;
}

using Taken = std::tuple<std::uint32_t, std::uint32_t, bool>;  // i, pair, touched before

// The loop of 5fac680, one pair at a time.
std::vector<Taken> reference_scan(RandomList& l, std::size_t begin, std::size_t end) {
  std::vector<Taken> taken;
  for (std::size_t i = begin; i < end; ++i) {
    for (std::uint32_t p = l.first[i]; p < l.first[i + 1]; ++p) {
      const std::uint32_t j = l.partner[p];
      const Vec3 d = l.x[i] - (l.x[j] + l.shift_table[l.code[p]]);
      const double rsum = l.r[i] + l.r[j];
      const bool on = !(norm2(d) >= rsum * rsum);
      if (on) taken.emplace_back(static_cast<std::uint32_t>(i), p, l.touching[p] != 0);
      l.touching[p] = on ? 1 : 0;
    }
  }
  return taken;
}

// The scan as the force loop drives it: batch after batch until the pairs
// run out, with or without the prefetches. Also returns the size of every
// batch it handed over.
std::vector<Taken> scan_in_batches(RandomList& l, std::size_t begin, std::size_t end, bool prefetch,
                                   std::vector<int>* batch_sizes) {
  std::vector<Taken> taken;
  ContactBatch batch;
  batch.size = 0;
  PairScanCursor cursor{begin, begin < end ? l.first[begin] : 0};
  const NeighborList::Arrays a = l.arrays();
  // The partners' force entries the scan prefetches; with two "owners" so
  // that both targets are used.
  std::vector<Vec3> force(l.x.size()), torque(l.x.size()), force_b(l.x.size()),
      torque_b(l.x.size());
  const PartnerForceTargets targets{force.data(), torque.data(), force_b.data(), torque_b.data(),
                                    (begin + end) / 2};
  for (;;) {
    stage_touching_pairs(a, l.x.data(), l.r.data(), end, cursor, batch,
                         prefetch ? &targets : nullptr);
    batch_sizes->push_back(batch.size);
    for (int s = 0; s < batch.size; ++s)
      taken.emplace_back(static_cast<std::uint32_t>(batch.i[s]), batch.pair[s],
                         batch.was_touching[s] != 0);
    if (!batch.full()) break;
    batch.size = 0;
  }
  EXPECT_EQ(cursor.i, end);
  return taken;
}

// Both scans, which must agree in everything (a prefetch changes no value);
// returns the one without prefetches.
std::vector<Taken> batched_scan(RandomList& l, std::size_t begin, std::size_t end,
                                std::vector<int>* batch_sizes) {
  RandomList copy = l;
  std::vector<int> sizes_with;
  const auto with = scan_in_batches(copy, begin, end, true, &sizes_with);
  const std::size_t before = batch_sizes->size();
  const auto without = scan_in_batches(l, begin, end, false, batch_sizes);
  EXPECT_EQ(with, without);
  EXPECT_EQ(copy.touching, l.touching);
  EXPECT_EQ(sizes_with,
            std::vector<int>(batch_sizes->begin() + static_cast<long>(before), batch_sizes->end()));
  return without;
}

TEST(PairScan, TakesTheSamePairsInTheSameOrderAsTheOnePairLoop) {
  RandomList l = random_list(997, 11);
  ASSERT_GT(l.partner.size(), 3u * ContactBatch::kCapacity);
  RandomList ref = l;
  std::vector<int> sizes;
  const auto expected = reference_scan(ref, 0, l.x.size());
  const auto got = batched_scan(l, 0, l.x.size(), &sizes);
  // Several full batches; some pairs overlap and some do not, and of those
  // that do some touched before and some did not.
  ASSERT_GT(expected.size(), 3u * ContactBatch::kCapacity);
  ASSERT_LT(expected.size(), l.partner.size());
  const auto before = std::count_if(expected.begin(), expected.end(),
                                    [](const Taken& t) { return std::get<2>(t); });
  ASSERT_GT(before, 0);
  ASSERT_LT(static_cast<std::size_t>(before), expected.size());
  EXPECT_EQ(got, expected);
  EXPECT_EQ(l.touching, ref.touching);
  // Every batch but the last is full; the last is not.
  for (std::size_t b = 0; b + 1 < sizes.size(); ++b) EXPECT_EQ(sizes[b], ContactBatch::kCapacity);
  EXPECT_LT(sizes.back(), ContactBatch::kCapacity);
}

TEST(PairScan, AChunkScansOnlyItsOwnParticlesAndResumesAcrossFullBatches) {
  // Two chunks as two threads would own them, the boundary at a particle
  // with pairs; each scan must stop at its own end.
  RandomList l = random_list(613, 5);
  RandomList ref = l;
  const std::size_t mid = 300;
  std::vector<int> sizes;
  auto expected = reference_scan(ref, 0, mid);
  const auto second = reference_scan(ref, mid, l.x.size());
  auto got = batched_scan(l, 0, mid, &sizes);
  const auto got_second = batched_scan(l, mid, l.x.size(), &sizes);
  EXPECT_EQ(got, expected);
  EXPECT_EQ(got_second, second);
  EXPECT_EQ(l.touching, ref.touching);
  // An empty range scans nothing.
  std::vector<int> none;
  EXPECT_TRUE(batched_scan(l, mid, mid, &none).empty());
}

TEST(PairScan, ABatchFullOnItsParticlesLastPairResumesAtTheNextParticle) {
  // Particle 0 lists exactly kCapacity overlapping pairs, particle 1 one more.
  const int c = ContactBatch::kCapacity;
  RandomList l;
  l.shift_table.assign(27, Vec3{});
  for (int k = 0; k <= c + 1; ++k) {
    l.x.push_back(Vec3{1e-4 * k, 0.0, 0.0});
    l.r.push_back(1.0);  // everything overlaps everything
  }
  for (int k = 1; k <= c; ++k) l.partner.push_back(static_cast<std::uint32_t>(k));
  l.first.push_back(static_cast<std::uint32_t>(l.partner.size()));
  l.partner.push_back(static_cast<std::uint32_t>(c + 1));
  l.first.push_back(static_cast<std::uint32_t>(l.partner.size()));
  while (l.first.size() < l.x.size() + 1) l.first.push_back(l.first.back());
  l.code.assign(l.partner.size(), 13);
  l.touching.assign(l.partner.size(), 0);
  l.history.resize(l.partner.size());
  std::vector<int> sizes;
  const auto got = batched_scan(l, 0, l.x.size(), &sizes);
  EXPECT_EQ(sizes, (std::vector<int>{c, 1}));
  ASSERT_EQ(got.size(), static_cast<std::size_t>(c + 1));
  EXPECT_EQ(got.back(), (Taken{1u, static_cast<std::uint32_t>(c), false}));
}

TEST(PairScan, ANaNPositionCountsAsAContact) {
  // So that it reaches the stability check through the forces.
  RandomList l = random_list(50, 3);
  std::size_t i = 0;
  while (l.first[i + 1] == l.first[i]) ++i;  // the first particle with a pair
  const std::uint32_t pair = l.first[i];
  l.x[l.partner[pair]].y = std::numeric_limits<double>::quiet_NaN();
  std::vector<int> sizes;
  const auto got = batched_scan(l, i, i + 1, &sizes);
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(std::get<1>(got.front()), pair);
  EXPECT_EQ(l.touching[pair], 1);
}

}  // namespace
}  // namespace demcal::dem
