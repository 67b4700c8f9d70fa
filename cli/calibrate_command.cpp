#include "cli/calibrate_command.hpp"

#include "calibrate/report/calibration_report.hpp"
#include "cli/console.hpp"
#include "study/study_calibration.hpp"
#include "study/study_pipeline.hpp"

namespace demcal::cli {

namespace {

namespace fs = std::filesystem;

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
  const study::StudyCalibrationOutcome c = study::calibrate_study_recordings(
      {o.study, o.overrides, o.output_dir}, study::simulate_verification, console);
  if (!o.quiet) print_headline(log, c.study_name, c.headline);
  out << "calibration report: " << c.report.string() << "\n";
  return {c.report, c.json};
}

namespace {

// The pipeline's stages as the commands run them, printing as they always have.
class CommandStages final : public study::StudyPipelineSteps {
 public:
  CommandStages(const StudyOptions& o, std::ostream& out, std::ostream& log)
      : o_(o), out_(out), log_(log) {
    fit_.study = o.doe.study;
    fit_.overrides = o.doe.overrides;
    fit_.output_dir = o.doe.output_dir;
    fit_.quiet = o.doe.quiet;
  }

  bool run_design() override {
    const DoeOutcome d = run_doe(o_.doe, out_, log_);
    if (d.not_run == 0 && d.missing == 0) return true;
    log_ << "demcal study: " << d.not_run + d.missing
         << " runs are not done; run the same command again\n";
    return false;
  }
  void fit() override { cli::fit(fit_, out_, log_); }
  void inspect() override { cli::inspect(fit_, out_, log_); }
  void calibrate() override { calibrate_study(fit_, out_, log_); }
  void skipped(const std::string& stage, const std::string& study_name,
               const fs::path& report) override {
    if (stage == "inspect") {
      out_ << "inspection report: " << report.string() << "\n";
      return;
    }
    // The main result all the same: the headline the report's JSON keeps.
    const auto head = study::read_calibration_headline(report.parent_path() / "calibration.json");
    if (!o_.doe.quiet && head) print_headline(log_, study_name, *head);
    out_ << "calibration report: " << report.string() << "\n";
  }

 private:
  const StudyOptions& o_;
  FitOptions fit_;
  std::ostream& out_;
  std::ostream& log_;
};

}  // namespace

fs::path run_study(const StudyOptions& o, std::ostream& out, std::ostream& log) {
  CommandStages stages(o, out, log);
  LogLines console(log);
  return study::run_study_pipeline({o.doe.study, o.doe.overrides, o.doe.output_dir, o.force},
                                   stages, console);
}

}  // namespace demcal::cli
