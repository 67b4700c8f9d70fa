// The mapped grain-wall rolling resistance acts in LAMMPS as in demcal (issue 17,
// suspect "the floor's rolling term"): a grain rolling without slip on a plane
// `fix wall/gran` written with the mapping's particle-wall words decelerates at
// 5/7 mu_r g, the rate of a sphere (I = 2/5 m R^2) against the limiting torque
// mu_r R m g that demcal's epsd applies at a wall (lever R* = R). Without the
// rolling term it keeps its speed. Labelled `engine`; skipped, with the reason,
// when LAMMPS (lmp) is not installed.
#include "engines/deck.hpp"
#include "engines/dump_reader.hpp"
#include "engines/engine_run.hpp"
#include "engines/parameter_mapping.hpp"
#include "tests/support/engine_fixtures.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <string>

namespace demcal::engines {
namespace {

std::string lammps_command() {
  const char* v = std::getenv("DEMCAL_LAMMPS");
  return v != nullptr && *v != '\0' ? std::string(v) : std::string("lmp");
}

std::string first_word(const std::string& s) { return s.substr(0, s.find(' ')); }

// One 1 mm grain settled on the floor, then set rolling at speed_m_s along x
// (omega_y = v / R, no slip) for seconds; the final dump holds its velocity.
Deck rolling_grain_deck(const std::string& wall_words, double speed_m_s, double seconds) {
  const double dt = 5e-6, radius = 0.5e-3;
  std::string s;
  s += "units si\natom_style sphere\natom_modify map array\nboundary p p f\nnewton off\n";
  s += "comm_modify vel yes\n";
  s += "region box block -0.05 0.05 -0.005 0.005 -0.003 0.02 units box\ncreate_box 1 box\n";
  s += "neighbor 0.0003 bin\npair_style granular\n";
  s += "pair_coeff * * " + wall_words + "\n";  // no second grain: never used
  s += "fix floor all wall/gran granular " + wall_words + " zplane 0 NULL\n";
  s += "create_atoms 1 single -0.04 0 " + deck_number(radius * 0.999) + " units box\n";
  s += "set type 1 diameter 0.001 density 2650\n";
  s += "fix g all gravity 9.81 vector 0 0 -1\nfix nve all nve/sphere\n";
  s += "timestep " + deck_number(dt) + "\nthermo 100000\nrun 20000\n";
  s += "velocity all set " + deck_number(speed_m_s) + " 0 0 units box\n";
  s += "set atom 1 omega 0 " + deck_number(speed_m_s / radius) + " 0\n";
  s += "run " + std::to_string(static_cast<long>(seconds / dt + 0.5)) + "\n";
  s += "write_dump all custom final.dump id type x y z radius vx vy vz modify sort id\n";
  Deck d;
  d.engine = "lammps";
  d.script_name = "in.demcal";
  d.script = s;
  d.final_dump_name = "final.dump";
  return d;
}

double final_speed(const Deck& deck, const std::string& name) {
  EngineLaunch launch;
  launch.command = lammps_command();
  const EngineRunResult r = run_engine(deck, launch, testing::fresh_dir("engine", name));
  const ParticleDump dump = read_custom_dump(r.directory / deck.final_dump_name);
  EXPECT_EQ(dump.size(), 1u);
  EXPECT_TRUE(dump.has_velocity);
  return dump.velocity_m_s.at(0).x;
}

TEST(EngineLammpsWallRolling, GrainRollingOnTheFloorDeceleratesAtFiveSeventhsMuRG) {
  if (!executable_available(first_word(lammps_command())))
    GTEST_SKIP() << "LAMMPS not installed: \"" << first_word(lammps_command())
                 << "\" is not on PATH (apt-get install lammps, or set DEMCAL_LAMMPS)";
  const auto material = testing::peer_material();  // epsd, wall mu_r 0.3
  const auto map = map_to_lammps(material, {}).value();
  ASSERT_TRUE(map.particle_wall.rolling);
  const double mu_r = map.particle_wall.rolling_friction;
  const double v0 = 0.1, t = 0.015;
  const double expected = v0 - 5.0 / 7.0 * mu_r * 9.81 * t;  // 0.0685 m/s at mu_r 0.3

  const double with = final_speed(rolling_grain_deck(map.particle_wall.granular_words(), v0, t),
                                  "lammps-wall-rolling");
  LammpsPairCoefficients dry = map.particle_wall;
  dry.rolling = false;
  const double without =
      final_speed(rolling_grain_deck(dry.granular_words(), v0, t), "lammps-wall-no-rolling");
  std::cout << "LAMMPS grain rolling on a fix wall/gran floor, mu_r " << mu_r << ": " << v0
            << " m/s -> " << with << " m/s after " << t << " s (5/7 mu_r g: " << expected
            << " m/s); without the rolling term " << without << " m/s\n";
  // The deceleration to 1 %: the spring's elastic phase at the start is a few
  // microseconds.
  EXPECT_NEAR(v0 - with, v0 - expected, 0.01 * (v0 - expected));
  EXPECT_NEAR(without, v0, 1e-6);
}

}  // namespace
}  // namespace demcal::engines
