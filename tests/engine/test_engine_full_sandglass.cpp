// The full (3D) sandglass on LAMMPS (region primitives) and on LIGGGHTS (STL
// meshes, engines/stl_mesh.hpp), each split over two MPI ranks as a cluster
// runs it (issue 17), against demcal's own run of the same apparatus: the fill
// settles, the shut orifice goes, the hopper empties, the pile below is
// measured by demcal's conical AoR code. Labelled `engine`; skipped, with the
// reason, when the engine is not installed; on one rank when mpirun is not.
#include "dem/apparatus/sandglass.hpp"
#include "engines/engine_measure.hpp"
#include "engines/engine_run.hpp"
#include "engines/lammps_deck.hpp"
#include "engines/liggghts_deck.hpp"
#include "tests/support/engine_fixtures.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <ostream>
#include <string>

namespace demcal::engines {
namespace {

std::string first_word(const std::string& s) { return s.substr(0, s.find(' ')); }

struct FullSandglassEngine {
  const char* name;         // "lammps"
  const char* executable;   // "lmp"
  const char* environment;  // "DEMCAL_LAMMPS": overrides the launch line
  const char* package;      // the Debian package that installs it
  DeckResult (*write)(const dem::SandglassOptions&, const dem::GranularMaterial&,
                      const dem::RunProtocol&, const DeckOptions&);
};

DeckResult write_lammps(const dem::SandglassOptions& s, const dem::GranularMaterial& m,
                        const dem::RunProtocol& p, const DeckOptions& o) {
  return write_lammps_deck(s, m, p, o);
}
DeckResult write_liggghts(const dem::SandglassOptions& s, const dem::GranularMaterial& m,
                          const dem::RunProtocol& p, const DeckOptions& o) {
  return write_liggghts_deck(s, m, p, o);
}

// The environment variable overrides; otherwise two ranks when mpirun is there.
std::string two_rank_command(const FullSandglassEngine& e) {
  const char* v = std::getenv(e.environment);
  if (v != nullptr && *v != '\0') return v;
  if (executable_available("mpirun"))
    return std::string("mpirun --allow-run-as-root --oversubscribe -np 2 ") + e.executable;
  std::cout << "mpirun not found: " << e.name << " runs on one rank\n";
  return e.executable;
}

class EngineFullSandglass : public ::testing::TestWithParam<FullSandglassEngine> {};

TEST_P(EngineFullSandglass, EmptiesOnTwoRanksAsDemcalsOwnRunDoes) {
  const FullSandglassEngine& e = GetParam();
  if (!executable_available(e.executable))
    GTEST_SKIP() << e.name << " not installed: \"" << e.executable
                 << "\" is not on PATH (apt-get install " << e.package << ", or set "
                 << e.environment << ")";
  const std::string command = two_rank_command(e);
  if (!executable_available(first_word(command)))
    GTEST_SKIP() << "\"" << first_word(command) << "\" (" << e.environment << ") is not on PATH";
  // tests/unit/test_engines_full_sandglass.cpp's apparatus with a smaller fill.
  const dem::SandglassOptions s = testing::small_full_sandglass(0.002);
  dem::RunProtocol protocol;
  protocol.max_flow_s = 2.0;
  const auto material = testing::peer_material();
  const DeckResult deck = e.write(s, material, protocol, DeckOptions{});
  ASSERT_TRUE(deck.ok()) << deck.refusal;
  const auto dir = testing::fresh_dir("engine", std::string(e.name) + "-full-sandglass");
  EngineLaunch launch;
  launch.command = command;
  const EngineRunResult run = run_engine(*deck.deck, launch, dir);
  const dem::ApparatusResult theirs = measure_engine_run(*deck.deck, dir);
  dem::Sandglass own(s, material, protocol);
  const dem::ApparatusResult mine = own.run({});

  const double fraction = theirs.details["discharge"]["discharged_fraction"].get<double>();
  std::cout << e.name << ", full sandglass, " << theirs.details["particles"] << " grains, \""
            << command << "\" (" << run.wall_time_s << " s): discharge time "
            << theirs.observables["discharge_time_s"] << " s (demcal "
            << mine.observables["discharge_time_s"] << "), " << 100.0 * fraction
            << " % discharged; bulk density " << theirs.observables["bulk_density_kg_m3"]
            << " kg/m3 (demcal " << mine.observables["bulk_density_kg_m3"] << "); AoR "
            << theirs.observables["angle_of_repose_deg"] << " deg (demcal "
            << mine.observables["angle_of_repose_deg"] << ")\n";
  // The lattice's top layer is thinned at random (delete_atoms porosity): the
  // count is the asked one to within a few grains, not exactly.
  EXPECT_NEAR(theirs.details["particles"].get<double>(),
              deck.deck->record["layout"]["particles"].get<double>(),
              0.01 * deck.deck->record["layout"]["particles"].get<double>());
  // The hopper leaves no dead zone: the chamber empties.
  EXPECT_GT(fraction, 0.98);
  ASSERT_TRUE(theirs.observables["discharge_time_s"].is_number()) << theirs.details.dump(2);
  ASSERT_TRUE(theirs.observables["bulk_density_kg_m3"].is_number());
  ASSERT_TRUE(theirs.observables["angle_of_repose_deg"].is_number()) << theirs.details.dump(2);
  // One seed each; the slices of the same grains agree within 2 % (density) and
  // 3 % (time), the limits leave room for the 3D run's own seed scatter.
  const double rho = mine.observables["bulk_density_kg_m3"].get<double>();
  EXPECT_NEAR(theirs.observables["bulk_density_kg_m3"].get<double>(), rho, 0.05 * rho);
  const double t = mine.observables["discharge_time_s"].get<double>();
  EXPECT_NEAR(theirs.observables["discharge_time_s"].get<double>(), t, 0.2 * t);
  // A heap, not a flat layer, measured about the apparatus' axis.
  EXPECT_GT(theirs.observables["angle_of_repose_deg"].get<double>(), 10.0);
  EXPECT_LT(theirs.observables["angle_of_repose_deg"].get<double>(), 40.0);
}

// Printed by its name: the test's name in ctest (".../lammps", ".../liggghts").
void PrintTo(const FullSandglassEngine& e, std::ostream* os) { *os << e.name; }

INSTANTIATE_TEST_SUITE_P(
    BothEngines, EngineFullSandglass,
    ::testing::Values(FullSandglassEngine{"lammps", "lmp", "DEMCAL_LAMMPS", "lammps", write_lammps},
                      FullSandglassEngine{"liggghts", "liggghts", "DEMCAL_LIGGGHTS", "liggghts",
                                          write_liggghts}));

}  // namespace
}  // namespace demcal::engines
