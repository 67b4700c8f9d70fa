#include "cli/doe_command.hpp"

#include "config/toml_reader.hpp"
#include "study/adaptive_campaign.hpp"
#include "study/doe_table.hpp"
#include "study/progress_observer.hpp"

#include <chrono>
#include <cstdio>
#include <exception>
#include <optional>
#include <thread>
#include <utility>

namespace demcal::cli {

using namespace demcal::config;
using namespace demcal::study;
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

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
class DoeConsole final : public ProgressObserver {
 public:
  DoeConsole(const DoePlan& plan, const DoeOptions& options, std::string who, std::ostream& log)
      : plan_(plan), options_(options), who_(std::move(who)), log_(log) {}

  void on_run_finished(const FinishedRun& e, const DesignProgress& p) override {
    if (options_.progress || options_.quiet) return;
    const PlannedRun& run = *e.run;
    log_ << "demcal doe: " << who_ << "[" << p.done() << "/" << p.total << "] point " << run.point
         << " replicate " << run.replicate << " " << run.apparatus << " ("
         << describe_point(plan_, run.point) << "): " << (e.ok ? "ok" : "failed") << " in "
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

  // Ends the bar's line, if one was drawn.
  void finish() {
    if (bar_shown_) log_ << '\n' << std::flush;
  }

 private:
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

// kind = "adaptive": the campaign loop of study/adaptive_campaign.hpp, then the same table.
DoeOutcome run_adaptive_doe(DoePlan& plan, const RunStore& store, const DesignRunOptions& run_options,
                            const DoeOptions& options, DoeOutcome outcome, std::ostream& out,
                            std::ostream& log, const std::string& who) {
  DoeConsole console(plan, options, who, log);
  AdaptiveCampaignOutcome a;
  try {
    a = run_adaptive_campaign(plan, store, run_options, console, options.dry_run || options.collect);
  } catch (...) {
    console.finish();
    throw;
  }
  console.finish();
  for (const std::string& problem : a.problems)
    log << "demcal doe: " << who << "warning: " << problem << "; the run was redone\n";
  outcome.rows = plan.rows.size();
  outcome.runs = outcome.assigned = plan.runs.size();
  outcome.reused = a.reused;
  outcome.executed = a.ran.executed;
  outcome.failed = a.ran.failed;
  outcome.executed_hashes = a.ran.executed_hashes;
  outcome.not_run = a.not_run;
  const std::string name = "demcal doe: " + who + plan.study_name + ": adaptive design, ";
  out << name << a.history.runs_done << " runs in " << a.history.batches.size() << " batches ("
      << outcome.reused << " found in the store, " << outcome.executed << " run, " << outcome.failed
      << " failed)\n";
  out << name << (a.finished ? "ended: " : "not ended: ")
      << (a.finished ? a.history.statement : a.waiting) << "\n";
  if (options.dry_run || options.shard || options.group.rank != 0) return outcome;
  std::filesystem::create_directories(outcome.study_dir);
  remove_stale_temporaries(outcome.study_dir);
  const DoeTable table = write_doe_table(plan, store, outcome.study_dir);
  outcome.missing = table.missing;
  outcome.ok = table.ok;
  outcome.table_written = true;
  outcome.table_csv = outcome.study_dir / "doe.csv";
  outcome.table_json = outcome.study_dir / "doe.json";
  write_design_history(outcome.study_dir, a);
  out << "store: " << outcome.runs_dir.string() << "\ntable: " << outcome.table_csv.string()
      << " (" << plan.rows.size() << " rows), history: "
      << (outcome.study_dir / "design_history.json").string() << "\n";
  return outcome;
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
    throw ConfigError("--shard " + text + ": expected i/N with 0 <= i < N, e.g. --shard 0/2");
  return sh;
}

DoeOutcome run_doe(const DoeOptions& options, std::ostream& out, std::ostream& log) {
  const ProcessGroup& group = options.group;
  if (options.jobs < 1)
    throw ConfigError("--jobs " + std::to_string(options.jobs) + ": expected an integer >= 1");
  if (options.collect && (options.shard || options.dry_run))
    throw ConfigError("--collect runs nothing and writes the whole table; it takes no --shard or "
                      "--dry-run");

  // Every process reads the study; if one cannot, none goes on.
  DoePlan plan;
  std::exception_ptr plan_error;
  try {
    plan = plan_doe(options.study, options.overrides, options.apparatus, options.threads_per_run);
  } catch (...) {
    plan_error = std::current_exception();
  }
  if (!group.agree(!plan_error)) {
    if (plan_error) std::rethrow_exception(plan_error);
    throw ConfigError("another MPI rank could not read " + options.study.string() +
                      "; see its message");
  }

  const bool mpi = group.size > 1;
  const std::string who = mpi ? "rank " + std::to_string(group.rank) + "/" +
                                    std::to_string(group.size) + ": "
                              : "";
  DoeOutcome outcome;
  outcome.study_dir = options.output_dir / plan.study_name;
  outcome.runs_dir = options.run_store.empty() ? outcome.study_dir / "runs" : options.run_store;
  outcome.rows = plan.rows.size();
  outcome.runs = plan.runs.size();
  const RunStore store(outcome.runs_dir);

  DesignRunOptions run_options;
  run_options.jobs = options.jobs;
  run_options.shard = options.shard;
  run_options.group = group;
  run_options.retry_failed = options.retry_failed;
  run_options.stop_after = options.stop_after;
  run_options.cancel = options.cancel;
  run_options.evaluator = options.evaluator;
  if (plan.design.adaptive) return run_adaptive_doe(plan, store, run_options, options, outcome, out, log, who);
  DesignRunner runner(plan, store, run_options, options.collect);
  const DesignShare& share = runner.share();
  const std::vector<std::size_t>& queue = share.queue;
  const std::vector<std::string>& state = share.state;
  outcome.assigned = share.assigned.size();
  outcome.reused = share.reused;
  if (!options.dry_run)
    for (const std::string& problem : share.problems)
      log << "demcal doe: " << who << "warning: " << problem << "; the run will be redone\n";

  const std::string study_line =
      plan.study_name + ": " + std::to_string(plan.rows.size()) + " rows (" +
      std::to_string(plan.generated.points.size()) + " design points x " +
      std::to_string(plan.design.replicates) +
      (plan.design.replicates == 1 ? " replicate x " : " replicates x ") +
      std::to_string(plan.apparatus.size()) + " apparatus), " + std::to_string(plan.runs.size()) +
      " distinct runs";

  if (options.dry_run) {
    if (group.rank == 0) {
      out << "demcal doe: " << study_line << "\n";
      out << "store: " << outcome.runs_dir.string() << "\n";
      for (const PlanRow& row : plan.rows) {
        const PlannedRun& run = plan.runs[row.run];
        std::string s = state[row.run];
        if (s.empty()) {
          // Not this process's share: say what the store holds all the same.
          const auto stored = store.load(run.key.hash, run.key.digest);
          s = stored ? "stored (" + stored->at("design").at("status").get<std::string>() + ")"
                     : "to run (another shard)";
        }
        out << "  point " << row.point << " replicate " << row.replicate << " seed " << row.seed
            << " " << row.apparatus << " (" << describe_point(plan, row.point)
            << "): " << run.key.hash << " " << s << "\n";
      }
      out << "this process would run " << queue.size() << " of its " << share.assigned.size()
          << " runs (" << outcome.reused << " stored); nothing was written\n";
    }
    outcome.not_run = queue.size();
    return outcome;
  }

  if (plan.study_asks_for_vtk && group.rank == 0 && !options.quiet)
    log << "demcal doe: note: [output] vtk = true is ignored; a campaign writes no snapshots\n";
  const unsigned cores = std::thread::hardware_concurrency();
  if (!options.quiet && cores > 0 && queue.size() > 1 &&
      static_cast<unsigned>(options.jobs) * static_cast<unsigned>(plan.threads_per_run) > cores)
    log << "demcal doe: " << who << "note: " << options.jobs << " jobs x "
        << plan.threads_per_run << " threads per run exceed the " << cores
        << " cores of this machine\n";

  const Clock::time_point start = Clock::now();
  DoeConsole console(plan, options, who, log);
  DesignRunResult ran;
  try {
    ran = runner.run(console);
  } catch (...) {
    console.finish();
    throw;
  }
  console.finish();
  outcome.executed = ran.executed;
  outcome.failed = ran.failed;
  outcome.executed_hashes = std::move(ran.executed_hashes);
  outcome.not_run = share.assigned.size() - outcome.reused - outcome.executed;

  const bool writes_table = !options.shard && group.rank == 0;
  if (writes_table) {
    std::filesystem::create_directories(outcome.study_dir);
    remove_stale_temporaries(outcome.study_dir);
    // --collect writes only a whole table: one with a row missing would replace
    // the table the store was collected into before (a run file lost, a store
    // not yet merged) with a less complete one.
    const DoeTable table = write_doe_table(plan, store, outcome.study_dir, options.collect);
    outcome.missing = table.missing;
    outcome.ok = table.ok;
    outcome.table_written = !(options.collect && table.missing > 0);
    if (outcome.table_written) {
      outcome.table_csv = outcome.study_dir / "doe.csv";
      outcome.table_json = outcome.study_dir / "doe.json";
    }
  }

  // Summary.
  std::string share_text;
  if (options.shard)
    share_text += "shard " + std::to_string(options.shard->index) + "/" +
                  std::to_string(options.shard->count) + ": ";
  out << "demcal doe: " << who << share_text << study_line << "\n";
  if (!options.collect)
    out << "demcal doe: " << who << share.assigned.size() << " runs here: " << outcome.reused
        << " already stored, " << outcome.executed << " run (" << outcome.failed << " failed)"
        << (outcome.not_run > 0 ? ", " + std::to_string(outcome.not_run) + " not run" : "")
        << " in " << seconds_text(seconds_since(start)) << "\n";
  if (group.rank == 0) out << "store: " << outcome.runs_dir.string() << "\n";
  if (writes_table && !outcome.table_written) {
    out << "table: not written: " << outcome.missing << " of " << plan.rows.size()
        << " rows have no run in the store " << outcome.runs_dir.string() << "; "
        << (outcome.study_dir / "doe.csv").string() << " is left as it was\n";
  } else if (writes_table) {
    out << "table: " << outcome.table_csv.string() << " (" << plan.rows.size() << " rows";
    if (outcome.missing > 0) out << ", " << outcome.missing << " without a result yet";
    out << ")\n";
  } else if (options.shard && group.rank == 0) {
    out << "once every shard has finished: demcal doe " << options.study.string()
        << " --collect" << (options.output_dir != "out" ? " --output " + options.output_dir.string() : "")
        << "\n";
  }
  return outcome;
}

}  // namespace demcal::cli
