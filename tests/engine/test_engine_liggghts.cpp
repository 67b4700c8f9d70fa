// Runs LIGGGHTS on demcal's deck of the small poured slab pile and measures
// the pile with demcal's own angle-of-repose code, and on the Sandglass slice
// with its hopper (slanted plates as STL meshes) against demcal's own run.
// Labelled `engine`; skipped, with the reason, when LIGGGHTS is not installed.
#include "dem/apparatus/sandglass.hpp"
#include "engines/engine_measure.hpp"
#include "engines/engine_run.hpp"
#include "engines/liggghts_deck.hpp"
#include "tests/support/engine_fixtures.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <string>

namespace demcal::engines {
namespace {

// DEMCAL_LIGGGHTS overrides the launch line (e.g. "mpirun -np 2 liggghts").
std::string liggghts_command() {
  const char* v = std::getenv("DEMCAL_LIGGGHTS");
  return v != nullptr && *v != '\0' ? std::string(v) : std::string("liggghts");
}

TEST(EngineLiggghts, SmallPouredPileHasASensibleAngleOfRepose) {
  const std::string command = liggghts_command();
  const std::string exe = command.substr(0, command.find(' '));
  if (!executable_available(exe))
    GTEST_SKIP() << "LIGGGHTS not installed: \"" << exe
                 << "\" is not on PATH (apt-get install liggghts, or set DEMCAL_LIGGGHTS)";
  dem::PouredSlabPileOptions pile;
  // As the LAMMPS test: the peers' pile at N = 1500 in its 120 mm box.
  pile.particles = 1500;
  const DeckResult deck = write_liggghts_deck(pile);
  ASSERT_TRUE(deck.ok()) << deck.refusal;
  const auto dir = testing::fresh_dir("engine", "liggghts-pile");
  EngineLaunch launch;
  launch.command = command;
  const EngineRunResult run = run_engine(*deck.deck, launch, dir);
  EXPECT_NE(run.engine_version.find("LIGGGHTS"), std::string::npos) << run.engine_version;
  const dem::ApparatusResult r = measure_engine_run(*deck.deck, dir);
  ASSERT_FALSE(r.observables["angle_of_repose_deg"].is_null()) << r.details.dump(2);
  const double aor = r.observables["angle_of_repose_deg"].get<double>();
  std::cout << "LIGGGHTS pile N = " << pile.particles << ": AoR " << aor << " deg, wall time "
            << run.wall_time_s << " s (" << run.engine_version << ")\n";
  EXPECT_GT(aor, 10.0);
  EXPECT_LT(aor, 35.0);
  EXPECT_EQ(r.details["particles"].get<std::size_t>(), pile.particles);
}

// The hopper's two slanted plates as STL meshes: the grains slide down them
// to the slot and the chamber empties, as in demcal and LAMMPS
// (test_engine_lammps_effects.cpp); the settled fill's dump gives demcal's
// bulk density of LIGGGHTS's fill.
TEST(EngineLiggghts, SandglassSliceHopperEmptiesTheChamber) {
  const std::string command = liggghts_command();
  const std::string exe = command.substr(0, command.find(' '));
  if (!executable_available(exe))
    GTEST_SKIP() << "LIGGGHTS not installed: \"" << exe
                 << "\" is not on PATH (apt-get install liggghts, or set DEMCAL_LIGGGHTS)";
  // Six diameters: LIGGGHTS's least periodic slab with mesh walls.
  const dem::SandglassOptions s = testing::small_hopper_slice(6.0);
  dem::RunProtocol protocol;
  protocol.max_flow_s = 2.0;
  const auto material = testing::peer_material();
  const DeckResult deck = write_liggghts_deck(s, material, protocol);
  ASSERT_TRUE(deck.ok()) << deck.refusal;
  const auto dir = testing::fresh_dir("engine", "liggghts-hopper");
  EngineLaunch launch;
  launch.command = command;
  const EngineRunResult run = run_engine(*deck.deck, launch, dir);
  const dem::ApparatusResult theirs = measure_engine_run(*deck.deck, dir);
  dem::Sandglass own(s, material, protocol);
  const dem::ApparatusResult mine = own.run({});
  const double fraction = theirs.details["discharge"]["discharged_fraction"].get<double>();
  std::cout << "LIGGGHTS sandglass slice with hopper: " << theirs.details["particles"]
            << " particles, discharge time " << theirs.observables["discharge_time_s"]
            << " s (demcal " << mine.observables["discharge_time_s"] << "), " << 100.0 * fraction
            << " % discharged; bulk density " << theirs.observables["bulk_density_kg_m3"]
            << " kg/m3 (demcal " << mine.observables["bulk_density_kg_m3"] << "), wall time "
            << run.wall_time_s << " s\n";
  EXPECT_GT(fraction, 0.98);
  ASSERT_TRUE(theirs.observables["bulk_density_kg_m3"].is_number()) << theirs.observables.dump();
  const double rho = mine.observables["bulk_density_kg_m3"].get<double>();
  EXPECT_NEAR(theirs.observables["bulk_density_kg_m3"].get<double>(), rho, 0.05 * rho);
  ASSERT_TRUE(theirs.observables["discharge_time_s"].is_number()) << theirs.details.dump(2);
  const double t = mine.observables["discharge_time_s"].get<double>();
  EXPECT_NEAR(theirs.observables["discharge_time_s"].get<double>(), t, 0.2 * t);
}

}  // namespace
}  // namespace demcal::engines
