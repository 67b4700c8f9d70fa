// Runs LAMMPS on demcal's deck of a small poured slab pile and measures the
// pile with demcal's own angle-of-repose code. Labelled `engine`; skipped, with
// the reason, when LAMMPS (lmp) is not installed.
#include "engines/engine_measure.hpp"
#include "engines/engine_run.hpp"
#include "engines/lammps_deck.hpp"
#include "tests/support/engine_fixtures.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace demcal::engines {
namespace {

// The launch line: DEMCAL_LAMMPS overrides (e.g. "mpirun --allow-run-as-root -np 2 lmp").
std::string lammps_command() {
  const char* v = std::getenv("DEMCAL_LAMMPS");
  return v != nullptr && *v != '\0' ? std::string(v) : std::string("lmp");
}

std::string first_word(const std::string& s) { return s.substr(0, s.find(' ')); }

TEST(EngineLammps, SmallPouredPileHasASensibleAngleOfRepose) {
  const std::string command = lammps_command();
  if (!executable_available(first_word(command)))
    GTEST_SKIP() << "LAMMPS not installed: \"" << first_word(command)
                 << "\" is not on PATH (apt-get install lammps, or set DEMCAL_LAMMPS)";
  // The peers' pile (d = 1 mm, E = 1e7 Pa, mu_s 0.5, mu_r 0.1, walls 0.9 / 0.3,
  // 120 mm box) at N = 1500: half a minute on one core. (In a 60 mm box the
  // heap reaches the side walls and the angle scatters from 10 to 19 deg.)
  dem::PouredSlabPileOptions pile;
  pile.particles = 1500;
  const DeckResult deck = write_lammps_deck(pile);
  ASSERT_TRUE(deck.ok()) << deck.refusal;
  const auto dir = testing::fresh_dir("engine", "lammps-pile");
  EngineLaunch launch;
  launch.command = command;
  const EngineRunResult run = run_engine(*deck.deck, launch, dir);
  EXPECT_NE(run.engine_version.find("LAMMPS"), std::string::npos);
  const dem::ApparatusResult r = measure_engine_run(*deck.deck, dir);
  ASSERT_FALSE(r.observables["angle_of_repose_deg"].is_null()) << r.details.dump(2);
  const double aor = r.observables["angle_of_repose_deg"].get<double>();
  std::cout << "LAMMPS pile N = " << pile.particles << ": AoR " << aor << " deg, wall time "
            << run.wall_time_s << " s (" << run.engine_version << ")\n";
  // Measured (seeds 4767, 11, 12): LAMMPS 17.2, 17.9, 12.9 deg; demcal's own
  // engine on the same case 14.1, 13.9, 18.2 deg; the peers' 21.7 deg is at
  // N = 3000. A pile of ten grains' height scatters by a few degrees, but a
  // heap it must be: not a flat layer, not banked against the walls.
  EXPECT_GT(aor, 10.0);
  EXPECT_LT(aor, 35.0);
  EXPECT_EQ(r.details["particles"].get<std::size_t>(), pile.particles);
}

// The sandglass slice (flat bottom, slot orifice): the fill settles, the
// orifice opens, m(t) is recorded; demcal reads a steady flow rate from it.
TEST(EngineLammps, SandglassSliceDischarges) {
  const std::string command = lammps_command();
  if (!executable_available(first_word(command)))
    GTEST_SKIP() << "LAMMPS not installed: \"" << first_word(command)
                 << "\" is not on PATH (apt-get install lammps, or set DEMCAL_LAMMPS)";
  dem::SandglassOptions s = testing::small_sandglass_slice();
  s.form_pile = false;
  dem::RunProtocol protocol;
  protocol.max_flow_s = 2.0;
  const DeckResult deck = write_lammps_deck(s, testing::peer_material(), protocol);
  ASSERT_TRUE(deck.ok()) << deck.refusal;
  const auto dir = testing::fresh_dir("engine", "lammps-sandglass");
  EngineLaunch launch;
  launch.command = command;
  const EngineRunResult run = run_engine(*deck.deck, launch, dir);
  const dem::ApparatusResult r = measure_engine_run(*deck.deck, dir);
  ASSERT_FALSE(r.observables["mass_flow_rate_kg_s"].is_null()) << r.details.dump(2);
  const double rate = r.observables["mass_flow_rate_kg_s"].get<double>();
  const double fraction = r.details["discharge"]["discharged_fraction"].get<double>();
  std::cout << "LAMMPS sandglass slice: " << r.details["particles"] << " particles, flow rate "
            << rate * 1e3 << " g/s, " << 100.0 * fraction << " % discharged ("
            << r.details["discharge"]["status"].get<std::string>() << "), wall time "
            << run.wall_time_s << " s\n";
  // A flat-bottomed 8 mm slot in a 4 mm slab of 1 mm grains: a few g/s, and
  // most of the fill out (dead zones stay on the flat bottom).
  EXPECT_GT(rate, 1e-3);
  EXPECT_LT(rate, 2e-2);
  EXPECT_GT(fraction, 0.5);
}

}  // namespace
}  // namespace demcal::engines
