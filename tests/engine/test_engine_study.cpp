// A design of a study with [engine] kind = "liggghts" run through demcal's
// design runner on the real LIGGGHTS (study/engine_evaluator.hpp): the deck is
// written from the study's rectangular container, LIGGGHTS runs it, demcal
// measures the pile and stores the runs. Labelled `engine`; skipped, with the
// reason, when LIGGGHTS is not installed.
#include "engines/engine_run.hpp"
#include "study/design_runner.hpp"
#include "study/doe_plan.hpp"
#include "study/run_store.hpp"
#include "tests/support/test_files.hpp"
#include "tests/support/study_text.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <string>

namespace demcal::study {
namespace {

namespace fs = std::filesystem;

std::string liggghts_command() {
  const char* v = std::getenv("DEMCAL_LIGGGHTS");
  return v != nullptr && *v != '\0' ? std::string(v) : std::string("liggghts");
}

TEST(EngineStudy, ADesignRunsOnLiggghtsIntoTheRunStore) {
  const std::string command = liggghts_command();
  const std::string exe = command.substr(0, command.find(' '));
  if (!engines::executable_available(exe))
    GTEST_SKIP() << "LIGGGHTS not installed: \"" << exe
                 << "\" is not on PATH (apt-get install liggghts, or set DEMCAL_LIGGGHTS)";
  const fs::path dir = testing::fresh_dir("engine", "liggghts-study");
  // A small container-quick: a periodic slab a few coarse-grained grains thick,
  // poured to a pile of about 500 grains, at a low and a high rolling friction.
  testing::spit(dir / "study.toml", R"([study]
name = "engine-study"
seed = 1

)" +
    testing::sand_and_glass_tables() +
    R"(
[protocol]
max_flow_s = 5.0

[apparatus.rectangular_container]
width_m = 0.12
height_m = 0.08
thickness_diameters = 4.0
boundary = "periodic"
fill_mass_kg = 0.012
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7

[design]
kind = "full_factorial"
parameters = { mu_r = { lower = 0.05, upper = 0.4, levels = 2 } }

[engine]
kind = "liggghts"
launch = ")" + command + "\"\n");
  const DoePlan plan = plan_doe(dir / "study.toml", {}, {}, 1);
  ASSERT_EQ(plan.runs.size(), 2u);
  EXPECT_EQ(plan.runs[0].key.key["engine"]["kind"], "liggghts");
  EXPECT_EQ(plan.runs[0].key.key["engine"]["version"].get<std::string>().rfind("LIGGGHTS (", 0),
            0u);
  const RunStore store(dir / "out" / "runs");
  DesignRunOptions options;
  options.jobs = 2;
  DesignRunner runner(plan, store, options);
  SilentObserver quiet;
  const DesignRunResult done = runner.run(quiet);
  ASSERT_EQ(done.executed, 2u);
  double aor[2] = {0.0, 0.0};
  for (std::size_t i = 0; i < 2; ++i) {
    const auto record = store.load(plan.runs[i].key.hash, plan.runs[i].key.digest);
    ASSERT_TRUE(record.has_value());
    const nlohmann::json& r = *record;
    ASSERT_EQ(r["design"]["status"], "ok") << r["results"].dump();
    EXPECT_EQ(r["engine"]["name"], "liggghts");
    ASSERT_TRUE(r["observables"]["angle_of_repose_deg"].is_number()) << r["details"].dump();
    aor[i] = r["observables"]["angle_of_repose_deg"].get<double>();
    std::cout << "LIGGGHTS via [engine], mu_r " << r["design"]["parameters"]["mu_r"] << ": AoR "
              << aor[i] << " deg, " << r["details"]["particles"] << " grains, engine wall time "
              << r["details"]["engine_wall_time_s"] << " s\n";
    EXPECT_GT(aor[i], 5.0);
    EXPECT_LT(aor[i], 50.0);
  }
  EXPECT_GT(aor[1], aor[0]) << "a higher rolling friction must give a steeper pile";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace demcal::study
