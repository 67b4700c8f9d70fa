// A design run on another engine ([engine], study/engine_evaluator.hpp),
// proved without LIGGGHTS: tests/data/engines/fake_engine.sh stands in for it
// (a log naming it, a final dump whose heap slope follows the deck's rolling
// friction). The runs land in the run store with the engine in the key and
// in the record, and demcal's own measurement reads the dump; for demcal's own
// engine the keys are what they were without [engine].
#include "config/study_config.hpp"
#include "study/design_runner.hpp"
#include "study/doe_plan.hpp"
#include "study/engine_evaluator.hpp"
#include "study/run_store.hpp"
#include "study/simulation_run.hpp"
#include "tests/support/study_text.hpp"
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace demcal::study {
namespace {

namespace fs = std::filesystem;
using config::ConfigError;

const std::string kFake = std::string(DEMCAL_SOURCE_DIR) + "/tests/data/engines/fake_engine.sh";

std::string study_text(const std::string& engine, const std::string& extra = "") {
  return R"([study]
name = "engine-dispatch"
seed = 1

)" + testing::sand_and_glass_tables() +
         extra + testing::small_container_design_tables() + engine;
}

fs::path write_study(const std::string& name, const std::string& text) {
  const fs::path dir = testing::fresh_dir("engine-dispatch", name);
  testing::spit(dir / "study.toml", text);
  return dir / "study.toml";
}

std::string fake_engine() {
  return "\n[engine]\nkind = \"liggghts\"\nlaunch = \"" + kFake + "\"\n";
}

TEST(EngineDispatch, AFakeEngineRunsTheDesignIntoTheStoreAndDemcalMeasuresIt) {
  const fs::path study = write_study("fake", study_text(fake_engine()));
  const DoePlan plan = plan_doe(study, {}, {}, 1);
  ASSERT_EQ(plan.runs.size(), 3u);
  for (const PlannedRun& run : plan.runs) {
    ASSERT_TRUE(run.key.key.contains("engine")) << run.key.key.dump();
    EXPECT_EQ(run.key.key["engine"]["kind"], "liggghts");
    EXPECT_EQ(run.key.key["engine"]["version"],
              "LIGGGHTS (Version fake-engine 1.0 for demcal's tests)");
    EXPECT_FALSE(run.key.key["inputs"].contains("engine")) << "the launch line is not in the key";
    // Runs made from an older deck writer are not reused (engines/deck.hpp).
    EXPECT_EQ(run.key.key["engine"]["deck_revision"], 2);
  }
  const RunStore store(study.parent_path() / "out" / "runs");
  DesignRunOptions options;
  options.jobs = 2;
  DesignRunner runner(plan, store, options);
  SilentObserver quiet;
  const DesignRunResult done = runner.run(quiet);
  EXPECT_EQ(done.executed, 3u);
  EXPECT_EQ(done.failed, 0u);

  double previous = 0.0;
  for (const PlannedRun& run : plan.runs) {
    const auto record = store.load(run.key.hash, run.key.digest);
    ASSERT_TRUE(record.has_value()) << run.key.hash;
    const nlohmann::json& r = *record;
    ASSERT_EQ(r["design"]["status"], "ok") << r["results"].dump();
    EXPECT_EQ(r["engine"]["name"], "liggghts");
    EXPECT_EQ(r["engine"]["launch"], kFake);
    EXPECT_NE(r["engine"]["version"].get<std::string>().find("fake-engine"), std::string::npos);
    EXPECT_TRUE(fs::exists(fs::path(r["engine"]["directory"].get<std::string>()) / "in.demcal"));
    // The mapping the deck was written with is in the record: demcal's cdt
    // mu_r is LIGGGHTS's 2 mu_r between equal spheres.
    const double mu_r = r["design"]["parameters"]["mu_r"].get<double>();
    double mapped = -1.0;
    for (const auto& p : r["engine_deck"]["mapping"]["parameters"])
      if (p["pair"] == "particle-particle" && p["engine_name"] == "coefficientRollingFriction")
        mapped = p["value"].get<double>();
    EXPECT_NEAR(mapped, 2.0 * mu_r, 1e-12);
    // demcal measured the fake's heap, whose flanks rise at atan(0.3 + mapped).
    ASSERT_TRUE(r["observables"]["angle_of_repose_deg"].is_number()) << r["details"].dump();
    const double aor = r["observables"]["angle_of_repose_deg"].get<double>();
    const double expected = std::atan(0.3 + mapped) * 180.0 / std::numbers::pi;
    EXPECT_NEAR(aor, expected, 2.0) << "mu_r " << mu_r;
    EXPECT_GT(aor, previous);
    previous = aor;
    EXPECT_GT(r["time_step_s"].get<double>(), 0.0);
  }
  // Run again: every run is found in the store, none is redone.
  const DoePlan again = plan_doe(study, {}, {}, 1);
  DesignRunner second(again, store, options);
  EXPECT_EQ(second.share().reused, 3u);
  EXPECT_TRUE(second.share().queue.empty());
  fs::remove_all(study.parent_path());
}

TEST(EngineDispatch, DemcalsOwnEngineKeepsTheRunKeysItHadWithoutEngineTable) {
  const fs::path absent = write_study("absent", study_text(""));
  const fs::path named = write_study("named", study_text("\n[engine]\nkind = \"demcal\"\n"));
  const DoePlan a = plan_doe(absent, {}, {}, 1);
  const DoePlan b = plan_doe(named, {}, {}, 1);
  ASSERT_EQ(a.runs.size(), b.runs.size());
  for (std::size_t i = 0; i < a.runs.size(); ++i) {
    EXPECT_EQ(a.runs[i].key.digest, b.runs[i].key.digest);
    EXPECT_FALSE(a.runs[i].key.key.contains("engine"));
  }
  // The other engine's keys differ from demcal's: its runs are other runs.
  const fs::path fake = write_study("other", study_text(fake_engine()));
  const DoePlan c = plan_doe(fake, {}, {}, 1);
  EXPECT_NE(c.runs[0].key.digest, a.runs[0].key.digest);
  for (const fs::path& p : {absent, named, fake}) fs::remove_all(p.parent_path());
}

std::string plan_error(const std::string& name, const std::string& text) {
  const fs::path study = write_study(name, text);
  std::string message;
  try {
    plan_doe(study, {}, {}, 1);
  } catch (const ConfigError& e) {
    message = e.what();
  }
  fs::remove_all(study.parent_path());
  return message;
}

TEST(EngineDispatch, WhatTheEngineCannotDoIsRefusedByNameBeforeAnythingRuns) {
  // A wall group with its own interaction: the decks have one wall material.
  const std::string group = plan_error(
      "group",
      study_text(fake_engine(), "\n[interaction.particle_wall.floor]\nsliding_friction = 0.2\n"));
  EXPECT_NE(group.find("engine.kind"), std::string::npos) << group;
  EXPECT_NE(group.find("wall group \"floor\""), std::string::npos) << group;
  // A command that is no DEM engine.
  std::string text = study_text(fake_engine());
  text.replace(text.find(kFake), kFake.size(), "/bin/true");
  const std::string not_engine = plan_error("true", text);
  EXPECT_NE(not_engine.find("engine.launch"), std::string::npos) << not_engine;
  EXPECT_NE(not_engine.find("names no LAMMPS or LIGGGHTS version"), std::string::npos)
      << not_engine;
  // The launch line starts another engine than the kind says.
  std::string other = study_text(fake_engine());
  other.replace(other.find(kFake), kFake.size(), "env DEMCAL_FAKE_ENGINE_NAME=LAMMPS " + kFake);
  const std::string mismatch = plan_error("mismatch", other);
  EXPECT_NE(mismatch.find("does not start liggghts"), std::string::npos) << mismatch;
  // LAMMPS has no counterpart of demcal's cdt rolling torque.
  std::string lammps = study_text(fake_engine());
  lammps.replace(lammps.find("kind = \"liggghts\""), 17, "kind = \"lammps\"");
  const std::string cdt = plan_error("cdt", lammps);
  EXPECT_NE(cdt.find("\"lammps\" cannot run apparatus \"rectangular_container\""),
            std::string::npos)
      << cdt;
  EXPECT_NE(cdt.find("cdt"), std::string::npos) << cdt;
}

TEST(EngineDispatch, AStatedSubstitutionLetsLammpsRunAndIsInTheKey) {
  // LAMMPS with demcal's cdt rolling: refused above; with allow_rolling_substitute the deck is
  // written with "rolling sds", and the run key says so (another deck, other runs).
  const std::string launch = "env DEMCAL_FAKE_ENGINE_NAME=LAMMPS " + kFake;
  const std::string base = "\n[engine]\nkind = \"lammps\"\nlaunch = \"" + launch + "\"\n";
  const fs::path study =
      write_study("substitute", study_text(base + "allow_rolling_substitute = true\n"));
  const DoePlan plan = plan_doe(study, {}, {}, 1);
  ASSERT_FALSE(plan.runs.empty());
  const nlohmann::json& engine = plan.runs[0].key.key.at("engine");
  EXPECT_EQ(engine.at("kind"), "lammps");
  EXPECT_EQ(engine.at("allow_rolling_substitute"), true);
  EXPECT_FALSE(engine.contains("allow_dry_walls")) << "absent when off";
  fs::remove_all(study.parent_path());
  // Only LAMMPS's mapping makes these substitutions: on another kind the key is refused.
  const std::string liggghts =
      plan_error("dry-walls-liggghts", study_text(fake_engine() + "allow_dry_walls = true\n"));
  EXPECT_NE(liggghts.find("engine.allow_dry_walls: is for kind = \"lammps\" only"),
            std::string::npos)
      << liggghts;
}

TEST(EngineDispatch, SimulateRunsTheStudysEngineToo) {
  // `demcal simulate` on a study whose [engine] is another engine runs that engine, as
  // `doe` does; before, it silently ran demcal's own DEM.
  const fs::path study = write_study("simulate", study_text(fake_engine()));
  SimulationRunOptions o;
  o.config = study;
  o.output_dir = (study.parent_path() / "run").string();
  o.overrides = {"mu_r=0.2"};
  SilentObserver quiet;
  const SimulationRunOutcome out = run_simulation(o, quiet);
  ASSERT_TRUE(fs::exists(out.run_record));
  const nlohmann::json r = nlohmann::json::parse(testing::slurp(out.run_record));
  EXPECT_EQ(out.engine, "liggghts");
  EXPECT_EQ(r["engine"]["name"], "liggghts");
  EXPECT_EQ(r["engine"]["launch"], kFake);
  EXPECT_EQ(r["results"]["stopped_because"], "finished");
  EXPECT_TRUE(fs::exists(study.parent_path() / "run" / "engine-run" / "in.demcal"));
  // demcal measured the fake's heap: flanks at atan(0.3 + 2 mu_r) (LIGGGHTS's cdt mu_r).
  ASSERT_TRUE(out.observables["angle_of_repose_deg"].is_number()) << r["details"].dump();
  EXPECT_NEAR(out.observables["angle_of_repose_deg"].get<double>(),
              std::atan(0.3 + 0.4) * 180.0 / std::numbers::pi, 2.0);
  // A launch line that starts no engine is refused before the output directory is touched.
  std::string text = study_text(fake_engine());
  text.replace(text.find(kFake), kFake.size(), "/bin/true");
  const fs::path bad = write_study("simulate-bad", text);
  o.config = bad;
  o.output_dir = (bad.parent_path() / "run").string();
  EXPECT_THROW(run_simulation(o, quiet), ConfigError);
  EXPECT_FALSE(fs::exists(bad.parent_path() / "run"));
  fs::remove_all(study.parent_path());
  fs::remove_all(bad.parent_path());
}

}  // namespace
}  // namespace demcal::study
