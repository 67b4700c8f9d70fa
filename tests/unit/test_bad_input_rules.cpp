// The rules of issue 15 that the bad-input corpus (tests/bad_input) cannot
// reach from the command line alone: a run store record edited by hand, a
// failed run next to a good one, a fit that fails halfway, a --collect with a
// run missing, a campaign whose every run failed, the damping root search at
// a tiny restitution, and that every checked-in study still reads (the rules
// change no valid input).
#include "cli/doe_command.hpp"
#include "config/doe_csv.hpp"
#include "cli/fit_command.hpp"
#include "study/run_record.hpp"
#include "config/run_sanity.hpp"
#include "study/run_store.hpp"
#include "study/stage_cache.hpp"
#include "config/study_config.hpp"
#include "config/toml_reader.hpp"
#include "dem/contact/restitution_damping.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

void spit(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("demcal-rules-" + name + "-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

nlohmann::json ok_record(const std::string& digest) {
  return {{"design", {{"digest", digest}, {"status", "ok"}}},
          {"observables", {{"angle_of_repose_deg", 30.5}, {"discharge_time_s", 0.55}}},
          {"series", {{"discharged_mass", {{"time_s", {0.0, 0.1, 0.2}}, {"mass_kg", {0.0, 0.01, 0.02}}}}}}};
}

TEST(RunStoreRecord, AHandEditedRecordIsRefusedAndRedone) {
  const fs::path dir = fresh_dir("store");
  const RunStore store(dir);
  store.store("0123456789abcdef", ok_record("d"));
  ASSERT_TRUE(store.load("0123456789abcdef", "d"));
  // The AoR edited to a plausible 89: only the content digest shows it.
  const fs::path file = store.file_for("0123456789abcdef");
  std::string text = slurp(file);
  const auto at = text.find("30.5");
  ASSERT_NE(at, std::string::npos);
  spit(file, text.replace(at, 4, "89.0"));
  std::string problem;
  EXPECT_FALSE(store.load("0123456789abcdef", "d", &problem));
  EXPECT_NE(problem.find("design.content_digest does not match the record"), std::string::npos) << problem;
  fs::remove_all(dir);
}

TEST(RunStoreRecord, ObservablesThatAreNotNumbersInRangeAreRefused) {
  std::string problem;
  nlohmann::json r = ok_record("d");
  r["observables"]["angle_of_repose_deg"] = "fourteen";
  EXPECT_FALSE(parse_run_record(r.dump(), "d", &problem));
  EXPECT_NE(problem.find("observables.angle_of_repose_deg is \"fourteen\"; expected null or a number in [0, 90]"),
            std::string::npos)
      << problem;
  r["observables"]["angle_of_repose_deg"] = 200;
  EXPECT_FALSE(parse_run_record(r.dump(), "d", &problem));
  r["observables"]["angle_of_repose_deg"] = nullptr;
  r["observables"]["discharge_time_s"] = -1;
  EXPECT_FALSE(parse_run_record(r.dump(), "d", &problem));
  EXPECT_NE(problem.find("observables.discharge_time_s"), std::string::npos) << problem;
  // An ok record without observables, a series that is not two arrays of one length.
  nlohmann::json bare = ok_record("d");
  bare.erase("observables");
  EXPECT_FALSE(parse_run_record(bare.dump(), "d", &problem));
  nlohmann::json series = ok_record("d");
  series["series"]["discharged_mass"]["mass_kg"] = {0.0, "x", 0.1};
  EXPECT_FALSE(parse_run_record(series.dump(), "d", &problem));
  EXPECT_NE(problem.find("series.discharged_mass"), std::string::npos) << problem;
  // What a run writes is accepted: numbers, nulls, and a failed run's nulls.
  EXPECT_TRUE(parse_run_record(ok_record("d").dump(), "d"));
  nlohmann::json failed = {{"design", {{"digest", "d"}, {"status", "failed"}}},
                           {"observables", {{"angle_of_repose_deg", nullptr}}}};
  EXPECT_TRUE(parse_run_record(failed.dump(), "d"));
}

TEST(FailedRunRecord, DoesNotReplaceAGoodRunJson) {
  const fs::path dir = fresh_dir("overwrite");
  const nlohmann::json good = {{"results", {{"stopped_because", "at_rest"}}}};
  write_run_record(dir, good);
  const nlohmann::json failed = {{"results", {{"stopped_because", "error"}, {"error", "unstable"}}}};
  EXPECT_EQ(write_failed_run_record(dir, failed), dir / "run.failed.json");
  EXPECT_EQ(nlohmann::json::parse(slurp(dir / "run.json")), good);
  EXPECT_EQ(nlohmann::json::parse(slurp(dir / "run.failed.json")), failed);
  // A failed run over a failed one (or over nothing) is the run.json.
  fs::remove(dir / "run.json");
  EXPECT_EQ(write_failed_run_record(dir, failed), dir / "run.json");
  fs::remove_all(dir);
}

TEST(FitStaging, AFitThatFailsHalfwayLeavesThePreviousSurrogatesWhole) {
  const fs::path dir = fresh_dir("fit");
  const fs::path base = fs::path(DEMCAL_SOURCE_DIR) / "tests/bad_input/base";
  for (const char* f : {"study.toml", "recordings.csv", "doe.csv"}) fs::copy_file(base / f, dir / f);
  FitOptions o;
  o.study = dir / "study.toml";
  o.output_dir = dir / "out";
  o.doe_csv = dir / "doe.csv";
  o.quiet = true;
  std::ostringstream sink;
  const FitOutcome first = fit(o, sink, sink);
  ASSERT_EQ(first.files.size(), 2u);
  const fs::path surrogates = dir / "out" / "quick" / "surrogates";
  const std::string before = directory_digest(surrogates);
  // The discharge time made constant: the AoR surrogate is fitted, then the time refused.
  std::istringstream rows(slurp(dir / "doe.csv"));
  std::string line, text;
  for (int n = 0; std::getline(rows, line); ++n) {
    if (n > 0) {
      std::vector<std::string> f = split_csv_line(line);
      f[7] = "0.5";
      line.clear();
      for (std::size_t k = 0; k < f.size(); ++k) line += (k ? "," : "") + f[k];
    }
    text += line + "\n";
  }
  spit(dir / "doe.csv", text);
  try {
    fit(o, sink, sink);
    FAIL() << "a constant column was fitted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("column discharge_time_s: every sandglass run gives 0.5"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(directory_digest(surrogates), before) << "the previous surrogates were touched";
  for (const auto& e : fs::directory_iterator(dir / "out" / "quick"))
    EXPECT_EQ(e.path().filename().string().find(".surrogates.staging"), std::string::npos) << e.path();
  fs::remove_all(dir);
}

TEST(StageCache, TheDigestOfAStagesFilesSeesEveryChange) {
  const fs::path dir = fresh_dir("digest");
  const std::string empty = directory_digest(dir / "none");
  spit(dir / "s" / "a.json", "1");
  const std::string one = directory_digest(dir / "s");
  EXPECT_NE(one, empty);
  spit(dir / "s" / "a.json", "2");
  EXPECT_NE(directory_digest(dir / "s"), one) << "an edited file";
  spit(dir / "s" / "a.json", "1");
  EXPECT_EQ(directory_digest(dir / "s"), one);
  spit(dir / "s" / "b.json", "1");
  EXPECT_NE(directory_digest(dir / "s"), one) << "an added file";
  fs::remove_all(dir);
}

const fs::path kTiny = fs::path(DEMCAL_SOURCE_DIR) / "tests/data/doe-tiny/study.toml";

TEST(DoeCollect, ARunMissingFromTheStoreLeavesTheTableAsItWas) {
  const fs::path out = fresh_dir("collect");
  DoeOptions o;
  o.study = kTiny;
  o.output_dir = out;
  o.jobs = 2;
  o.quiet = true;
  std::ostringstream sink;
  const DoeOutcome full = run_doe(o, sink, sink);
  ASSERT_TRUE(full.complete());
  const std::string table = slurp(full.table_csv);
  fs::remove(fs::directory_iterator(out / "doe-tiny" / "runs")->path());
  o.collect = true;
  const DoeOutcome collected = run_doe(o, sink, sink);
  EXPECT_FALSE(collected.table_written);
  EXPECT_EQ(collected.missing, 1u);
  EXPECT_EQ(slurp(out / "doe-tiny" / "doe.csv"), table);
  fs::remove_all(out);
}

TEST(DoeExitCode, ACampaignWhoseEveryRunFailedExitsNonZero) {
  const fs::path dir = fresh_dir("all-failed");
  std::string text = slurp(kTiny);
  // A time step of a whole Rayleigh time is unstable within a few hundred steps.
  text = text.substr(0, text.find("[design]")) +
         "[design]\nkind = \"list\"\nparameters = { \"protocol.time_step_fraction_of_rayleigh\" = { lower = 0.5, "
         "upper = 1.0 } }\nvalues = [[1.0]]\n";
  spit(dir / "study.toml", text);
  const std::string cmd = "cd '" + dir.string() + "' && '" + DEMCAL_EXECUTABLE +
                          "' doe study.toml --quiet --output out > log.txt 2>&1";
  const int status = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1) << slurp(dir / "log.txt");
  EXPECT_NE(slurp(dir / "log.txt").find("every run of the table failed"), std::string::npos) << slurp(dir / "log.txt");
  fs::remove_all(dir);
}

TEST(RestitutionDamping, ATinyRestitutionIsRefusedInsteadOfSearchedForever) {
  const auto start = std::chrono::steady_clock::now();
  try {
    dem::damping_beta_for_restitution(1e-12);
    FAIL() << "1e-12 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("below the smallest the exact restitution model resolves"), std::string::npos);
  }
  const double beta = dem::damping_beta_for_restitution(1e-6);
  EXPECT_NEAR(dem::restitution_for_damping_beta(beta), 1e-6, 1e-8);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  EXPECT_LT(dem::smallest_resolved_restitution(), 1e-6);
}

TEST(FileNames, EveryNameThatBecomesAFileNameIsChecked) {
  for (const char* bad : {"", ".", "..", "a/b", "a\\b", "../x", "a..b"})
    EXPECT_FALSE(reader::file_name_problem(bad).empty()) << bad;
  EXPECT_FALSE(reader::file_name_problem(std::string("a\0b", 3)).empty());
  for (const char* good : {"sandglass", "orifice_16mm", "quick-2", "a.b"})
    EXPECT_TRUE(reader::file_name_problem(good).empty()) << good;
}

TEST(CsvNumbers, AreDecimalOnly) {
  EXPECT_FALSE(parse_csv_number("0x10"));
  EXPECT_FALSE(parse_csv_number("inf"));
  EXPECT_FALSE(parse_csv_number("nan"));
  EXPECT_FALSE(parse_csv_number(" 1"));
  EXPECT_EQ(parse_csv_number("-1.5e3"), -1500.0);
}

// The new rules refuse no study the repository holds: each still reads and builds.
TEST(CheckedInStudies, StillReadUnderTheSanityRules) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(fs::path(DEMCAL_SOURCE_DIR) / "studies")) {
    const fs::path study = e.path() / "study.toml";
    if (!fs::exists(study) || !is_study_config(read_config_file(study))) continue;
    ++n;
    try {
      const StudyConfig s = load_study_config(study, {});
      for (const StudyApparatus& a : s.apparatus) {
        const RunEstimate est = estimate_run(s.material, {}, s.protocol);
        EXPECT_GT(est.time_step_s, 0.0) << study << " " << a.name;
      }
    } catch (const std::exception& ex) {
      ADD_FAILURE() << study << ": " << ex.what();
    }
  }
  EXPECT_GE(n, 14u);
}

}  // namespace
}  // namespace demcal::cli
