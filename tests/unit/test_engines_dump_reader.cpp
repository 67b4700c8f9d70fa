// The dump and mass-series readers (engines/dump_reader.hpp) on small
// handmade files, malformed ones named by file and line, and demcal's
// measurement of engine output (engines/engine_measure.hpp).
#include "engines/dump_reader.hpp"
#include "engines/engine_measure.hpp"

#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <sstream>

namespace demcal::engines {
namespace {

const char* kDump =
    "ITEM: TIMESTEP\n"
    "1200\n"
    "ITEM: NUMBER OF ATOMS\n"
    "2\n"
    "ITEM: BOX BOUNDS ff pp ff\n"
    "-0.03 0.03\n"
    "0 0.005\n"
    "-0.001 0.04\n"
    "ITEM: ATOMS id type x y z radius vx vy vz\n"
    "1 1 0.001 0.002 0.0005 0.0005 0 0 -0.1\n"
    "2 1 -0.001 0.003 0.0015 0.0005 0.01 0 0\n";

// The message must name the file and the line.
void expect_error(const std::string& text, const std::string& where, const std::string& what) {
  try {
    parse_custom_dump(text, "bad.dump");
    FAIL() << "no error for " << what;
  } catch (const DumpFormatError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("bad.dump:" + where + ": ", 0), 0u) << m;
    EXPECT_NE(m.find(what), std::string::npos) << m;
  }
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  s.replace(s.find(from), from.size(), to);
  return s;
}

TEST(EnginesDumpReader, ReadsACustomDump) {
  const ParticleDump d = parse_custom_dump(kDump, "ok.dump");
  EXPECT_EQ(d.timestep, 1200);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d.id[1], 2);
  EXPECT_DOUBLE_EQ(d.position_m[1].x, -0.001);
  EXPECT_DOUBLE_EQ(d.radius_m[0], 0.0005);
  EXPECT_TRUE(d.has_velocity);
  EXPECT_DOUBLE_EQ(d.velocity_m_s[0].z, -0.1);
  EXPECT_DOUBLE_EQ(d.box_upper_m.y, 0.005);
  // Columns in another order, without velocities; two snapshots: the last counts.
  const std::string two =
      std::string(kDump) +
      "ITEM: TIMESTEP\n1300\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS ff pp ff\n"
      "-0.03 0.03\n0 0.005\n-0.001 0.04\nITEM: ATOMS radius z y x id\n"
      "0.0004 0.01 0.002 0.003 7\n";
  const ParticleDump e = parse_custom_dump(two, "two.dump");
  EXPECT_EQ(e.timestep, 1300);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e.id[0], 7);
  EXPECT_DOUBLE_EQ(e.position_m[0].x, 0.003);
  EXPECT_FALSE(e.has_velocity);
}

TEST(EnginesDumpReader, MalformedDumpsNameFileAndLine) {
  expect_error("", "0", "no snapshot");
  expect_error(replaced(kDump, "ITEM: TIMESTEP", "ITEM: TIME"), "1", "expected \"ITEM: TIMESTEP\"");
  expect_error(replaced(kDump, "1200", "12x0"), "2", "timestep");
  expect_error(replaced(kDump, "\n2\n", "\n-2\n"), "4", "atom count");
  expect_error(replaced(kDump, "-0.03 0.03", "0.03 -0.03"), "6", "invalid box bounds");
  expect_error(replaced(kDump, "id type x y z radius", "id type x y z"), "9", "lack \"radius\"");
  expect_error(replaced(kDump, "0.002 0.0005 0.0005", "0.002 nan 0.0005"), "10", "column z");
  expect_error(replaced(kDump, "0.0015 0.0005", "0.0015 -0.0005"), "11", "radius");
  expect_error(replaced(kDump, "0 0 -0.1\n", "0 0\n"), "10", "expected 9 columns, found 8");
  // Truncated: one atom line short.
  const std::string cut(kDump, std::string(kDump).rfind("2 1 -0.001"));
  expect_error(cut, "10", "unexpected end of file, expected 2 atom lines, found 1");
}

TEST(EnginesDumpReader, ReadsFromAFileAndNamesIt) {
  const auto dir = testing::fresh_dir("engines", "dump");
  testing::spit(dir / "final.dump", kDump);
  EXPECT_EQ(read_custom_dump(dir / "final.dump").size(), 2u);
  testing::spit(dir / "bad.dump", replaced(kDump, "1200", "x"));
  try {
    read_custom_dump(dir / "bad.dump");
    FAIL();
  } catch (const DumpFormatError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "bad.dump").string() + ":2:"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(read_custom_dump(dir / "missing.dump"), DumpFormatError);
}

TEST(EnginesDumpReader, MassSeries) {
  const std::string ok =
      "# t_since_opening_s discharged_mass_kg mass_above_orifice_kg\n"
      "# Fix print output for fix mass_series\n"
      "0 0 0.002\n0.005 0.0001 0.0019\n0.01 0.0003 0.0017\n";
  const MassSeries m = parse_mass_series(ok, "m.txt");
  ASSERT_EQ(m.time_s.size(), 3u);
  EXPECT_DOUBLE_EQ(m.fill_mass_kg(), 0.002);
  EXPECT_DOUBLE_EQ(m.discharged_kg[2], 0.0003);
  auto error_of = [](const std::string& text) {
    try {
      parse_mass_series(text, "m.txt");
    } catch (const DumpFormatError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error_of("0 0 1\n0 0.1 0.9\n"),
            "m.txt:2: time 0 does not increase (previous row 0.000000)");
  EXPECT_EQ(error_of("# c\n0 0 1\n0.1 0.1\n").rfind("m.txt:3: expected 3 columns", 0), 0u);
  EXPECT_EQ(error_of("0 0 1\n0.1 x 0.9\n"), "m.txt:2: \"x\" is not a finite number");
  EXPECT_EQ(error_of("0 0 1\n0.1 0.1 -0.9\n"), "m.txt:2: negative mass");
  EXPECT_EQ(error_of("0 0 1\n"), "m.txt:1: a mass series needs at least 2 rows, found 1");
}

// A synthetic quasi-2D heap of known slope, written as an engine would dump it.
std::string heap_dump(double angle_deg, double d) {
  std::ostringstream s;
  std::vector<std::array<double, 3>> grains;
  const double slope = std::tan(angle_deg * M_PI / 180.0);
  const double half = 0.03;
  for (double x = -half + d / 2; x < half; x += d)
    for (double y = d / 2; y < 4 * d; y += d) {
      const double top = std::max(d / 2, 0.02 - slope * std::abs(x));
      for (double z = d / 2; z <= top; z += d) grains.push_back({x, y, z});
    }
  s << "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n"
    << grains.size()
    << "\nITEM: BOX BOUNDS ff pp ff\n-0.03 0.03\n0 0.004\n0 0.03\nITEM: ATOMS id type x y z "
       "radius\n";
  for (std::size_t i = 0; i < grains.size(); ++i)
    s << i + 1 << " 1 " << grains[i][0] << " " << grains[i][1] << " " << grains[i][2] << " "
      << d / 2 << "\n";
  return s.str();
}

TEST(EnginesMeasure, SliceAngleOfReposeFromADump) {
  const ParticleDump d = parse_custom_dump(heap_dump(30.0, 1e-3), "heap.dump");
  const nlohmann::json plan = {{"kind", "slice_angle_of_repose"},
                               {"apparatus", "poured_slab_pile"},
                               {"long_axis", 0},
                               {"base_height_m", 0.0}};
  const auto r = measure_engine_output(plan, d, nullptr);
  ASSERT_FALSE(r.observables["angle_of_repose_deg"].is_null()) << r.details.dump();
  EXPECT_NEAR(r.observables["angle_of_repose_deg"].get<double>(), 30.0, 2.0);
}

TEST(EnginesMeasure, SandglassDischargeFromASeries) {
  // 1 g at 10 g/s after a short start; every grain leaves (no arch).
  MassSeries m;
  for (int i = 0; i <= 40; ++i) {
    const double t = 0.005 * i;
    const double out = std::min(1e-3, std::max(0.0, 0.01 * (t - 0.01)));
    m.time_s.push_back(t);
    m.discharged_kg.push_back(out);
    m.above_orifice_kg.push_back(1e-3 - out);
  }
  ParticleDump d;  // the final state: everything below the plate
  const nlohmann::json plan = {{"kind", "sandglass_slice"}, {"apparatus", "sandglass"},
                               {"orifice_plane_z_m", 0.03}, {"orifice_width_m", 0.008},
                               {"form_pile", false},        {"stall_time_s", 0.05}};
  const auto r = measure_engine_output(plan, d, &m);
  EXPECT_NEAR(r.observables["mass_flow_rate_kg_s"].get<double>(), 0.01, 1e-6);
  EXPECT_FALSE(r.observables["discharge_time_s"].is_null()) << r.details.dump();
  EXPECT_THROW(measure_engine_output(plan, d, nullptr), std::invalid_argument);
}

// The flat slice of studies/engine-crosscheck on LIGGGHTS: m(t) sampled every
// 561 steps (4.998 ms), the flow stopped at about half the fill (dead zones on
// the flat bottom), and the deck ended it after a 0.1 s chunk with no change. Its
// series then ends with 20 equal samples, 0.09997 s: two sample intervals are
// what the deck's sampling can fall short of the stall time, so that is a stop.
TEST(EnginesMeasure, AStopIsReadAtTheResolutionOfTheEnginesSampling) {
  const double interval = 0.0049984;
  auto stopped_series = [&](int quiet_samples) {
    MassSeries m;
    const double out = 1.66e-3, fill = 3.24e-3;
    for (int i = 0;; ++i) {
      const double t = interval * i;
      const double passed = std::min(out, 0.0083 * t);
      m.time_s.push_back(t);
      m.discharged_kg.push_back(passed);
      m.above_orifice_kg.push_back(fill - passed);
      if (passed == out && --quiet_samples < 0) break;
    }
    return m;
  };
  const nlohmann::json plan = {{"kind", "sandglass_slice"}, {"apparatus", "sandglass"},
                               {"orifice_plane_z_m", 0.03}, {"orifice_width_m", 0.008},
                               {"form_pile", false},        {"stall_time_s", 0.1}};
  const MassSeries ended = stopped_series(20);
  ASSERT_LT(ended.time_s.back() - ended.time_s[ended.time_s.size() - 21], 0.1);
  const auto r = measure_engine_output(plan, ParticleDump{}, &ended);
  EXPECT_FALSE(r.observables["discharge_time_s"].is_null()) << r.details["discharge"].dump(1);
  EXPECT_NEAR(r.details["retained_in_dead_zones_fraction"].get<double>(), 1.0 - 1.66 / 3.24,
              1e-3);
  // A quiet tail three intervals short of the stall time is a flow still
  // running when the series ended (a time cap), as before.
  const MassSeries cut = stopped_series(17);
  const auto running = measure_engine_output(plan, ParticleDump{}, &cut);
  EXPECT_TRUE(running.observables["discharge_time_s"].is_null());
  EXPECT_EQ(running.details["discharge"]["status"], "running");
}

}  // namespace
}  // namespace demcal::engines
