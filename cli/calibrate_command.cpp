#include "cli/calibrate_command.hpp"

#include "calibrate/report/calibration_report.hpp"
#include "cli/console.hpp"
#include "config/calibration_config.hpp"
#include "config/study_config.hpp"
#include "dem/output/atomic_file.hpp"
#include "study/run_store.hpp"
#include "study/stage_cache.hpp"
#include "study/study_calibration.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace demcal::cli {

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The calibration's progress lines on the log.
class LogLines final : public study::ProgressObserver {
 public:
  explicit LogLines(std::ostream& log) : log_(log) {}
  void on_message(const std::string& text) override { log_ << text << "\n"; }

 private:
  std::ostream& log_;
};

// The closing summary: the report's headline box as text.
void print_headline(std::ostream& log, const std::string& study, const calibrate::Headline& head) {
  std::vector<std::vector<std::string>> rows{head.header};
  for (const auto& r : head.rows) rows.push_back(r);
  log << "\n" << study << ": the calibrated values\n" << aligned_table(rows);
  for (const auto& s : head.sentences) log << "  - " << s << "\n";
  log << "  (the solver's notes, the figures and the tables: in the calibration report)\n\n";
}

}  // namespace

CalibrateOutcome calibrate_study(const FitOptions& o, std::ostream& out, std::ostream& log) {
  LogLines console(log);
  const study::StudyCalibrationOutcome c =
      study::calibrate_study_recordings({o.study, o.overrides, o.output_dir}, study::simulate_verification, console);
  if (!o.quiet) print_headline(log, c.study_name, c.headline);
  out << "calibration report: " << c.report.string() << "\n";
  return {c.report, c.json};
}

namespace {

std::string table_text(const toml::table& t, const char* key) {
  std::ostringstream s;
  if (const auto* n = t.get(key)) s << toml::toml_formatter(toml::table{{key, *n}});
  return s.str();
}

}  // namespace

fs::path run_study(const StudyOptions& o, std::ostream& out, std::ostream& log) {
  const DoeOutcome d = run_doe(o.doe, out, log);
  if (d.not_run > 0 || d.missing > 0) {
    log << "demcal study: " << d.not_run + d.missing
        << " runs are not done; run the same command again\n";
    return {};
  }
  config::StudyConfig study = config::load_study_config(o.doe.study, o.doe.overrides);
  const fs::path dir = study::study_directory(o.doe.output_dir, study.name);
  study::StageCache stages(dir / "stages.json");
  FitOptions fo;
  fo.study = o.doe.study;
  fo.overrides = o.doe.overrides;
  fo.output_dir = o.doe.output_dir;
  fo.quiet = o.doe.quiet;
  const std::string doe_csv = slurp(dir / "doe.csv");
  const std::string fit_digest =
      config::sha256_hex(doe_csv + "\n" + table_text(study.resolved, "surrogate") +
                 table_text(study.resolved, "design"));
  const fs::path surrogates = dir / "surrogates";
  if (o.force || !stages.current("fit", fit_digest, surrogates)) {
    fit(fo, out, log);
    stages.done("fit", fit_digest, surrogates);
    stages.forget("inspect");
    stages.forget("calibrate");
  } else {
    log << "fit: up to date (doe.csv, [surrogate] and the surrogate files unchanged)\n";
  }
  // The later stages read the surrogate files: their digest is part of their inputs.
  const std::string surrogates_digest = study::directory_digest(surrogates);
  const std::string inspect_digest = config::sha256_hex(fit_digest + surrogates_digest);
  const fs::path inspection = dir / "reports" / "inspection" / "index.html";
  if (o.force || !stages.current("inspect", inspect_digest, inspection.parent_path()) ||
      !fs::exists(inspection)) {
    inspect(fo, out, log);
    stages.done("inspect", inspect_digest, inspection.parent_path());
  } else {
    log << "inspect: up to date\n";
    out << "inspection report: " << inspection.string() << "\n";
  }
  if (!study.calibration) return inspection;
  const std::string cal_digest =
      config::sha256_hex(fit_digest + surrogates_digest + table_text(study.resolved, "calibration") +
                 slurp(study.calibration->recordings));
  const fs::path report = dir / "reports" / "calibration" / "index.html";
  if (o.force || !stages.current("calibrate", cal_digest, report.parent_path()) ||
      !fs::exists(report)) {
    calibrate_study(fo, out, log);
    stages.done("calibrate", cal_digest, report.parent_path());
  } else {
    log << "calibrate: up to date (surrogates, [calibration] and recordings unchanged)\n";
    // The main result all the same: the headline the report's JSON keeps.
    try {
      std::ifstream in(report.parent_path() / "calibration.json");
      const auto j = nlohmann::json::parse(in);
      if (!o.doe.quiet && j.contains("headline")) {
        calibrate::Headline head;
        head.header = j["headline"]["header"].get<std::vector<std::string>>();
        head.rows = j["headline"]["rows"].get<std::vector<std::vector<std::string>>>();
        head.sentences = j["headline"]["sentences"].get<std::vector<std::string>>();
        print_headline(log, study.name, head);
      }
    } catch (const std::exception&) {
      // An older report without a headline: its path is enough.
    }
    out << "calibration report: " << report.string() << "\n";
  }
  return report;
}

}  // namespace demcal::cli
