#include "cli/doe_command.hpp"

#include "config/toml_reader.hpp"
#include "study/progress_observer.hpp"

#include <cstdio>
#include <utility>

namespace demcal::cli {

namespace {

using study::DesignProgress;
using study::DoePlan;

std::string duration_text(double s) {
  char buf[64];
  if (s < 60.0)
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 3600.0)
    std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s) / 3600,
                  (static_cast<int>(s) / 60) % 60);
  return buf;
}

std::string seconds_text(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f s", s);
  return buf;
}

// Prints a design's progress as `demcal doe` always has: a line per stored
// run (with the ETA at most every 30 s), or a bar redrawn on a terminal.
class DoeConsole final : public study::ProgressObserver {
 public:
  DoeConsole(const DoePlan& plan, const DoeOptions& options, std::string who, std::ostream& log)
      : plan_(plan), options_(options), who_(std::move(who)), log_(log) {}
  ~DoeConsole() override { end_bar(); }

  void on_warning(const std::string& text) override {
    end_bar();  // an adaptive design's warnings come after its batches
    log_ << "demcal doe: " << who_ << "warning: " << text << "\n";
  }
  void on_message(const std::string& text) override {
    if (!options_.quiet) log_ << "demcal doe: " << text << "\n";
  }

  void on_run_finished(const study::FinishedRun& e, const DesignProgress& p) override {
    if (options_.progress || options_.quiet) return;
    const study::PlannedRun& run = *e.run;
    log_ << "demcal doe: " << who_ << "[" << p.done() << "/" << p.total << "] point " << run.point
         << " replicate " << run.replicate << " " << run.apparatus << " ("
         << study::describe_point(plan_, run.point) << "): " << (e.ok ? "ok" : "failed") << " in "
         << seconds_text(e.wall_time_s) << (e.ok ? "" : ": " + e.error) << " -> runs/"
         << run.key.hash << ".json\n";
    // The ETA in a log too (no terminal, no bar): at most every 30 s and at the end.
    if (p.elapsed_s - last_eta_s_ >= 30.0 || p.done() == p.total) {
      last_eta_s_ = p.elapsed_s;
      log_ << "demcal doe: " << who_ << p.done() << "/" << p.total << " done, " << p.failed
           << " failed, " << duration_text(p.elapsed_s) << " elapsed"
           << (p.done() < p.total ? ", ETA " + eta_text(p) : std::string()) << "\n";
    }
    log_ << std::flush;
  }

  void on_progress(const DesignProgress& p) override {
    if (!options_.progress) return;
    constexpr std::size_t kCells = 24;
    const std::size_t filled = p.total > 0 ? p.done() * kCells / p.total : kCells;
    std::string line = who_ + plan_.study_name + " [" + std::string(filled, '#') +
                       std::string(kCells - filled, '.') + "] " + std::to_string(p.done()) + "/" +
                       std::to_string(p.total) + " done, " + std::to_string(p.failed) +
                       " failed | " + duration_text(p.elapsed_s) + " elapsed | ETA " +
                       (p.executed > 0 ? eta_text(p) : "?");
    if (line.size() < bar_width_) line.append(bar_width_ - line.size(), ' ');
    bar_width_ = line.size();
    log_ << '\r' << line << std::flush;
    bar_shown_ = true;
  }

 private:
  // Ends the bar's line, if one was drawn.
  void end_bar() {
    if (bar_shown_) log_ << '\n' << std::flush;
    bar_shown_ = false;
  }

  std::string eta_text(const DesignProgress& p) const {
    const double mean = p.run_seconds / static_cast<double>(p.executed);
    return duration_text(mean * static_cast<double>(p.total - p.done()) / options_.jobs);
  }

  const DoePlan& plan_;
  const DoeOptions& options_;
  std::string who_;
  std::ostream& log_;
  double last_eta_s_ = 0.0;
  std::size_t bar_width_ = 0;
  bool bar_shown_ = false;
};

void print_adaptive(const DoeOptions& options, const DoePlan& plan, const DoeOutcome& r,
                    const std::string& who, std::ostream& out) {
  const std::string name = "demcal doe: " + who + plan.study_name + ": adaptive design, ";
  out << name << r.adaptive_runs_done << " runs in " << r.adaptive_batches << " batches ("
      << r.reused << " found in the store, " << r.executed << " run, " << r.failed << " failed)\n";
  out << name << (r.adaptive_finished ? "ended: " : "not ended: ") << r.adaptive_statement << "\n";
  if (options.dry_run || options.shard || options.group.rank != 0) return;
  out << "store: " << r.runs_dir.string() << "\ntable: " << r.table_csv.string() << " ("
      << plan.rows.size() << " rows), history: " << r.design_history.string() << "\n";
}

void print_dry_run(const DoePlan& plan, const DoeOutcome& r, const std::string& study_line,
                   std::ostream& out) {
  out << "demcal doe: " << study_line << "\n";
  out << "store: " << r.runs_dir.string() << "\n";
  for (std::size_t i = 0; i < plan.rows.size(); ++i) {
    const study::PlanRow& row = plan.rows[i];
    out << "  point " << row.point << " replicate " << row.replicate << " seed " << row.seed << " "
        << row.apparatus << " (" << study::describe_point(plan, row.point)
        << "): " << plan.runs[row.run].key.hash << " " << r.row_states[i] << "\n";
  }
  out << "this process would run " << r.not_run << " of its " << r.assigned << " runs (" << r.reused
      << " stored); nothing was written\n";
}

}  // namespace

Shard parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  auto number = [&](const std::string& s, std::size_t& v) {
    if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos)
      return false;
    v = static_cast<std::size_t>(std::stoul(s));
    return true;
  };
  Shard sh;
  if (slash == std::string::npos || !number(text.substr(0, slash), sh.index) ||
      !number(text.substr(slash + 1), sh.count) || sh.count < 1 || sh.index >= sh.count)
    throw config::ConfigError("--shard " + text +
                              ": expected i/N with 0 <= i < N, e.g. --shard 0/2");
  return sh;
}

DoeOutcome run_doe(const DoeOptions& options, std::ostream& out, std::ostream& log) {
  study::DoeCampaign campaign(options);
  const DoePlan& plan = campaign.plan();
  const ProcessGroup& group = options.group;
  const std::string who = group.size > 1 ? "rank " + std::to_string(group.rank) + "/" +
                                               std::to_string(group.size) + ": "
                                         : "";
  DoeOutcome r;
  {
    DoeConsole console(plan, options, who, log);  // its bar ends before the summary
    r = campaign.run(console);
  }
  if (r.adaptive) {
    print_adaptive(options, plan, r, who, out);
    return r;
  }

  const std::string study_line =
      plan.study_name + ": " + std::to_string(plan.rows.size()) + " rows (" +
      std::to_string(plan.generated.points.size()) + " design points x " +
      std::to_string(plan.design.replicates) +
      (plan.design.replicates == 1 ? " replicate x " : " replicates x ") +
      std::to_string(plan.apparatus.size()) + " apparatus), " + std::to_string(plan.runs.size()) +
      " distinct runs";
  if (options.dry_run) {
    if (group.rank == 0) print_dry_run(plan, r, study_line, out);
    return r;
  }

  std::string share_text;
  if (options.shard)
    share_text += "shard " + std::to_string(options.shard->index) + "/" +
                  std::to_string(options.shard->count) + ": ";
  out << "demcal doe: " << who << share_text << study_line << "\n";
  if (!options.collect)
    out << "demcal doe: " << who << r.assigned << " runs here: " << r.reused << " already stored, "
        << r.executed << " run (" << r.failed << " failed)"
        << (r.not_run > 0 ? ", " + std::to_string(r.not_run) + " not run" : "") << " in "
        << seconds_text(r.wall_time_s) << "\n";
  if (group.rank == 0) out << "store: " << r.runs_dir.string() << "\n";
  if (r.table_withheld) {
    out << "table: not written: " << r.missing << " of " << plan.rows.size()
        << " rows have no run in the store " << r.runs_dir.string() << "; "
        << (r.study_dir / "doe.csv").string() << " is left as it was\n";
  } else if (r.table_written) {
    out << "table: " << r.table_csv.string() << " (" << plan.rows.size() << " rows";
    if (r.missing > 0) out << ", " << r.missing << " without a result yet";
    out << ")\n";
  } else if (options.shard && group.rank == 0) {
    out << "once every shard has finished: demcal doe " << options.study.string() << " --collect"
        << (options.output_dir != "out" ? " --output " + options.output_dir.string() : "") << "\n";
  }
  return r;
}

}  // namespace demcal::cli
