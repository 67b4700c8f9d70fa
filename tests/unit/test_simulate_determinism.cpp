// `demcal simulate` twice with the same seed and thread count writes identical
// files (all but the wall-clock fields of run.json); an existing run is never
// overwritten without --overwrite.
#include "cli/simulate_command.hpp"
#include "config/simulation_config.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace demcal::cli {
namespace {

using namespace demcal::config;
using namespace demcal::study;

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

SimulateOptions small_pile(const fs::path& dir, int threads) {
  SimulateOptions o;
  o.config = fs::path(DEMCAL_SOURCE_DIR) / "studies/poured-pile/study.toml";
  o.overrides = {"insertion[0].count=250", "run.end_time_s=0.08", "output.snapshot_interval_s=0.02"};
  o.output_dir = dir.string();
  o.threads = threads;
  o.quiet = true;
  return o;
}

fs::path run_small_pile(const std::string& tag, int threads) {
  const fs::path dir = fs::temp_directory_path() / ("demcal-determinism-" + tag);
  fs::remove_all(dir);
  std::ostringstream sink;
  simulate(small_pile(dir, threads), sink, sink);
  return dir;
}

nlohmann::json without_clock(nlohmann::json j) {
  j.erase("written_utc");
  j["results"].erase("wall_time_s");
  j["results"].erase("particle_steps_per_s");
  j.erase("outputs");
  j["inputs"]["output"].erase("directory");
  return j;
}

TEST(SimulateDeterminism, SameSeedAndThreadsWriteIdenticalFiles) {
  for (int threads : {1, 2}) {
    const std::string t = std::to_string(threads);
    const fs::path a = run_small_pile("a" + t, threads);
    const fs::path b = run_small_pile("b" + t, threads);
    std::size_t compared = 0;
    for (const auto& entry : fs::directory_iterator(a / "vtk")) {
      const fs::path other = b / "vtk" / entry.path().filename();
      ASSERT_TRUE(fs::exists(other)) << other;
      EXPECT_EQ(slurp(entry.path()), slurp(other)) << entry.path().filename();
      ++compared;
    }
    EXPECT_GE(compared, 8u);
    const auto ja = nlohmann::json::parse(slurp(a / "run.json"));
    const auto jb = nlohmann::json::parse(slurp(b / "run.json"));
    EXPECT_GT(ja["results"]["particles"].get<int>(), 200);
    EXPECT_EQ(without_clock(ja), without_clock(jb)) << threads << " threads";
    fs::remove_all(a);
    fs::remove_all(b);
  }
}

TEST(SimulateDeterminism, RefusesToOverwriteAnEarlierRunBeforeComputing) {
  const fs::path dir = run_small_pile("keep", 1);
  const std::string record = slurp(dir / "run.json");
  const std::string last_snapshot = slurp(dir / "particles.pvd");
  std::ostringstream sink;
  SimulateOptions again = small_pile(dir, 1);
  again.overrides.push_back("simulation.seed=99");
  try {
    simulate(again, sink, sink);
    FAIL() << "expected a refusal";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--overwrite"), std::string::npos) << e.what();
  }
  EXPECT_EQ(slurp(dir / "run.json"), record);
  EXPECT_EQ(slurp(dir / "particles.pvd"), last_snapshot);
  again.overwrite = true;
  simulate(again, sink, sink);
  EXPECT_NE(slurp(dir / "run.json"), record);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace demcal::cli
