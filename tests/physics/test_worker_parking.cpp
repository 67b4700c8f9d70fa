// Parking a thread team's workers moves chunks between threads and nothing
// else: a 2-thread pour gives the same positions bit for bit whether the
// workers always work, never work, or are parked and woken hundreds of times
// during the run by a rule fed with real (hence irreproducible) wall times.
#include "dem/apparatus/poured_slab_pile.hpp"

#include <gtest/gtest.h>

namespace demcal::dem {
namespace {

struct PourResult {
  std::vector<Vec3> position_m;
  std::vector<Vec3> omega_rad_s;
  std::uint64_t probes = 0;
  std::uint64_t switches = 0;
};

PourResult pour(WorkerParking parking, WorkerParkingOptions parking_options = {}) {
  PouredSlabPileOptions o;
  o.particles = 400;
  o.box_length_m = 0.09;
  o.sliding_friction = 0.5;
  o.rolling_friction = 0.1;
  o.threads = 2;
  o.particle_order = ParticleOrder::kSpatial;
  o.worker_parking = parking;
  o.worker_parking_options = parking_options;
  auto sim = make_poured_slab_pile(o);
  sim->run_until(0.15);
  return {sim->particles().position_m, sim->particles().omega_rad_s,
          sim->worker_parking()->probes(), sim->worker_parking()->switches()};
}

void expect_bitwise_equal(const std::vector<Vec3>& a, const std::vector<Vec3>& b,
                          const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z) ++differ;
  EXPECT_EQ(differ, 0u) << what << ": " << differ << " of " << a.size() << " particles differ";
}

TEST(WorkerParking, ParkedWorkersChangeNoBit) {
  const PourResult working = pour(WorkerParking::kNever);
  ASSERT_GT(working.position_m.size(), 300u);
  EXPECT_EQ(working.probes, 0u);
  const PourResult parked = pour(WorkerParking::kAlways);
  expect_bitwise_equal(working.position_m, parked.position_m, "always parked, positions");
  expect_bitwise_equal(working.omega_rad_s, parked.omega_rad_s, "always parked, spins");

  // A rule that probes at every other run and switches on any gain: the mode
  // changes many times, at moments set by the machine's timing.
  WorkerParkingOptions restless;
  restless.window_s = 1e-12;
  restless.min_runs_per_window = 1;
  restless.switch_margin = 0.0;
  restless.first_probe_interval_windows = 1;
  restless.max_probe_interval_windows = 1;
  const PourResult switching = pour(WorkerParking::kAdaptive, restless);
  EXPECT_GT(switching.probes, 1000u);
  EXPECT_GT(switching.switches, 10u) << "the rule never switched: the test proves nothing";
  expect_bitwise_equal(working.position_m, switching.position_m, "switching, positions");
  expect_bitwise_equal(working.omega_rad_s, switching.omega_rad_s, "switching, spins");
}

}  // namespace
}  // namespace demcal::dem
