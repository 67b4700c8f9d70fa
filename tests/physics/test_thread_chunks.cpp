// The thread team's chunks (dem/thread_team.hpp): a run is cut into threads x
// chunks_per_thread pieces that any thread may claim. Every chunk must run
// exactly once per run whichever thread takes it, so that a run with more
// chunks than threads repeats bit for bit at its thread count and differs from
// the one-thread run only by the order of summation.
#include "frictional_bed.hpp"

#include "dem/thread_team.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <iostream>
#include <vector>

namespace demcal::dem {
namespace {

TEST(ThreadChunks, EveryChunkRunsOncePerRun) {
  EXPECT_EQ(ThreadTeam(1, 8).chunks(), 1) << "a team of one has one chunk";
  EXPECT_THROW(ThreadTeam(2, 0), std::invalid_argument);
  EXPECT_THROW(ThreadTeam(2, 65), std::invalid_argument);
  for (int per_member : {1, 3, 8}) {
    ThreadTeam team(2, per_member);
    ASSERT_EQ(team.chunks(), 2 * per_member);
    std::vector<std::atomic<int>> calls(static_cast<std::size_t>(team.chunks()));
    for (int run = 0; run < 2000; ++run)
      team.run([&](int c) { calls.at(static_cast<std::size_t>(c)).fetch_add(1); });
    for (std::size_t c = 0; c < calls.size(); ++c)
      EXPECT_EQ(calls[c].load(), 2000) << "chunk " << c << " of " << per_member << " per member";
  }
}

TEST(ThreadChunks, ManyChunksRepeatBitForBitAndFollowOneThread) {
  using testing::by_id;
  using testing::frictional_bed;
  auto one = frictional_bed(ParticleOrder::kSpatial, 1);
  auto a = frictional_bed(ParticleOrder::kSpatial, 2, 4);
  auto b = frictional_bed(ParticleOrder::kSpatial, 2, 4);
  double worst_x = 0.0, worst_v = 0.0;
  std::size_t contacts = 0;
  for (int k = 0; k < 20; ++k) {
    one->run_steps(100);
    a->run_steps(100);
    b->run_steps(100);
    const testing::ById s1 = by_id(one->particles()), sa = by_id(a->particles());
    for (std::size_t i = 0; i < s1.position.size(); ++i) {
      worst_x = std::max(worst_x, norm(s1.position[i] - sa.position[i]));
      worst_v = std::max(worst_v, norm(s1.velocity[i] - sa.velocity[i]));
    }
    contacts = std::max(contacts, a->contact_count());
    EXPECT_EQ(one->contact_count(), a->contact_count()) << "after " << (k + 1) * 100 << " steps";
  }
  EXPECT_GT(contacts, 200u) << "the bed should be in contact";
  EXPECT_TRUE(testing::bitwise_equal(a->particles(), b->particles()));
  // The same bounds as the particle-order test: round-off of another summation
  // order, far below the bed's scales (speeds ~0.05 m/s).
  EXPECT_LT(worst_x, 1e-11) << "m";
  EXPECT_LT(worst_v, 1e-8) << "m/s";
  std::cout << "8 chunks on 2 threads against 1 thread, largest difference per id over 2000 "
               "steps: x "
            << worst_x << " m, v " << worst_v << " m/s\n";
}

}  // namespace
}  // namespace demcal::dem
