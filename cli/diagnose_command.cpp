#include "cli/diagnose_command.hpp"

#include "cli/calibrate_command.hpp"
#include "cli/doe_command.hpp"
#include "study/diagnosis_workflow.hpp"

namespace demcal::cli {
namespace {

// The diagnosis' steps as the commands run them, printing as they always have.
class CommandSteps final : public study::DiagnosisSteps {
 public:
  CommandSteps(const DiagnoseOptions& o, std::ostream& out, std::ostream& log)
      : o_(o), out_(out), log_(log) {}

  bool run_study_pipeline() override {
    StudyOptions so;
    so.doe.study = o_.study;
    so.doe.overrides = o_.overrides;
    so.doe.output_dir = o_.output_dir;
    so.doe.run_store = o_.run_store;
    so.doe.jobs = o_.jobs;
    so.doe.quiet = o_.quiet;
    so.doe.evaluator = o_.evaluator;
    return !run_study(so, out_, log_).empty();
  }

  study::DerivedDesignOutcome run_design(const std::filesystem::path& study_file) override {
    DoeOptions d;
    d.study = study_file;
    d.output_dir = o_.output_dir;
    d.run_store = o_.run_store;
    d.jobs = o_.jobs;
    d.quiet = o_.quiet;
    d.evaluator = o_.evaluator;
    const DoeOutcome done = run_doe(d, out_, log_);
    return {done.complete(), done.executed, done.table_csv};
  }

 private:
  const DiagnoseOptions& o_;
  std::ostream& out_;
  std::ostream& log_;
};

// "diagnose: <line>" on the log, as the command always wrote its progress.
class DiagnoseConsole final : public study::ProgressObserver {
 public:
  explicit DiagnoseConsole(std::ostream& log) : log_(log) {}
  void on_message(const std::string& text) override { log_ << "diagnose: " << text << "\n"; }

 private:
  std::ostream& log_;
};

}  // namespace

DiagnoseOutcome diagnose(const DiagnoseOptions& o, std::ostream& out, std::ostream& log) {
  CommandSteps steps(o, out, log);
  DiagnoseConsole console(log);
  const DiagnoseOutcome outcome =
      study::diagnose_study({o.study, o.overrides, o.output_dir}, steps, console);
  if (!outcome.report.empty()) {
    out << outcome.summary << "\n";
    out << "diagnosis report: " << outcome.report.string() << "\n";
  }
  return outcome;
}

}  // namespace demcal::cli
