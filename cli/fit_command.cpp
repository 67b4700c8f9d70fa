#include "cli/fit_command.hpp"

#include "cli/console.hpp"

namespace demcal::cli {
namespace {

// The fit's lines on the log, one per surrogate, unless quiet.
class LogLines final : public study::ProgressObserver {
 public:
  LogLines(std::ostream& log, bool quiet) : log_(log), quiet_(quiet) {}
  void on_message(const std::string& text) override {
    if (!quiet_) log_ << text << "\n";
  }

 private:
  std::ostream& log_;
  bool quiet_;
};

study::SurrogateFitOptions fit_options(const FitOptions& o) {
  return {o.study, o.overrides, o.output_dir, o.doe_csv};
}

}  // namespace

FitOutcome fit(const FitOptions& o, std::ostream& out, std::ostream& log) {
  LogLines lines(log, o.quiet);
  const study::SurrogateFitOutcome fitted = study::fit_surrogates(fit_options(o), lines);
  for (const auto& w : fitted.warnings) warn_once(log, w);
  for (const auto& f : fitted.files) out << "surrogate: " << f.string() << "\n";
  return {fitted.files, fitted.warnings};
}

std::filesystem::path inspect(const FitOptions& o, std::ostream& out, std::ostream& log) {
  LogLines notes(log, /*quiet=*/false);  // its notes were always printed
  const study::InspectionOutcome report = study::inspect_surrogates(fit_options(o), notes);
  for (const auto& w : report.warnings) warn_once(log, w);
  out << "inspection report: " << report.html.string() << "\n";
  return report.html;
}

}  // namespace demcal::cli
