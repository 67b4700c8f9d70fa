// Raw recordings (config/raw_recordings.hpp): analytic profiles and mass series measured with
// the engine's own definitions. A symmetric heap with a known slope gives its angle; a linear
// m(t) gives t25/t50/t75 and the discharge time at the known fractions and its rate; the
// reading error is propagated and the repeats averaged; bad files are refused at
// file:line:column.
#include "config/raw_recordings.hpp"

#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

namespace demcal::config {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A triangular heap of `angle_deg`, crest at x = 0 of height `crest_m`, readings every `dx`
// over [-width, width], flat (0) beyond the toe.
SurfaceProfile heap(double angle_deg, double crest_m, double dx, double width) {
  SurfaceProfile p;
  const double slope = std::tan(angle_deg * kPi / 180.0);
  for (double x = -width; x <= width + 1e-12; x += dx) {
    p.position_m.push_back(x);
    p.height_m.push_back(std::max(0.0, crest_m - slope * std::abs(x)));
  }
  return p;
}

TEST(RawRecordings, AKnownSlopeGivesItsAngle) {
  for (const double angle : {25.0, 33.0, 40.0}) {
    const auto got = measure_profile(heap(angle, 0.02, 2e-4, 0.06), 5e-4, 1e-4);
    ASSERT_TRUE(got.count("angle_of_repose_deg")) << angle;
    EXPECT_NEAR(got.at("angle_of_repose_deg").first, angle, 0.3) << angle;
    const double sigma = got.at("angle_of_repose_deg").second;
    EXPECT_GT(sigma, 0.0);
    EXPECT_LT(sigma, 1.0);
  }
}

TEST(RawRecordings, TheAngleReadingErrorGrowsWithTheHeightError) {
  const SurfaceProfile p = heap(33.0, 0.02, 2e-4, 0.06);
  const double a = measure_profile(p, 5e-4, 1e-4).at("angle_of_repose_deg").second;
  const double b = measure_profile(p, 5e-4, 4e-4).at("angle_of_repose_deg").second;
  EXPECT_NEAR(b / a, 4.0, 1e-9);
}

TEST(RawRecordings, AFlatProfileGivesNoAngleAndSaysWhy) {
  SurfaceProfile p;
  for (int i = 0; i < 50; ++i) {
    p.position_m.push_back(1e-3 * i);
    p.height_m.push_back(0.0);
  }
  std::string why;
  EXPECT_TRUE(measure_profile(p, 5e-4, 1e-4, &why).empty());
  EXPECT_FALSE(why.empty());
}

// m(t) = rate t until the fill has passed, sampled every dt, then flat for a while.
MassSeries linear_discharge(double fill, double rate, double dt) {
  MassSeries s;
  const double end = fill / rate;
  for (double t = 0.0; t <= end + 1.0 + 1e-12; t += dt) {
    s.time_s.push_back(t);
    s.mass_kg.push_back(std::min(fill, rate * t));
  }
  return s;
}

TEST(RawRecordings, ALinearMassSeriesGivesItsTimesAndRate) {
  const double fill = 0.2, rate = 0.05;  // 4 s to empty
  const auto got = measure_mass_series(linear_discharge(fill, rate, 1e-3), fill, 1e-4, 1e-3);
  ASSERT_TRUE(got.count("discharge_t50_s"));
  EXPECT_NEAR(got.at("discharge_t25_s").first, 1.0, 2e-3);
  EXPECT_NEAR(got.at("discharge_t50_s").first, 2.0, 2e-3);
  EXPECT_NEAR(got.at("discharge_t75_s").first, 3.0, 2e-3);
  EXPECT_NEAR(got.at("discharge_time_s").first, 0.98 * 4.0, 2e-3);  // 98 % of the final mass
  EXPECT_NEAR(got.at("mass_flow_rate_kg_s").first, rate, 1e-6);
  // A crossing time's reading error: the clock's and the balance's over the rate.
  EXPECT_NEAR(got.at("discharge_t50_s").second, std::hypot(1e-3, 1e-4 / rate), 1e-12);
  EXPECT_GT(got.at("mass_flow_rate_kg_s").second, 0.0);
}

TEST(RawRecordings, AnUnfinishedDischargeGivesNoTime) {
  MassSeries s;
  for (int i = 0; i <= 10; ++i) {
    s.time_s.push_back(0.1 * i);
    s.mass_kg.push_back(0.01 * i);
  }
  std::string why;
  const auto got = measure_mass_series(s, 1.0, 1e-4, 1e-3, &why);
  EXPECT_FALSE(got.count("discharge_time_s"));
  EXPECT_NE(why.find("did not finish"), std::string::npos) << why;
}

std::string profile_csv(const SurfaceProfile& p) {
  std::ostringstream s;
  s.precision(17);
  s << "position_m,height_m\n";
  for (std::size_t i = 0; i < p.position_m.size(); ++i)
    s << p.position_m[i] << "," << p.height_m[i] << "\n";
  return s.str();
}

std::string mass_csv(const MassSeries& m) {
  std::ostringstream s;
  s.precision(17);
  s << "time_s,discharged_mass_kg\n";
  for (std::size_t i = 0; i < m.time_s.size(); ++i) s << m.time_s[i] << "," << m.mass_kg[i] << "\n";
  return s.str();
}

TEST(RawRecordings, RepeatsAreAveragedAndTheirScatterStated) {
  const auto dir = testing::fresh_dir("raw", "repeats");
  RawRecordingsConfig c;
  RawSetupRecordings r;
  r.setup = "sandglass";
  r.grain_diameter_m = 5e-4;
  r.height_reading_error_m = 1e-4;
  r.fill_mass_kg = 0.2;
  r.mass_reading_error_kg = 1e-4;
  r.time_reading_error_s = 1e-3;
  const double angles[] = {31.0, 33.0, 35.0};
  const double rates[] = {0.04, 0.05, 0.05};
  for (int k = 0; k < 3; ++k) {
    const auto p = dir / ("pile-" + std::to_string(k) + ".csv");
    testing::spit(p, profile_csv(heap(angles[k], 0.02, 2e-4, 0.06)));
    r.profiles.push_back(p);
    const auto m = dir / ("mass-" + std::to_string(k) + ".csv");
    testing::spit(m, mass_csv(linear_discharge(0.2, rates[k], 2e-3)));
    r.mass_series.push_back(m);
  }
  c.setups.push_back(r);
  const auto measured = measure_raw_recordings(c);
  const auto find = [&](const std::string& name) {
    for (const auto& m : measured)
      if (m.observable == name) return m;
    ADD_FAILURE() << name << " not measured";
    return RawMeasurement{};
  };
  const RawMeasurement aor = find("angle_of_repose_deg");
  ASSERT_EQ(aor.values.size(), 3u);
  EXPECT_NEAR(aor.mean, 33.0, 0.3);
  EXPECT_NEAR(aor.repeats_sd, 2.0, 0.3);
  double var = 0.0;
  for (const double s : aor.reading_sigma) var += s * s;
  EXPECT_NEAR(aor.sigma, std::sqrt(var) / 3.0, 1e-12);
  const RawMeasurement t50 = find("discharge_t50_s");
  EXPECT_NEAR(t50.mean, (2.5 + 2.0 + 2.0) / 3.0, 5e-3);
  const auto recs = to_recordings(measured);
  for (const auto& rec : recs) {
    EXPECT_EQ(rec.repeats, 3);
    EXPECT_GT(rec.sigma, 0.0);
  }
  const auto lines = raw_recording_lines(measured);
  ASSERT_FALSE(lines.empty());
  EXPECT_NE(lines.front().find("the mean of 3 repeats"), std::string::npos) << lines.front();
  EXPECT_NE(lines.front().find("reading error"), std::string::npos);
}

TEST(RawRecordings, BadFilesAreRefusedAtLineAndColumn) {
  const auto refused = [](const std::string& text, bool mass) {
    std::istringstream in(text);
    try {
      if (mass)
        read_mass_series_csv(in, "m.csv", 0.1);
      else
        read_surface_profile_csv(in, "p.csv");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refused("", false), "p.csv:1: empty file; expected the header position_m,height_m");
  EXPECT_NE(refused("position_m,height_m\n0,1\n1,nan\n", false).find("p.csv:3:2: height_m"),
            std::string::npos);
  EXPECT_NE(refused("position_m,height_m\nx,1\n", false).find("p.csv:2:1: position_m"),
            std::string::npos);
  EXPECT_NE(refused("time_s,discharged_mass_kg\n0,0\n-1,0.01\n", true).find("m.csv:3:1: time_s"),
            std::string::npos);
  EXPECT_NE(refused("time_s,discharged_mass_kg\n0,0\n1,0.5\n", true)
                .find("m.csv:3:2: discharged_mass_kg: expected a mass in [0, fill_mass_kg = 0.1]"),
            std::string::npos);
  EXPECT_NE(refused("time_s,discharged_mass_kg\n0,0\n", true).find("at least 2 samples"),
            std::string::npos);
  // Empty heights are points without a reading, comments and a BOM are allowed.
  EXPECT_EQ(refused("\xEF\xBB\xBF# laser line\nposition_m,height_m\n0,0.01\n1,\n2,0.02\n3,0.01\n4,0\n",
                    false),
            "accepted");
}

// A small deterministic fuzz in the suite (fuzz/fuzz_raw_recordings.cpp is the libFuzzer
// harness): random rows, some of them corrupted. A file without a corrupted row must be read
// and measured (the readers are not stricter than their format); one with a corrupted row
// gives a ConfigError; nothing else escapes, and nothing crashes.
TEST(RawRecordings, NoiseIsRefusedOrMeasuredNeverCrashes) {
  const std::string junk[] = {"x", "", "1,2,3", "nan", "inf", "-1", "1e999", "\"", "#", ",,"};
  std::uint64_t state = 12345;
  const auto next = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<std::size_t>(state >> 33);
  };
  const auto uniform = [&] { return static_cast<double>(next() % 100000) / 100000.0; };
  int clean = 0, measured = 0;
  for (int k = 0; k < 2000; ++k) {
    const bool profile = k % 2 == 1;
    std::ostringstream text;
    text.precision(9);
    text << (profile ? "position_m,height_m\n" : "time_s,discharged_mass_kg\n");
    const std::size_t rows = 4 + next() % 60;
    bool corrupted = false;
    double t = 0.0, m = 0.0;
    for (std::size_t i = 0; i < rows; ++i) {
      if (next() % 50 == 0) {
        const std::string& j = junk[next() % 10];
        const bool first = next() % 2 == 0;
        // A line starting with # is a comment, an empty height a position without a reading:
        // legal; everything else here is not.
        const bool legal = (first && j == "#") || (!first && profile && j.empty());
        corrupted = corrupted || !legal;
        text << (first ? j + ",1" : "1," + j) << "\n";
        continue;
      }
      if (profile) {
        text << (uniform() - 0.5) * 0.1 << "," << uniform() * 0.03 << "\n";
      } else {
        t += 1e-3 + uniform() * 0.05;
        m = std::min(0.5, m + uniform() * 0.02);
        text << t << "," << m << "\n";
      }
    }
    if (!corrupted) ++clean;
    try {
      std::istringstream in(text.str());
      if (profile) {
        const auto p = read_surface_profile_csv(in, "p.csv");
        (void)measure_profile(p, 5e-4, 1e-4);
      } else {
        const auto s = read_mass_series_csv(in, "m.csv", 0.5);
        (void)measure_mass_series(s, 0.5, 1e-3, 1e-3);
      }
      ++measured;
    } catch (const ConfigError& e) {
      EXPECT_TRUE(corrupted) << "a clean file was refused: " << e.what() << "\n" << text.str();
    }
  }
  EXPECT_GT(clean, 500);
  EXPECT_GE(measured, clean);
}

}  // namespace
}  // namespace demcal::config
