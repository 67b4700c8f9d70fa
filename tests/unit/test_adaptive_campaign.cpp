// The adaptive design as a campaign (study/adaptive_campaign.hpp) on a tiny DEM study
// (tests/data/doe-tiny-adaptive: runs of a few tenths of a second): it ends by its own
// rule and writes doe.csv, doe.json (batch and slot per row) and design_history.json; a
// campaign stopped after k runs and started again ends with the same store, table and
// history as one never interrupted, and makes the same choices; and the keys of
// [design] kind = "adaptive" are read strictly.
#include "cli/doe_command.hpp"
#include "config/doe_csv.hpp"
#include "config/study_config.hpp"
#include "config/toml_reader.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace demcal::cli {
namespace {

namespace fs = std::filesystem;
const fs::path kStudy = fs::path(DEMCAL_SOURCE_DIR) / "tests/data/doe-tiny-adaptive/study.toml";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("demcal-adaptive-" + name + "-" + std::to_string(getpid()));
  fs::remove_all(dir);
  return dir;
}

DoeOutcome run(const fs::path& output, std::optional<std::size_t> stop_after = std::nullopt,
               int jobs = 2) {
  DoeOptions o;
  o.study = kStudy;
  o.output_dir = output;
  o.jobs = jobs;
  o.quiet = true;
  o.stop_after = stop_after;
  std::ostringstream sink;
  return run_doe(o, sink, sink);
}

// The store's run names with their design blocks (the rest depends on the clock).
std::map<std::string, nlohmann::json> store_of(const fs::path& output) {
  std::map<std::string, nlohmann::json> files;
  for (const auto& e : fs::directory_iterator(output / "doe-tiny-adaptive" / "runs")) {
    const std::string name = e.path().filename().string();
    if (name.front() == '.') continue;
    const auto j = nlohmann::json::parse(slurp(e.path()));
    files[name] = {j.at("design"), j.at("observables")};
  }
  return files;
}

TEST(AdaptiveCampaign, EndsByItsRuleAndWritesTableAndHistory) {
  const fs::path out = fresh_dir("whole");
  const DoeOutcome r = run(out);
  EXPECT_TRUE(r.complete());
  const fs::path dir = out / "doe-tiny-adaptive";
  const auto history = nlohmann::json::parse(slurp(dir / "design_history.json"));
  const std::string status = history.at("status").get<std::string>();
  EXPECT_NE(status, "running") << history.dump(1);
  EXPECT_LE(history.at("runs_done").get<int>(), 11);
  EXPECT_GE(history.at("runs_done").get<int>(), 7);
  EXPECT_EQ(history.at("runs_done").get<std::size_t>(), r.rows);
  EXPECT_FALSE(history.at("text").get<std::string>().empty());
  // doe.csv reads back (its seeds are below 2^53), as `demcal fit` reads it.
  const config::DoeCsv csv_table = config::read_doe_csv(dir / "doe.csv");
  EXPECT_EQ(csv_table.rows.size(), r.rows);
  const auto table = nlohmann::json::parse(slurp(dir / "doe.json"));
  EXPECT_EQ(table.at("design").at("kind"), "adaptive");
  for (const auto& row : table.at("rows")) {
    EXPECT_TRUE(row.contains("batch") && row.contains("slot")) << row.dump();
    EXPECT_EQ(row.at("status"), "ok");
  }
  // The run records say which run of the design they are.
  for (const auto& [name, rec] : store_of(out)) {
    EXPECT_EQ(rec[0].at("kind"), "adaptive") << name;
    EXPECT_TRUE(rec[0].contains("batch") && rec[0].contains("slot")) << name;
  }
  // Run again: everything is found in the store, nothing runs, the same files.
  const std::string csv = slurp(dir / "doe.csv"), hist = slurp(dir / "design_history.json");
  const DoeOutcome again = run(out);
  EXPECT_EQ(again.executed, 0u);
  EXPECT_EQ(slurp(dir / "doe.csv"), csv);
  EXPECT_EQ(slurp(dir / "design_history.json"), hist);
  fs::remove_all(out);
}

TEST(AdaptiveCampaign, StoppedAndResumedEqualsUninterrupted) {
  const fs::path whole = fresh_dir("reference"), parts = fresh_dir("resumed");
  const DoeOutcome w = run(whole, std::nullopt, 1);
  ASSERT_TRUE(w.complete());
  // Killed after 3 runs (in the start), again after 3 more (across a batch boundary),
  // then to the end, on another number of threads.
  const DoeOutcome a = run(parts, 3);
  EXPECT_FALSE(a.complete());
  EXPECT_EQ(a.executed, 3u);
  const DoeOutcome b = run(parts, 3);
  EXPECT_EQ(b.executed, 3u);
  const DoeOutcome c = run(parts);
  EXPECT_TRUE(c.complete());
  EXPECT_EQ(a.executed + b.executed + c.executed, w.executed);
  EXPECT_EQ(store_of(whole), store_of(parts));
  for (const char* f : {"doe.csv", "doe.json", "design_history.json"})
    EXPECT_EQ(slurp(whole / "doe-tiny-adaptive" / f), slurp(parts / "doe-tiny-adaptive" / f)) << f;
  fs::remove_all(whole);
  fs::remove_all(parts);
}

// The tiny study with an adaptive [design] over mu_r and the given lines after it.
std::string adaptive_study(const std::string& design_lines) {
  const std::string text = slurp(kStudy);
  return text.substr(0, text.find("[design]")) + "[design]\nkind = \"adaptive\"\n" +
         "parameters = { mu_r = { lower = 0.1, upper = 0.4 } }\n" + design_lines;
}

// The swing-damping variants are TOML keys of [design.acquisition]; absent, the options
// keep their defaults (off), so existing studies choose the same points.
TEST(AdaptiveCampaign, AcquisitionVariantsAreKeys) {
  const auto design_of = [](const std::string& design_lines) {
    const auto study = config::build_study(
        config::parse_config_string(adaptive_study(design_lines), "adaptive.toml"));
    EXPECT_TRUE(study.design && study.design->adaptive);
    return *study.design->adaptive;
  };
  const calibrate::AdaptiveDesignOptions defaults;
  const auto plain = design_of("");
  EXPECT_EQ(plain.acquisition_weight_batches, defaults.acquisition_weight_batches);
  EXPECT_EQ(plain.acquisition_tempering, defaults.acquisition_tempering);
  EXPECT_EQ(plain.space_filling_batch, defaults.space_filling_batch);
  EXPECT_EQ(plain.confirm_region_parts, defaults.confirm_region_parts);
  EXPECT_TRUE(design_of("[design.stopping]\nconfirm_region_parts = true\n").confirm_region_parts);
  const auto set = design_of(
      "[design.acquisition]\nweight_batches = 2\ntempering = 0.5\nspace_filling = true\n");
  EXPECT_EQ(set.acquisition_weight_batches, 2);
  EXPECT_EQ(set.acquisition_tempering, 0.5);
  EXPECT_TRUE(set.space_filling_batch);
  EXPECT_NE(defaults.acquisition_tempering, 0.5);
  EXPECT_FALSE(defaults.space_filling_batch);
}

// The adaptive keys, each refused by name when out of range or not for this kind.
config::ConfigError read_error(const std::string& design_lines) {
  try {
    config::build_study(config::parse_config_string(adaptive_study(design_lines), "adaptive.toml"));
  } catch (const config::ConfigError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << design_lines;
  return config::ConfigError("");
}

TEST(AdaptiveCampaign, KeysAreReadStrictly) {
  const std::map<std::string, std::string> cases = {
      {"initial_points = 2\n", "design.initial_points"},
      {"initial_replicated_points = 9\n", "design.initial_replicated_points"},
      {"batch_size = 0\n", "design.batch_size"},
      {"max_runs = 5\n", "design.max_runs"},
      {"min_separation = 0.5\n", "design.min_separation"},
      {"replicates = 2\n", "design.replicates"},
      {"points = 10\n", "design.points"},
      {"batch = 4\n", "design.batch"},
      {"[design.stopping]\narea_tolerance = 1.5\n", "design.stopping.area_tolerance"},
      {"[design.stopping]\nstable_batch = 2\n", "design.stopping.stable_batch"},
      {"[design.acquisition]\ngrid_points_per_axis = 3\n",
       "design.acquisition.grid_points_per_axis"},
      {"[design.acquisition]\ntempering = 0\n", "design.acquisition.tempering"},
      {"[design.acquisition]\ntempering = 1.5\n", "design.acquisition.tempering"},
      {"[design.acquisition]\nweight_batches = 3\n", "design.acquisition.weight_batches"},
      {"[design.acquisition]\nspace_filling = 1\n", "design.acquisition.space_filling"},
      {"[design.stopping]\nconfirm_region_parts = \"yes\"\n",
       "design.stopping.confirm_region_parts"},
  };
  for (const auto& [lines, key] : cases) {
    const std::string what = read_error(lines).what();
    EXPECT_NE(what.find(key), std::string::npos) << lines << " -> " << what;
    EXPECT_NE(what.find("adaptive.toml:"), std::string::npos) << what;
  }
  // Levels belong to a factorial design.
  std::string text = slurp(kStudy);
  text = text.substr(0, text.find("[design]")) +
         "[design]\nkind = \"adaptive\"\nparameters = { mu_r = { lower = 0.1, upper = 0.4, "
         "levels = 3 } }\n";
  try {
    config::build_study(config::parse_config_string(text, "adaptive.toml"));
    ADD_FAILURE() << "levels accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("levels"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace demcal::cli
