// `demcal doe` on a tiny study (tests/data/doe-tiny: 2 design points x 2
// replicates of a container with about 400 coarse grains, well under a second
// a run): the store and table it writes, and that they come out the same
// whether the campaign runs on 1 or 2 threads, is stopped and resumed, is
// killed with SIGKILL and restarted, or is split into shards and merged; that
// failed runs are recorded and not retried; and that bad input is refused with
// file:line before the store is touched.
#include "config/design_config.hpp"
#include "cli/doe_command.hpp"
#include "study/doe_plan.hpp"
#include "study/run_store.hpp"
#include "config/study_config.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace demcal::cli {
namespace {

using namespace demcal::config;
using namespace demcal::study;

namespace fs = std::filesystem;

const fs::path kStudy = fs::path(DEMCAL_SOURCE_DIR) / "tests/data/doe-tiny/study.toml";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("demcal-doe-" + name + "-" + std::to_string(getpid()));
  fs::remove_all(dir);
  return dir;
}

DoeOptions options_for(const fs::path& output, int jobs = 2) {
  DoeOptions o;
  o.study = kStudy;
  o.output_dir = output;
  o.jobs = jobs;
  o.quiet = true;
  return o;
}

DoeOutcome run(const DoeOptions& o) {
  std::ostringstream sink;
  return run_doe(o, sink, sink);
}

// A run record without what depends on the clock or the path it was run as.
nlohmann::json without_clock(nlohmann::json j) {
  j.erase("written_utc");
  j.erase("config_file");
  j["results"].erase("wall_time_s");
  j["results"].erase("particle_steps_per_s");
  return j;
}

// The store's run files by name, parsed (and every name a valid run file).
std::map<std::string, nlohmann::json> store_of(const fs::path& output) {
  std::map<std::string, nlohmann::json> files;
  const fs::path runs = output / "doe-tiny" / "runs";
  if (!fs::exists(runs)) return files;
  for (const auto& e : fs::directory_iterator(runs)) {
    const std::string name = e.path().filename().string();
    if (name.front() == '.') continue;  // a temporary: not part of the store
    files[name] = without_clock(nlohmann::json::parse(slurp(e.path())));
  }
  return files;
}

void expect_same_store(const fs::path& a, const fs::path& b) {
  const auto sa = store_of(a), sb = store_of(b);
  ASSERT_EQ(sa.size(), sb.size());
  for (const auto& [name, record] : sa) {
    ASSERT_TRUE(sb.count(name)) << name;
    EXPECT_EQ(record, sb.at(name)) << name;
  }
}

// One uninterrupted campaign on two threads, shared by the tests that compare with it.
class DoeCommandTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    reference_ = new fs::path(fresh_dir("reference"));
    reference_outcome_ = new DoeOutcome(run(options_for(*reference_, 2)));
  }
  static void TearDownTestSuite() {
    fs::remove_all(*reference_);
    delete reference_;
    delete reference_outcome_;
  }
  static fs::path* reference_;
  static DoeOutcome* reference_outcome_;
};
fs::path* DoeCommandTest::reference_ = nullptr;
DoeOutcome* DoeCommandTest::reference_outcome_ = nullptr;

TEST_F(DoeCommandTest, RunsEveryPointAndReplicateIntoTheStoreAndTable) {
  const DoeOutcome& r = *reference_outcome_;
  EXPECT_EQ(r.rows, 4u);
  EXPECT_EQ(r.runs, 4u);
  EXPECT_EQ(r.executed, 4u);
  EXPECT_EQ(r.failed, 0u);
  EXPECT_TRUE(r.complete());
  const auto store = store_of(*reference_);
  ASSERT_EQ(store.size(), 4u);
  for (const auto& [name, record] : store) {
    EXPECT_EQ(name, record["design"]["hash"].get<std::string>() + ".json");
    EXPECT_EQ(record["design"]["status"], "ok");
    EXPECT_EQ(record["apparatus"], "rectangular_container");
    EXPECT_EQ(record["seed"], record["design"]["seed"]);
    EXPECT_FALSE(record["inputs"].contains("design"));
    EXPECT_FALSE(record["inputs"].contains("output"));
    // The design value reached the run through the override.
    EXPECT_EQ(record["inputs"]["interaction"]["particle_particle"]["rolling_friction"],
              record["design"]["parameters"]["mu_r"]);
  }

  // Table: header, rows in (point, replicate, apparatus) order, seeds study.seed + replicate.
  std::istringstream csv(slurp(r.table_csv));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line,
            "point,replicate,seed,apparatus,mu_r,angle_of_repose_deg,discharge_time_s,"
            "mass_flow_rate_kg_s,bulk_density_kg_m3,discharge_t25_s,discharge_t50_s,discharge_t75_s,status,hash");
  const std::vector<std::string> expected_heads = {
      "0,0,1,rectangular_container,0.1,", "0,1,2,rectangular_container,0.1,",
      "1,0,1,rectangular_container,0.4,", "1,1,2,rectangular_container,0.4,"};
  std::set<std::string> hashes;
  for (const std::string& head : expected_heads) {
    ASSERT_TRUE(std::getline(csv, line));
    EXPECT_EQ(line.substr(0, head.size()), head) << line;
    EXPECT_NE(line.find(",,,,ok,"), std::string::npos) << "AoR measured, the rest empty: " << line;
    hashes.insert(line.substr(line.rfind(',') + 1));
  }
  EXPECT_FALSE(std::getline(csv, line));
  EXPECT_EQ(hashes.size(), 4u);
  for (const std::string& h : hashes) EXPECT_TRUE(store.count(h + ".json")) << h;

  const auto table = nlohmann::json::parse(slurp(r.table_json));
  EXPECT_EQ(table["design"]["kind"], "full_factorial");
  EXPECT_EQ(table["rows"].size(), 4u);
  EXPECT_EQ(table["summary"]["ok"], 4);
}

TEST_F(DoeCommandTest, ASecondRunReusesEveryRunAndRewritesTheSameTable) {
  const std::string csv = slurp(reference_outcome_->table_csv);
  const auto before = store_of(*reference_);
  const DoeOutcome again = run(options_for(*reference_, 2));
  EXPECT_EQ(again.executed, 0u);
  EXPECT_EQ(again.reused, 4u);
  EXPECT_EQ(slurp(again.table_csv), csv);
  EXPECT_EQ(store_of(*reference_), before);
}

TEST_F(DoeCommandTest, AnotherStudyOfTheSameApparatusSharesTheRunStore) {
  // [study] is not in a run's hash: a study renamed (a variant, a concealed-
  // effect study, a diagnosis' derived study) pointed at the same store runs nothing.
  const fs::path dir = fresh_dir("shared");
  DoeOptions o = options_for(dir, 2);
  o.overrides = {"study.name=doe-tiny-variant"};
  o.run_store = *reference_ / "doe-tiny" / "runs";
  const auto before = store_of(*reference_);
  const DoeOutcome r = run(o);
  EXPECT_EQ(r.executed, 0u);
  EXPECT_EQ(r.reused, 4u);
  EXPECT_EQ(r.runs_dir, o.run_store);
  EXPECT_EQ(r.study_dir, dir / "doe-tiny-variant");
  EXPECT_FALSE(fs::exists(dir / "doe-tiny-variant" / "runs"));
  EXPECT_EQ(slurp(r.table_csv), slurp(reference_outcome_->table_csv));
  EXPECT_EQ(store_of(*reference_), before);
  fs::remove_all(dir);
}

TEST_F(DoeCommandTest, OneJobAndTwoJobsGiveTheSameStore) {
  const fs::path dir = fresh_dir("jobs1");
  const DoeOutcome r = run(options_for(dir, 1));
  EXPECT_EQ(r.executed, 4u);
  expect_same_store(dir, *reference_);
  EXPECT_EQ(slurp(r.table_csv), slurp(reference_outcome_->table_csv));
  fs::remove_all(dir);
}

TEST_F(DoeCommandTest, StoppedHalfwayAndResumedEqualsUninterruptedAndRerunsNothing) {
  const fs::path dir = fresh_dir("resume");
  DoeOptions o = options_for(dir, 2);
  o.stop_after = 2;  // the other worker's run in progress is abandoned
  const DoeOutcome first = run(o);
  EXPECT_EQ(first.executed, 2u);
  EXPECT_EQ(first.not_run, 2u);
  EXPECT_FALSE(first.complete());
  EXPECT_EQ(first.missing, 2u) << "the table says which rows have no result yet";
  EXPECT_EQ(store_of(dir).size(), 2u);

  o.stop_after.reset();
  const DoeOutcome second = run(o);
  EXPECT_EQ(second.reused, 2u);
  EXPECT_EQ(second.executed, 2u);
  EXPECT_TRUE(second.complete());
  for (const std::string& h : second.executed_hashes)
    EXPECT_EQ(std::count(first.executed_hashes.begin(), first.executed_hashes.end(), h), 0)
        << h << " ran twice";
  expect_same_store(dir, *reference_);
  EXPECT_EQ(slurp(second.table_csv), slurp(reference_outcome_->table_csv));
  fs::remove_all(dir);
}

TEST_F(DoeCommandTest, CancellationAbandonsRunsInProgressWithoutATrace) {
  const fs::path dir = fresh_dir("cancel");
  std::atomic<bool> cancel{false};
  DoeOptions o = options_for(dir, 2);
  o.cancel = &cancel;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    cancel = true;
  });
  const DoeOutcome r = run(o);
  stopper.join();
  EXPECT_EQ(r.executed + r.not_run, 4u);
  EXPECT_GT(r.not_run, 0u);
  // Nothing half-written: every file there is a whole record.
  const RunStore store(dir / "doe-tiny" / "runs");
  for (const auto& [name, record] : store_of(dir))
    EXPECT_TRUE(store.load(record["design"]["hash"], record["design"]["digest"])) << name;
  fs::remove_all(dir);
}

TEST_F(DoeCommandTest, ShardsMergedEqualTheFullStore) {
  const fs::path a = fresh_dir("shard0"), b = fresh_dir("shard1"), merged = fresh_dir("merged");
  DoeOptions o = options_for(a, 1);
  o.shard = Shard{0, 2};
  const DoeOutcome ra = run(o);
  o.output_dir = b;
  o.shard = Shard{1, 2};
  const DoeOutcome rb = run(o);
  EXPECT_EQ(ra.executed, 2u);
  EXPECT_EQ(rb.executed, 2u);
  EXPECT_TRUE(ra.table_csv.empty()) << "a shard writes no table";
  // Merging is copying files together.
  fs::create_directories(merged / "doe-tiny" / "runs");
  for (const fs::path& part : {a, b})
    for (const auto& e : fs::directory_iterator(part / "doe-tiny" / "runs"))
      fs::copy_file(e.path(), merged / "doe-tiny" / "runs" / e.path().filename());
  expect_same_store(merged, *reference_);
  DoeOptions collect = options_for(merged);
  collect.collect = true;
  const DoeOutcome rc = run(collect);
  EXPECT_EQ(rc.executed, 0u);
  EXPECT_TRUE(rc.complete());
  EXPECT_EQ(slurp(rc.table_csv), slurp(reference_outcome_->table_csv));
  for (const fs::path& d : {a, b, merged}) fs::remove_all(d);
}

TEST_F(DoeCommandTest, KilledProcessRestartedEndsWithTheSameStore) {
  const fs::path dir = fresh_dir("sigkill");
  const fs::path runs = dir / "doe-tiny" / "runs";
  const std::string exe = DEMCAL_EXECUTABLE;
  std::vector<std::string> args = {exe,     "doe",    kStudy.string(), "--output",
                                   dir.string(), "--jobs", "1",   "--quiet"};
  std::vector<char*> argv;
  for (auto& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  pid_t child = 0;
  ASSERT_EQ(posix_spawn(&child, exe.c_str(), nullptr, nullptr, argv.data(), environ), 0);
  // Kill it as soon as the first run file appears (a run is well under a second).
  auto count_runs = [&] {
    std::size_t n = 0;
    std::error_code ec;
    if (fs::exists(runs, ec))
      for (const auto& e : fs::directory_iterator(runs, ec))
        if (e.path().extension() == ".json" && e.path().filename().string().front() != '.') ++n;
    return n;
  };
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(300);
  while (count_runs() == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_EQ(kill(child, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the child finished before it was killed";
  const std::size_t survived = count_runs();
  ASSERT_GE(survived, 1u);
  ASSERT_LT(survived, 4u);

  const DoeOutcome resumed = run(options_for(dir, 2));
  EXPECT_EQ(resumed.reused, survived);
  EXPECT_EQ(resumed.executed, 4u - survived);
  expect_same_store(dir, *reference_);
  EXPECT_EQ(slurp(resumed.table_csv), slurp(reference_outcome_->table_csv));
  for (const auto& e : fs::directory_iterator(runs))
    EXPECT_NE(e.path().filename().string().front(), '.') << "the killed writer's temporary was cleaned up";
  fs::remove_all(dir);
}

// The tiny study with another [design] table.
fs::path study_with_design(const std::string& name, const std::string& design) {
  const std::string text = slurp(kStudy);
  const fs::path dir = fresh_dir(name);
  fs::create_directories(dir);
  const fs::path p = dir / "study.toml";
  std::ofstream(p) << text.substr(0, text.find("[design]")) << design;
  return p;
}

TEST(DoeFailedRuns, AreRecordedAndNotRetriedUnlessAsked) {
  // A time step of a whole Rayleigh time is unstable within a few hundred steps.
  const fs::path study = study_with_design("failing", R"([design]
kind = "full_factorial"
parameters = { "protocol.time_step_fraction_of_rayleigh" = { lower = 0.5, upper = 1.0, levels = 2 } }
)");
  const fs::path out = study.parent_path() / "out";
  DoeOptions o = options_for(out);
  o.study = study;
  o.apparatus = {"rectangular_container"};
  // A fast failure: only the unstable point runs to its failure; the stable one is cut short.
  o.overrides = {"protocol.max_flow_s=0.15"};
  const DoeOutcome first = run(o);
  EXPECT_EQ(first.executed, 2u);
  EXPECT_EQ(first.failed, 1u);
  EXPECT_TRUE(first.complete()) << "a failed run is a result";
  const std::string csv = slurp(first.table_csv);
  EXPECT_NE(csv.find(",1,rectangular_container,1,,,,,,,,failed,"), std::string::npos) << csv;
  const auto table = nlohmann::json::parse(slurp(first.table_json));
  EXPECT_NE(table["rows"][1]["error"].get<std::string>().find("unstable"), std::string::npos);

  const DoeOutcome again = run(o);
  EXPECT_EQ(again.executed, 0u);
  EXPECT_EQ(again.reused, 2u);
  o.retry_failed = true;
  const DoeOutcome retried = run(o);
  EXPECT_EQ(retried.executed, 1u);
  EXPECT_EQ(retried.failed, 1u);
  fs::remove_all(study.parent_path());
}

TEST(DoeBadInput, IsRefusedWithFileLineAndKeyBeforeTheStoreIsTouched) {
  const fs::path good = study_with_design("bad-input", R"([design]
kind = "full_factorial"
parameters = { mu_r = { lower = 0.1, upper = 0.4, levels = 2 } }
)");
  const fs::path out = good.parent_path() / "out";
  // A store with a file in it that must survive.
  const fs::path runs = out / "doe-tiny" / "runs";
  fs::create_directories(runs);
  std::ofstream(runs / "0123456789abcdef.json") << "{}";

  auto error_of = [&](const std::string& design, std::vector<std::string> overrides = {}) {
    const fs::path p = study_with_design("bad-input-case", design);
    DoeOptions o = options_for(out);
    o.study = p;
    o.overrides = std::move(overrides);
    std::string message;
    try {
      run(o);
    } catch (const ConfigError& e) {
      message = e.what();
    }
    fs::remove_all(p.parent_path());
    return message;
  };
  const std::string header = "[design]\nkind = \"full_factorial\"\n";
  // The [design] table starts on the line after the study's other tables.
  const std::string text = slurp(kStudy);
  const std::size_t design_line =
      static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(text.find("[design]")), '\n')) + 1;
  const std::string params_line = ":" + std::to_string(design_line + 2) + ": ";

  std::string m = error_of(header + "parameters = { mu_r = { lower = 0.4, upper = 0.1, levels = 2 } }\n");
  EXPECT_NE(m.find(params_line + "design.parameters.mu_r.upper: expected a number > lower"),
            std::string::npos) << m;
  m = error_of(header + "parameters = { mu_r = { lower = 0.1, upper = 0.4, levels = 1 } }\n");
  EXPECT_NE(m.find(params_line + "design.parameters.mu_r.levels: expected an integer >= 2"),
            std::string::npos) << m;
  m = error_of("[design]\nkind = \"latin_hypercube\"\nparameters = { mu_r = { lower = 0.1, upper = 0.4 } }\n");
  EXPECT_NE(m.find(":" + std::to_string(design_line) + ": design.points: missing required key"),
            std::string::npos) << m;
  m = error_of(header + "parameters = { mu_x = { lower = 0.1, upper = 0.4, levels = 2 } }\n");
  EXPECT_NE(m.find(params_line + "design.parameters.mu_x: lower = 0.1 is refused: mu_x: unknown key"),
            std::string::npos) << m;
  m = error_of(header + "parameters = { mu_r = { lower = -0.1, upper = 0.4, levels = 2 } }\n");
  EXPECT_NE(m.find(params_line + "design.parameters.mu_r: lower = -0.1 is refused: "
                                 "interaction.particle_particle.rolling_friction: expected a number >= 0"),
            std::string::npos) << m;
  m = error_of(header + "parameters = { \"apparatus.rectangular_container.fill_mass_kg\" = "
                        "{ lower = 0.04, upper = 0.2, levels = 2 } }\n");
  EXPECT_NE(m.find(params_line + "design.parameters.\"apparatus.rectangular_container.fill_mass_kg\": "
                                 "upper = 0.2 is refused"),
            std::string::npos) << m;
  m = error_of(header + "parameters = { \"study.seed\" = { lower = 1, upper = 4, levels = 2 } }\n");
  EXPECT_NE(m.find("cannot vary [study] keys"), std::string::npos) << m;
  m = error_of(header + "colour = 3\nparameters = { mu_r = { lower = 0.1, upper = 0.4, levels = 2 } }\n");
  EXPECT_NE(m.find(":" + std::to_string(design_line + 2) + ": design.colour: unknown key"),
            std::string::npos) << m;
  m = error_of("[design]\nkind = \"sobol\"\npoints = 4\n"
               "parameters = { mu_r = { lower = 0.1, upper = 0.4, levels = 3 } }\n");
  EXPECT_NE(m.find("design.parameters.mu_r.levels: applies only to kind = \"full_factorial\""),
            std::string::npos) << m;
  // A list design: every point has one value per parameter, inside the bounds.
  const std::string list = "[design]\nkind = \"list\"\nparameters = { mu_r = { lower = 0.1, upper = 0.4 } }\n";
  m = error_of(list + "values = [[0.2], [0.5]]\n");
  EXPECT_NE(m.find("design.values[1]: mu_r = 0.5 is outside its bounds [0.1, 0.4]"), std::string::npos) << m;
  m = error_of(list + "values = [[0.2, 0.3]]\n");
  EXPECT_NE(m.find("design.values[0]: expected 1 numbers"), std::string::npos) << m;
  m = error_of(list);
  EXPECT_NE(m.find("design.values: expected an array of points"), std::string::npos) << m;
  m = error_of(header + "values = [[0.2]]\nparameters = { mu_r = { lower = 0.1, upper = 0.4, levels = 2 } }\n");
  EXPECT_NE(m.find("design.values: applies only to kind = \"list\""), std::string::npos) << m;
  // An override (as for simulate) is checked like the file.
  m = error_of(header + "parameters = { mu_r = { lower = 0.1, upper = 0.4, levels = 2 } }\n",
               {"material.colour=3"});
  EXPECT_NE(m.find("material.colour: unknown key"), std::string::npos) << m;
  // A study without [design].
  m = error_of("");
  EXPECT_NE(m.find("design: the study has no [design] table"), std::string::npos) << m;

  // A missing file.
  DoeOptions missing = options_for(out);
  missing.study = good.parent_path() / "no-such-study.toml";
  EXPECT_THROW(run(missing), ConfigError);

  // Nothing in the store was touched, and no table was written.
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(runs)) {
    ++files;
    EXPECT_EQ(slurp(e.path()), "{}");
  }
  EXPECT_EQ(files, 1u);
  EXPECT_FALSE(fs::exists(out / "doe-tiny" / "doe.csv"));
  fs::remove_all(good.parent_path());
}

TEST(DoePlanTest, RowsSeedsAndHashesFollowTheStatedRules) {
  const fs::path study = study_with_design("plan", R"([design]
kind = "latin_hypercube"
points = 3
replicates = 2
seed = 7
parameters = { mu_s = { lower = 0.3, upper = 0.7 }, mu_r = { lower = 0.1, upper = 0.4 } }
)");
  const DoePlan plan = plan_doe(study, {}, {}, 1);
  ASSERT_EQ(plan.rows.size(), 6u);
  ASSERT_EQ(plan.runs.size(), 6u);
  // Columns in the order written, not alphabetical.
  EXPECT_EQ(plan.design.spec.parameters[0].name, "mu_s");
  EXPECT_EQ(plan.design.parameter_paths[1], "interaction.particle_particle.rolling_friction");
  for (std::size_t i = 0; i < plan.rows.size(); ++i) {
    EXPECT_EQ(plan.rows[i].point, i / 2);
    EXPECT_EQ(plan.rows[i].replicate, static_cast<int>(i % 2));
    EXPECT_EQ(plan.rows[i].seed, 1u + i % 2) << "study.seed + replicate";
  }
  // The same plan made again, and with more threads per run.
  const DoePlan again = plan_doe(study, {}, {}, 1);
  const DoePlan two_threads = plan_doe(study, {}, {}, 2);
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    EXPECT_EQ(again.runs[i].key.digest, plan.runs[i].key.digest);
    EXPECT_NE(two_threads.runs[i].key.digest, plan.runs[i].key.digest);
  }
  // The run built for a row is the study with its values, seed and threads set.
  const StudyConfig built = build_study(run_document(plan, plan.runs[3]));
  EXPECT_EQ(built.protocol.seed, 2u);
  EXPECT_EQ(built.material.particle_particle.sliding_friction, plan.generated.points[1][0]);
  EXPECT_EQ(built.material.particle_particle.rolling_friction, plan.generated.points[1][1]);
  fs::remove_all(study.parent_path());
}

TEST(DoePlanTest, AParameterAlsoSetsTheKeysTiedToIt) {
  // One physical quantity written in two places (the grains' and the walls'
  // surface energy): also_sets gives the other key the parameter's value.
  const fs::path study = study_with_design("tied", R"([design]
kind = "list"
values = [[0.002], [0.004]]
parameters = { surface_energy = { lower = 0.0, upper = 0.005, also_sets = ["surface_energy_wall"] } }
)");
  {
    std::string text = slurp(study);
    text.replace(text.find("rolling = \"cdt\""), 15, "rolling = \"cdt\"\nadhesion = \"jkr\"");
    for (const std::string table : {"[interaction.particle_particle]\n", "[interaction.particle_wall]\n"})
      text.insert(text.find(table) + table.size(), "surface_energy_j_m2 = 0.0\n");
    std::ofstream(study) << text;
  }
  const DoePlan plan = plan_doe(study, {}, {}, 1);
  ASSERT_EQ(plan.design.tied_paths.at(0), std::vector<std::string>{"interaction.particle_wall.surface_energy_j_m2"});
  const toml::table t = run_document(plan, plan.runs[1]).table;
  EXPECT_EQ(t.at_path("interaction.particle_particle.surface_energy_j_m2").value<double>(), 0.004);
  EXPECT_EQ(t.at_path("interaction.particle_wall.surface_energy_j_m2").value<double>(), 0.004);
  fs::remove_all(study.parent_path());
  // A tie to a [study] key, or to the parameter itself, is refused at its line.
  const fs::path bad = study_with_design("tied-bad", R"([design]
kind = "list"
values = [[0.3]]
parameters = { mu_s = { lower = 0.1, upper = 0.9, also_sets = ["mu_s"] } }
)");
  try {
    plan_doe(bad, {}, {}, 1);
    ADD_FAILURE() << "a tie of a parameter to itself was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("design.parameters.mu_s.also_sets"), std::string::npos) << e.what();
  }
  fs::remove_all(bad.parent_path());
}

TEST(DoePlanTest, RowsWithIdenticalInputsShareOneRun) {
  // A second apparatus, and a design over its orifice only: the container's
  // runs do not depend on it, so its rows of a replicate share one run.
  const fs::path study = study_with_design("shared", R"(
[apparatus.sandglass]
upper_diameter_m = 0.08
upper_height_m = 0.13
bottom = "conical"
hopper_half_angle_deg = 30.0
orifice_diameter_m = 0.03
fill_mass_kg = 0.34
lower_diameter_m = 0.2
drop_height_m = 0.08
slice = true
slice_thickness_diameters = 4.2
coarse_graining_factor = 6.0
shear_modulus_pa = 1.0e7

[design]
kind = "full_factorial"
parameters = { "apparatus.sandglass.orifice_diameter_m" = { lower = 0.025, upper = 0.035, levels = 3 } }
)");
  const DoePlan container = plan_doe(study, {}, {"rectangular_container"}, 1);
  EXPECT_EQ(container.rows.size(), 3u);
  EXPECT_EQ(container.runs.size(), 1u);
  const DoePlan both = plan_doe(study, {}, {}, 1);
  EXPECT_EQ(both.rows.size(), 6u);
  EXPECT_EQ(both.runs.size(), 4u);
  EXPECT_EQ(both.apparatus, (std::vector<std::string>{"rectangular_container", "sandglass"}));
  EXPECT_EQ(both.runs[both.rows[0].run].key.digest, container.runs[0].key.digest);
  fs::remove_all(study.parent_path());
}

}  // namespace
}  // namespace demcal::cli
