// Runs LIGGGHTS on demcal's deck of the small poured slab pile and measures
// the pile with demcal's own angle-of-repose code. Labelled `engine`; skipped,
// with the reason, when LIGGGHTS is not installed.
#include "engines/engine_measure.hpp"
#include "engines/engine_run.hpp"
#include "engines/liggghts_deck.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
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

}  // namespace
}  // namespace demcal::engines
