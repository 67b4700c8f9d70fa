// `demcal study` end to end on a tiny whole study (tests/data/study-tiny: 8
// container runs of a few tenths of a second, a plane surrogate, one
// recording): the stage cache reruns a stage exactly when a file it reads or
// wrote has changed (the surrogate files included, so a surrogate edited or
// left by another command is never used stale), and a stage that fails exits
// non-zero and leaves the previous outputs and the stage record as they were.
#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace demcal {
namespace {

namespace fs = std::filesystem;
using testing::fresh_dir;
using testing::slurp;
using testing::spit;

const fs::path kStudyDir = fs::path(DEMCAL_SOURCE_DIR) / "tests/data/study-tiny";

struct Outcome {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// Runs `demcal study study.toml --output out <extra>` in `dir`.
Outcome run_study(const fs::path& dir, const std::string& extra = "") {
  const fs::path log = dir / "console.txt";
  const std::string command = "cd '" + dir.string() + "' && '" + DEMCAL_EXECUTABLE +
                              "' study study.toml --output out --jobs 2 " + extra +
                              " > console.txt 2>&1";
  const int status = std::system(command.c_str());
  Outcome o;
  o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  o.output = slurp(log);
  return o;
}

bool says(const Outcome& o, const std::string& words) {
  return o.output.find(words) != std::string::npos;
}

class StudyStages : public ::testing::Test {
 protected:
  // One first run for the whole suite (the 8 DEM runs); each test works on a copy.
  static void SetUpTestSuite() {
    reference_ = new fs::path(fresh_dir("stages", "reference"));
    fs::copy(kStudyDir, *reference_, fs::copy_options::recursive);
    const Outcome first = run_study(*reference_);
    ASSERT_EQ(first.exit_code, 0) << first.output;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*reference_);
    delete reference_;
  }
  fs::path copy_of_reference(const std::string& name) const {
    const fs::path dir = fresh_dir("stages", name);
    fs::copy(*reference_, dir, fs::copy_options::recursive);
    return dir;
  }
  static fs::path study_out(const fs::path& dir) { return dir / "out" / "study-tiny"; }
  static fs::path surrogate(const fs::path& dir) {
    return study_out(dir) / "surrogates" / "rectangular_container.angle_of_repose_deg.json";
  }
  static fs::path* reference_;
};

fs::path* StudyStages::reference_ = nullptr;

TEST_F(StudyStages, NothingChangedMeansEveryStageUpToDate) {
  const fs::path dir = copy_of_reference("unchanged");
  const Outcome o = run_study(dir);
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_TRUE(says(o, "fit: up to date")) << o.output;
  EXPECT_TRUE(says(o, "inspect: up to date")) << o.output;
  EXPECT_TRUE(says(o, "calibrate: up to date")) << o.output;
  EXPECT_TRUE(says(o, "8 already stored, 0 run")) << o.output;
  fs::remove_all(dir);
}

TEST_F(StudyStages, AnEditedSurrogateFileIsRefittedNotUsed) {
  const fs::path dir = copy_of_reference("edited-surrogate");
  const std::string good = slurp(surrogate(dir));
  ASSERT_FALSE(good.empty());
  // An edit that keeps the file valid JSON (another value of a coefficient, as a
  // hand edit or another command's output would leave it).
  std::string edited = good;
  const std::size_t at = edited.find("\"coefficients");
  ASSERT_NE(at, std::string::npos) << good.substr(0, 400);
  const std::size_t digit = edited.find_first_of("123456789", at);
  ASSERT_NE(digit, std::string::npos);
  edited[digit] = edited[digit] == '9' ? '1' : static_cast<char>(edited[digit] + 1);
  spit(surrogate(dir), edited);

  const Outcome o = run_study(dir);
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_FALSE(says(o, "fit: up to date")) << o.output;
  EXPECT_FALSE(says(o, "calibrate: up to date")) << o.output;
  EXPECT_EQ(slurp(surrogate(dir)), good) << "the refit must restore the surrogate the runs give";
  fs::remove_all(dir);
}

TEST_F(StudyStages, ChangedRecordingsRecalibrateWithoutRefitting) {
  const fs::path dir = copy_of_reference("recordings");
  spit(dir / "recordings.csv",
       "setup,observable,value,sigma,unit,repeats\nrectangular_container,angle_of_repose_deg,29.0,"
       "0.5,deg,3\n");
  const Outcome o = run_study(dir);
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_TRUE(says(o, "fit: up to date")) << o.output;
  EXPECT_FALSE(says(o, "calibrate: up to date")) << o.output;
  fs::remove_all(dir);
}

// A triangular heap profile (header position_m,height_m) of `angle_deg`, crest 20 mm at
// x = 0, a reading every 0.5 mm over +-60 mm.
std::string heap_profile_csv(double angle_deg) {
  std::string text = "position_m,height_m\n";
  const double slope = std::tan(angle_deg * 3.14159265358979323846 / 180.0);
  for (int i = -120; i <= 120; ++i) {
    const double x = 5e-4 * i;
    text += std::to_string(x) + "," + std::to_string(std::max(0.0, 0.02 - slope * std::abs(x))) +
            "\n";
  }
  return text;
}

// A laboratory with only raw series: no recordings CSV at all ([calibration] without
// `recordings`), the AoR measured from two profiles. The calibration reads those files, so
// an edited profile must recalibrate (it was left "up to date": the digest saw only the CSV).
TEST_F(StudyStages, RawSeriesAloneAreTheRecordingsAndAnEditedOneRecalibrates) {
  const fs::path dir = copy_of_reference("raw-series");
  std::string study = slurp(dir / "study.toml");
  const std::string csv_key = "recordings = \"recordings.csv\"";
  const std::size_t at = study.find(csv_key);
  ASSERT_NE(at, std::string::npos);
  study.erase(at, csv_key.size());
  study +=
      "\n[raw_recordings.rectangular_container]\n"
      "profiles = [\"raw/pile-1.csv\", \"raw/pile-2.csv\"]\n"
      "grain_diameter_m = 5.0e-4\n"
      "height_reading_error_m = 1.0e-4\n";
  spit(dir / "study.toml", study);
  fs::remove(dir / "recordings.csv");  // nothing may read it
  fs::create_directories(dir / "raw");
  spit(dir / "raw" / "pile-1.csv", heap_profile_csv(29.0));
  spit(dir / "raw" / "pile-2.csv", heap_profile_csv(30.0));

  const fs::path json = study_out(dir) / "reports" / "calibration" / "calibration.json";
  const Outcome first = run_study(dir);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_TRUE(says(first, "fit: up to date")) << first.output;
  EXPECT_FALSE(says(first, "calibrate: up to date")) << first.output;
  const std::string calibrated = slurp(json);

  const Outcome unchanged = run_study(dir);
  ASSERT_EQ(unchanged.exit_code, 0) << unchanged.output;
  EXPECT_TRUE(says(unchanged, "calibrate: up to date")) << unchanged.output;

  spit(dir / "raw" / "pile-2.csv", heap_profile_csv(36.0));
  const Outcome edited = run_study(dir);
  ASSERT_EQ(edited.exit_code, 0) << edited.output;
  EXPECT_FALSE(says(edited, "calibrate: up to date")) << edited.output;
  EXPECT_NE(slurp(json), calibrated) << "the report must follow the edited profile";
  fs::remove_all(dir);
}

// Without [raw_recordings] the CSV is the only source: leaving `recordings` out is refused
// at the key, and the earlier outputs stay.
TEST_F(StudyStages, NoRecordingsAtAllIsRefusedAtTheKey) {
  const fs::path dir = copy_of_reference("no-recordings");
  std::string study = slurp(dir / "study.toml");
  const std::string csv_key = "recordings = \"recordings.csv\"";
  const std::size_t at = study.find(csv_key);
  ASSERT_NE(at, std::string::npos);
  study.erase(at, csv_key.size());
  spit(dir / "study.toml", study);
  const fs::path json = study_out(dir) / "reports" / "calibration" / "calibration.json";
  const std::string before = slurp(json);
  const Outcome o = run_study(dir);
  EXPECT_NE(o.exit_code, 0) << o.output;
  EXPECT_TRUE(says(o, "study.toml")) << o.output;
  EXPECT_TRUE(says(o, "recordings")) << o.output;
  EXPECT_EQ(slurp(json), before);
  fs::remove_all(dir);
}

TEST_F(StudyStages, AnEditedReportIsRewritten) {
  const fs::path dir = copy_of_reference("edited-report");
  const fs::path json = study_out(dir) / "reports" / "calibration" / "calibration.json";
  ASSERT_TRUE(fs::exists(json));
  spit(json, slurp(json) + " ");
  const Outcome o = run_study(dir);
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_TRUE(says(o, "fit: up to date")) << o.output;
  EXPECT_FALSE(says(o, "calibrate: up to date")) << o.output;
  fs::remove_all(dir);
}

TEST_F(StudyStages, AFailedFitExitsNonZeroAndLeavesThePreviousOutputs) {
  const fs::path dir = copy_of_reference("failed-fit");
  const std::string surrogate_before = slurp(surrogate(dir));
  const std::string stages_before = slurp(study_out(dir) / "stages.json");
  const std::string report_before =
      slurp(study_out(dir) / "reports" / "calibration" / "calibration.json");

  // A cubic needs 10 terms; the design has 4 points: the fit must fail.
  const Outcome failed = run_study(dir, "--set surrogate.degree=3");
  EXPECT_NE(failed.exit_code, 0) << failed.output;
  EXPECT_TRUE(says(failed, "doe.csv")) << failed.output;
  EXPECT_EQ(slurp(surrogate(dir)), surrogate_before);
  EXPECT_EQ(slurp(study_out(dir) / "stages.json"), stages_before);
  EXPECT_EQ(slurp(study_out(dir) / "reports" / "calibration" / "calibration.json"), report_before);

  // The good outputs are still the current ones for the unchanged study.
  const Outcome again = run_study(dir);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_TRUE(says(again, "fit: up to date")) << again.output;
  EXPECT_TRUE(says(again, "calibrate: up to date")) << again.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace demcal
