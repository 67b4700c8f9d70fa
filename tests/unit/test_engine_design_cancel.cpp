// A design on another engine that is stopped or runs too long
// (engines/engine_process.hpp through study/engine_evaluator.hpp): an engine
// that never ends (a shell stand-in that sleeps with a child of its own) is
// ended with its child when the campaign is cancelled — and nothing is stored
// for its runs — or when a run passes [engine] timeout_s — and the run is
// stored as failed, saying so.
#include "study/design_runner.hpp"
#include "study/doe_plan.hpp"
#include "study/progress_observer.hpp"
#include "study/run_store.hpp"
#include "tests/support/study_text.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include <signal.h>

namespace demcal::study {
namespace {

namespace fs = std::filesystem;

// Answers the version query (an empty deck) as LIGGGHTS would; any other deck
// never ends.
const char* const kSleepingEngine = R"SH(#!/bin/sh
deck=""; log="log.liggghts"
while [ $# -gt 0 ]; do
  case "$1" in
    -in) deck="$2"; shift 2 ;;
    -log) log="$2"; shift 2 ;;
    *) shift ;;
  esac
done
echo "LIGGGHTS (Version sleeping-fake-engine 1.0 for demcal's tests)" > "$log"
[ -s "$deck" ] || exit 0
sleep 60 & echo $! > child.pid; wait
)SH";

fs::path write_study(const std::string& name, const std::string& engine_extra) {
  const fs::path dir = testing::fresh_dir("engine-design-cancel", name);
  testing::spit(dir / "sleeping_engine.sh", kSleepingEngine);
  testing::spit(dir / "study.toml", "[study]\nname = \"engine-cancel\"\nseed = 1\n\n" +
                                        testing::sand_and_glass_tables() +
                                        testing::small_container_design_tables() + R"(
[engine]
kind = "liggghts"
launch = "sh )" + (dir / "sleeping_engine.sh").string() +
                                        "\"\n" + engine_extra);
  return dir / "study.toml";
}

// The children the engine runs started, one per run directory that got one.
std::vector<pid_t> engine_children(const fs::path& engine_runs) {
  std::vector<pid_t> pids;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(engine_runs, ec)) {
    std::ifstream in(e.path() / "child.pid");
    pid_t pid = 0;
    if (in >> pid && pid > 0) pids.push_back(pid);
  }
  return pids;
}

bool running(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return false;
  const auto close = line.rfind(')');
  return close != std::string::npos && close + 2 < line.size() && line[close + 2] != 'Z';
}

TEST(EngineDesignCancel, ACancelledCampaignEndsTheEnginesAndStoresNothing) {
  const fs::path study = write_study("cancel", "");
  const DoePlan plan = plan_doe(study, {}, {}, 1);
  ASSERT_EQ(plan.runs.size(), 3u);
  const RunStore store(study.parent_path() / "out" / "runs");
  std::atomic<bool> cancel{false};
  DesignRunOptions options;
  options.jobs = 2;
  options.cancel = &cancel;
  DesignRunner runner(plan, store, options);
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(800));
    cancel = true;
  });
  SilentObserver quiet;
  const auto t0 = std::chrono::steady_clock::now();
  const DesignRunResult done = runner.run(quiet);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stopper.join();
  EXPECT_EQ(done.executed, 0u);
  EXPECT_LT(took, 8.0) << "the runs waited for their engines instead of ending them";
  for (const PlannedRun& run : plan.runs)
    EXPECT_FALSE(store.load(run.key.hash, run.key.digest).has_value()) << run.key.hash;
  const std::vector<pid_t> children = engine_children(study.parent_path() / "out" / "engine-runs");
  EXPECT_EQ(children.size(), 2u);  // two workers had started their engines
  for (const pid_t child : children) EXPECT_FALSE(running(child)) << "engine child " << child;
  fs::remove_all(study.parent_path());
}

TEST(EngineDesignCancel, ARunPastTheTimeoutIsStoredAsFailedWithTheReason) {
  const fs::path study = write_study("timeout", "timeout_s = 0.4\n");
  const DoePlan plan = plan_doe(study, {}, {}, 1);
  ASSERT_EQ(plan.runs.size(), 3u);
  const RunStore store(study.parent_path() / "out" / "runs");
  DesignRunOptions options;
  options.jobs = 2;
  DesignRunner runner(plan, store, options);
  SilentObserver quiet;
  const DesignRunResult done = runner.run(quiet);
  EXPECT_EQ(done.executed, 3u);
  EXPECT_EQ(done.failed, 3u);
  for (const PlannedRun& run : plan.runs) {
    const auto record = store.load(run.key.hash, run.key.digest);
    ASSERT_TRUE(record.has_value()) << run.key.hash;
    EXPECT_EQ((*record)["design"]["status"], "failed");
    const std::string error = (*record)["results"].dump();
    EXPECT_NE(error.find("timed out after 0.4 s"), std::string::npos) << error;
    EXPECT_EQ((*record)["engine"]["timeout_s"], 0.4);
    EXPECT_FALSE(run.key.key.dump().find("timeout") != std::string::npos)
        << "timeout_s is not in the run key";
  }
  const std::vector<pid_t> children = engine_children(study.parent_path() / "out" / "engine-runs");
  EXPECT_EQ(children.size(), 3u);
  for (const pid_t child : children) EXPECT_FALSE(running(child)) << "engine child " << child;
  fs::remove_all(study.parent_path());
}

}  // namespace
}  // namespace demcal::study
