// The engine launcher (engines/engine_process.hpp, engines/engine_run.hpp)
// without a real engine: a shell script stands in for it, and either ends
// (a clean run, an ERROR line and a non-zero status, a crash) or sleeps with a
// child of its own, which a timeout, a cancel flag, a poll that throws or a
// SIGINT to this process must end — the child included.
#include "engines/engine_process.hpp"
#include "engines/engine_run.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <fstream>
#include <string>
#include <thread>

#include <signal.h>
#include <unistd.h>

namespace demcal::engines {
namespace {

namespace fs = std::filesystem;

// Takes the engine's command line; what it does is the deck's only word.
const char* const kFakeEngine = R"SH(#!/bin/sh
deck=""; log="log.engine"
while [ $# -gt 0 ]; do
  case "$1" in
    -in) deck="$2"; shift 2 ;;
    -log) log="$2"; shift 2 ;;
    *) shift ;;
  esac
done
echo "LAMMPS (fake engine for the launcher test)" > "$log"
case "$(cat "$deck")" in
  ok) echo "ran" > final.dump ;;
  fail) echo "ERROR: Lost atoms: original 10 current 9 (fake)" >> "$log"
        echo "Last command: run 1000" >> "$log"; exit 3 ;;
  crash) kill -SEGV $$ ;;
  sleep) sleep 60 & echo $! > child.pid; wait ;;
  stubborn) trap '' TERM; sleep 60 & echo $! > child.pid; wait ;;
esac
)SH";

// A scratch folder with the fake engine in it, removed when the test ends.
struct Fixture {
  explicit Fixture(const std::string& name) : dir(testing::fresh_dir("engine-process", name)) {
    testing::spit(dir / "fake_engine.sh", kFakeEngine);
    launch.command = "sh '" + (dir / "fake_engine.sh").string() + "'";
    launch.grace_period_s = 1.0;
  }
  ~Fixture() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  Fixture(const Fixture&) = delete;
  Fixture& operator=(const Fixture&) = delete;

  fs::path dir;
  EngineLaunch launch;
};

Deck deck_doing(const std::string& what) {
  Deck d;
  d.engine = "lammps";
  d.script_name = "in.test";
  d.script = what;
  d.final_dump_name = "final.dump";
  return d;
}

// Gone, or a zombie waiting for init: either way no longer running.
bool gone(pid_t pid) {
  for (int i = 0; i < 150; ++i) {
    if (::kill(pid, 0) == -1 && errno == ESRCH) return true;
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    std::getline(stat, line);
    const auto close = line.rfind(')');
    if (close != std::string::npos && close + 2 < line.size() && line[close + 2] == 'Z')
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

pid_t child_pid(const fs::path& run_dir) {
  std::ifstream in(run_dir / "child.pid");
  pid_t pid = 0;
  in >> pid;
  return pid;
}

std::string error_of(const Deck& deck, const EngineLaunch& launch, const fs::path& dir) {
  try {
    run_engine(deck, launch, dir);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(EngineProcess, CleanRunReportsTheVersionAndTheOutput) {
  Fixture f("clean");
  const EngineRunResult r = run_engine(deck_doing("ok"), f.launch, f.dir / "run");
  EXPECT_EQ(r.engine_version, "LAMMPS (fake engine for the launcher test)");
  EXPECT_TRUE(fs::exists(f.dir / "run" / "final.dump"));
  EXPECT_TRUE(fs::exists(f.dir / "run" / "engine.stdout"));
  EXPECT_LT(r.wall_time_s, 10.0);
}

TEST(EngineProcess, ARelativeRunDirectoryWorks) {
  // As `demcal simulate --output out` gives it: relative to demcal's working directory.
  Fixture f("relative");
  const fs::path relative = "demcal-engine-process-relative-" + std::to_string(::getpid());
  fs::remove_all(relative);
  const EngineRunResult r = run_engine(deck_doing("ok"), f.launch, relative / "run");
  EXPECT_TRUE(fs::exists(relative / "run" / "final.dump"));
  EXPECT_TRUE(fs::exists(relative / "run" / "engine.stdout"));
  EXPECT_EQ(r.engine_version, "LAMMPS (fake engine for the launcher test)");
  fs::remove_all(relative);
}

TEST(EngineProcess, NonZeroExitReportsTheLastErrorLine) {
  Fixture f("fail");
  const std::string e = error_of(deck_doing("fail"), f.launch, f.dir / "run");
  EXPECT_NE(e.find("lammps run failed"), std::string::npos) << e;
  EXPECT_NE(e.find("exited with status 3"), std::string::npos) << e;
  EXPECT_NE(e.find("ERROR: Lost atoms: original 10 current 9 (fake)"), std::string::npos) << e;
  EXPECT_NE(e.find(f.launch.command), std::string::npos) << e;
  EXPECT_NE(e.find((f.dir / "run" / "log.engine").string()), std::string::npos) << e;
  EXPECT_NE(e.find((f.dir / "run" / "engine.stdout").string()), std::string::npos) << e;
}

TEST(EngineProcess, DeathBySignalIsReportedByName) {
  Fixture f("crash");
  const std::string e = error_of(deck_doing("crash"), f.launch, f.dir / "run");
  // dash reports its child's death as 128 + N; a shell that execs the line dies itself.
  EXPECT_NE(e.find("SIGSEGV"), std::string::npos) << e;
}

TEST(EngineProcess, TimeoutEndsTheEngineAndItsChild) {
  Fixture f("timeout");
  f.launch.timeout_s = 0.5;
  const auto t0 = std::chrono::steady_clock::now();
  const std::string e = error_of(deck_doing("sleep"), f.launch, f.dir / "run");
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_NE(e.find("timed out after 0.5 s"), std::string::npos) << e;
  EXPECT_NE(e.find(f.launch.command), std::string::npos) << e;
  EXPECT_NE(e.find("log.engine"), std::string::npos) << e;
  EXPECT_LT(took, 5.0);
  const pid_t child = child_pid(f.dir / "run");
  ASSERT_GT(child, 0);
  EXPECT_TRUE(gone(child)) << "the engine's child " << child << " survived the timeout";
}

TEST(EngineProcess, AGroupThatIgnoresSigtermIsKilledAfterTheGracePeriod) {
  Fixture f("stubborn");
  f.launch.timeout_s = 0.3;
  f.launch.grace_period_s = 0.5;
  const auto t0 = std::chrono::steady_clock::now();
  const std::string e = error_of(deck_doing("stubborn"), f.launch, f.dir / "run");
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_NE(e.find("timed out after 0.3 s"), std::string::npos) << e;
  EXPECT_GE(took, 0.75);  // the grace period was waited for
  EXPECT_LT(took, 5.0);
  const pid_t child = child_pid(f.dir / "run");
  ASSERT_GT(child, 0);
  EXPECT_TRUE(gone(child)) << "the engine's child " << child << " survived SIGKILL";
}

TEST(EngineProcess, CancelFlagSetByAnotherThreadEndsTheRun) {
  Fixture f("cancel");
  std::atomic<bool> cancel{false};
  f.launch.cancel = &cancel;
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    cancel = true;
  });
  const std::string e = error_of(deck_doing("sleep"), f.launch, f.dir / "run");
  canceller.join();
  EXPECT_NE(e.find("lammps run stopped"), std::string::npos) << e;
  EXPECT_NE(e.find("cancelled"), std::string::npos) << e;
  const pid_t child = child_pid(f.dir / "run");
  ASSERT_GT(child, 0);
  EXPECT_TRUE(gone(child));
}

struct StopRequested {};  // not a std::exception, as the design runner's RunCancelled

TEST(EngineProcess, AnExceptionFromThePollPassesThroughAfterTheGroupIsEnded) {
  Fixture f("poll");
  const auto t0 = std::chrono::steady_clock::now();
  f.launch.poll = [&] {
    if (std::chrono::steady_clock::now() - t0 > std::chrono::milliseconds(300))
      throw StopRequested{};
  };
  EXPECT_THROW(run_engine(deck_doing("sleep"), f.launch, f.dir / "run"), StopRequested);
  const pid_t child = child_pid(f.dir / "run");
  ASSERT_GT(child, 0);
  EXPECT_TRUE(gone(child));
}

std::atomic<int> g_test_handler_calls{0};
extern "C" void count_sigint(int) { g_test_handler_calls.fetch_add(1); }

TEST(EngineProcess, SigintEndsTheGroupThenReachesTheProcessOwnDisposition) {
  // This process's SIGINT disposition is one that does not end it, so that the
  // launcher's raising the signal again can be observed here.
  struct sigaction mine {
  }, before{};
  mine.sa_handler = count_sigint;
  ::sigemptyset(&mine.sa_mask);
  ASSERT_EQ(::sigaction(SIGINT, &mine, &before), 0);
  g_test_handler_calls = 0;
  Fixture f("sigint");
  std::thread interrupter([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::kill(::getpid(), SIGINT);
  });
  const std::string e = error_of(deck_doing("sleep"), f.launch, f.dir / "run");
  interrupter.join();
  struct sigaction after {};
  ::sigaction(SIGINT, &before, &after);
  EXPECT_NE(e.find("interrupted by SIGINT"), std::string::npos) << e;
  EXPECT_EQ(g_test_handler_calls.load(), 1);  // raised again, once, to the disposition restored
  EXPECT_EQ(after.sa_handler, &count_sigint);
  const pid_t child = child_pid(f.dir / "run");
  ASSERT_GT(child, 0);
  EXPECT_TRUE(gone(child));
}

TEST(EngineProcess, ProcessOutcomeDescribesEachEnd) {
  ProcessOutcome o;
  o.exit_code = 139;
  EXPECT_EQ(o.describe(), "exited with status 139 (the shell's code for SIGSEGV)");
  o.ended = ProcessOutcome::Ended::signalled;
  o.signal = SIGKILL;
  EXPECT_EQ(o.describe(), "killed by SIGKILL");
  EXPECT_EQ(signal_name(40), "signal 40");
  ProcessOptions bad;
  bad.timeout_s = 0.0;
  EXPECT_THROW(run_process(bad), std::invalid_argument);
}

}  // namespace
}  // namespace demcal::engines
