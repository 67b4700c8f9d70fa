// The rule that parks a thread team's workers, fed with made-up run times:
// it settles on the faster mode, notices a load that comes and goes, costs a
// quiet machine about one probe window in 128, and keeps its fixed modes fixed.
#include "dem/worker_parking.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

namespace demcal::dem {
namespace {

// A run takes `team_s` with the workers working and `parked_s` with them parked.
struct Machine {
  double team_s;
  double parked_s;
};

// Runs `runs` runs on `machine`; returns how many of them were parked.
std::uint64_t run(WorkerParkingPolicy& policy, Machine machine, std::uint64_t runs) {
  std::uint64_t parked = 0;
  for (std::uint64_t r = 0; r < runs; ++r) {
    const bool park = policy.park();
    parked += park ? 1 : 0;
    policy.record(park ? machine.parked_s : machine.team_s);
  }
  return parked;
}

WorkerParkingOptions small_windows() {
  WorkerParkingOptions o;
  o.window_s = 1.0;  // with 0.01 s runs: 100 runs a window
  o.min_runs_per_window = 10;
  return o;
}

TEST(WorkerParkingPolicy, QuietMachineKeepsTheTeamAndProbesRarely) {
  WorkerParkingPolicy policy(WorkerParking::kAdaptive, small_windows());
  const Machine quiet{0.010, 0.018};      // two threads 1.8x faster than one
  const std::uint64_t runs = 100 * 2000;  // 2000 windows
  const std::uint64_t parked = run(policy, quiet, runs);
  EXPECT_FALSE(policy.settled_parked());
  EXPECT_EQ(policy.switches(), 0u);
  // Probes after 8, 16, 32, 64, then every 128 windows: 4 + (2000 - 124) / 129 = 18.
  EXPECT_GE(policy.probes(), 17u);
  EXPECT_LE(policy.probes(), 19u);
  // Each probe window is parked (runs take longer, so fewer runs fill it).
  EXPECT_LT(static_cast<double>(parked) / static_cast<double>(runs), 0.006);
}

TEST(WorkerParkingPolicy, ParksUnderLoadAndWakesWhenTheLoadGoes) {
  WorkerParkingPolicy policy(WorkerParking::kAdaptive, small_windows());
  run(policy, {0.010, 0.018}, 100 * 10);
  EXPECT_FALSE(policy.settled_parked());
  // Another process takes a core: the team is now slower than the caller alone.
  const Machine loaded{0.025, 0.019};
  run(policy, loaded, 100 * 100);
  EXPECT_TRUE(policy.settled_parked());
  EXPECT_EQ(policy.switches(), 1u);
  // Once parked, most runs are parked.
  const std::uint64_t parked = run(policy, loaded, 100 * 1000);
  EXPECT_GT(static_cast<double>(parked) / (100.0 * 1000.0), 0.95);
  EXPECT_EQ(policy.switches(), 1u);
  // The load goes: within the longest probe interval (128 windows of 56 parked
  // runs) and its probe, the team works again.
  run(policy, {0.010, 0.018}, 56 * 130 + 100);
  EXPECT_FALSE(policy.settled_parked());
  EXPECT_EQ(policy.switches(), 2u);
}

TEST(WorkerParkingPolicy, AGainInsideTheMarginDoesNotSwitch) {
  WorkerParkingPolicy policy(WorkerParking::kAdaptive, small_windows());  // margin 5 %
  run(policy, {0.0100, 0.0097}, 100 * 500);  // parked 3 % faster: not worth a switch
  EXPECT_FALSE(policy.settled_parked());
  EXPECT_EQ(policy.switches(), 0u);
  EXPECT_GT(policy.probes(), 5u);
}

TEST(WorkerParkingPolicy, FixedModesNeverChange) {
  WorkerParkingPolicy never(WorkerParking::kNever, small_windows());
  EXPECT_EQ(run(never, {0.030, 0.010}, 100 * 200), 0u);
  EXPECT_EQ(never.probes(), 0u);
  WorkerParkingPolicy always(WorkerParking::kAlways, small_windows());
  EXPECT_EQ(run(always, {0.010, 0.030}, 100 * 200), 100u * 200u);
  EXPECT_EQ(always.probes(), 0u);
}

TEST(WorkerParkingPolicy, NonsenseTimesDoNotSteerIt) {
  WorkerParkingPolicy policy(WorkerParking::kAdaptive, small_windows());
  run(policy, {0.010, 0.018}, 100 * 10);
  for (int r = 0; r < 100000; ++r) policy.record(-1.0);  // a clock that went backwards
  for (int r = 0; r < 1000; ++r) policy.record(std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(policy.settled_parked());
  run(policy, {0.010, 0.018}, 100 * 200);
  EXPECT_FALSE(policy.settled_parked());
}

TEST(WorkerParkingPolicy, NamesAndBadOptionsFailReadably) {
  for (const auto& name : worker_parking_names())
    EXPECT_EQ(worker_parking_name(parse_worker_parking(name)), name);
  try {
    parse_worker_parking("sometimes");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("\"adaptive\""), std::string::npos) << e.what();
  }
  WorkerParkingOptions bad;
  bad.window_s = 0.0;
  EXPECT_THROW(WorkerParkingPolicy(WorkerParking::kAdaptive, bad), std::invalid_argument);
  bad = {};
  bad.switch_margin = 1.0;
  EXPECT_THROW(WorkerParkingPolicy(WorkerParking::kAdaptive, bad), std::invalid_argument);
  bad = {};
  bad.first_probe_interval_windows = 8;
  bad.max_probe_interval_windows = 4;
  EXPECT_THROW(WorkerParkingPolicy(WorkerParking::kAdaptive, bad), std::invalid_argument);
}

}  // namespace
}  // namespace demcal::dem
