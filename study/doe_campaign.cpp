#include "study/doe_campaign.hpp"

#include "config/toml_reader.hpp"
#include "study/doe_table.hpp"
#include "study/run_store.hpp"

#include <chrono>
#include <exception>
#include <thread>
#include <utility>

namespace demcal::study {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Every process reads the study; if one cannot, none goes on.
DoePlan plan_on_every_rank(const DoeCampaignOptions& o) {
  DoePlan plan;
  std::exception_ptr plan_error;
  try {
    plan = plan_doe(o.study, o.overrides, o.apparatus, o.threads_per_run);
  } catch (...) {
    plan_error = std::current_exception();
  }
  if (!o.group.agree(!plan_error)) {
    if (plan_error) std::rethrow_exception(plan_error);
    throw config::ConfigError("another MPI rank could not read " + o.study.string() +
                              "; see its message");
  }
  return plan;
}

const DoeCampaignOptions& checked(const DoeCampaignOptions& o) {
  if (o.jobs < 1)
    throw config::ConfigError("--jobs " + std::to_string(o.jobs) + ": expected an integer >= 1");
  if (o.collect && (o.shard || o.dry_run))
    throw config::ConfigError(
        "--collect runs nothing and writes the whole table; it takes no --shard or "
        "--dry-run");
  return o;
}

DesignRunOptions design_run_options(const DoeCampaignOptions& o) {
  DesignRunOptions r;
  r.jobs = o.jobs;
  r.shard = o.shard;
  r.group = o.group;
  r.retry_failed = o.retry_failed;
  r.stop_after = o.stop_after;
  r.cancel = o.cancel;
  r.evaluator = o.evaluator;
  return r;
}

// The text before a rank's own messages under MPI.
std::string rank_label(const ProcessGroup& group) {
  if (group.size <= 1) return "";
  return "rank " + std::to_string(group.rank) + "/" + std::to_string(group.size) + ": ";
}

}  // namespace

DoeCampaign::DoeCampaign(DoeCampaignOptions options)
    : options_(std::move(options)), plan_(plan_on_every_rank(checked(options_))) {}

DoeCampaignOutcome DoeCampaign::run(ProgressObserver& observer) {
  DoeCampaignOutcome outcome;
  outcome.study_dir = options_.output_dir / plan_.study_name;
  outcome.runs_dir = options_.run_store.empty() ? outcome.study_dir / "runs" : options_.run_store;
  outcome.rows = plan_.rows.size();
  outcome.runs = plan_.runs.size();
  return plan_.design.adaptive ? run_adaptive(observer, std::move(outcome))
                               : run_grid(observer, std::move(outcome));
}

DoeCampaignOutcome DoeCampaign::run_grid(ProgressObserver& observer, DoeCampaignOutcome outcome) {
  const ProcessGroup& group = options_.group;
  const RunStore store(outcome.runs_dir);
  DesignRunner runner(plan_, store, design_run_options(options_), options_.collect);
  const DesignShare& share = runner.share();
  outcome.assigned = share.assigned.size();
  outcome.reused = share.reused;
  outcome.not_run = share.queue.size();

  if (options_.dry_run) {
    if (group.rank != 0) return outcome;
    for (const PlanRow& row : plan_.rows) {
      const PlannedRun& run = plan_.runs[row.run];
      std::string s = share.state[row.run];
      if (s.empty()) {
        // Not this process's share: say what the store holds all the same.
        const auto stored = store.load(run.key.hash, run.key.digest);
        s = stored ? "stored (" + stored->at("design").at("status").get<std::string>() + ")"
                   : "to run (another shard)";
      }
      outcome.row_states.push_back(std::move(s));
    }
    return outcome;
  }

  for (const std::string& problem : share.problems)
    observer.on_warning(problem + "; the run will be redone");
  if (plan_.study_asks_for_vtk && group.rank == 0)
    observer.on_message("note: [output] vtk = true is ignored; a campaign writes no snapshots");
  const unsigned cores = std::thread::hardware_concurrency();
  if (cores > 0 && share.queue.size() > 1 &&
      static_cast<unsigned>(options_.jobs) * static_cast<unsigned>(plan_.threads_per_run) > cores)
    observer.on_message(rank_label(group) + "note: " + std::to_string(options_.jobs) + " jobs x " +
                        std::to_string(plan_.threads_per_run) + " threads per run exceed the " +
                        std::to_string(cores) + " cores of this machine");

  const Clock::time_point start = Clock::now();
  DesignRunResult ran = runner.run(observer);
  outcome.executed = ran.executed;
  outcome.failed = ran.failed;
  outcome.executed_hashes = std::move(ran.executed_hashes);
  outcome.not_run = share.assigned.size() - outcome.reused - outcome.executed;
  outcome.wall_time_s = seconds_since(start);

  if (options_.shard || group.rank != 0) return outcome;
  std::filesystem::create_directories(outcome.study_dir);
  remove_stale_temporaries(outcome.study_dir);
  // --collect writes only a whole table: one with a row missing would replace
  // the table the store was collected into before (a run file lost, a store
  // not yet merged) with a less complete one.
  const DoeTable table = write_doe_table(plan_, store, outcome.study_dir, options_.collect);
  outcome.missing = table.missing;
  outcome.ok = table.ok;
  outcome.table_written = !(options_.collect && table.missing > 0);
  outcome.table_withheld = !outcome.table_written;
  if (outcome.table_written) {
    outcome.table_csv = outcome.study_dir / "doe.csv";
    outcome.table_json = outcome.study_dir / "doe.json";
  }
  outcome.wall_time_s = seconds_since(start);
  return outcome;
}

// kind = "adaptive": the campaign loop of study/adaptive_campaign.hpp, then the same table.
DoeCampaignOutcome DoeCampaign::run_adaptive(ProgressObserver& observer,
                                             DoeCampaignOutcome outcome) {
  const RunStore store(outcome.runs_dir);
  const AdaptiveCampaignOutcome a = run_adaptive_campaign(
      plan_, store, design_run_options(options_), observer, options_.dry_run || options_.collect);
  for (const std::string& problem : a.problems)
    observer.on_warning(problem + "; the run was redone");
  outcome.rows = plan_.rows.size();
  outcome.runs = outcome.assigned = plan_.runs.size();
  outcome.reused = a.reused;
  outcome.executed = a.ran.executed;
  outcome.failed = a.ran.failed;
  outcome.executed_hashes = a.ran.executed_hashes;
  outcome.not_run = a.not_run;
  outcome.adaptive = true;
  outcome.adaptive_runs_done = a.history.runs_done;
  outcome.adaptive_batches = a.history.batches.size();
  outcome.adaptive_finished = a.finished;
  outcome.adaptive_statement = a.finished ? a.history.statement : a.waiting;
  if (options_.dry_run || options_.shard || options_.group.rank != 0) return outcome;
  std::filesystem::create_directories(outcome.study_dir);
  remove_stale_temporaries(outcome.study_dir);
  const DoeTable table = write_doe_table(plan_, store, outcome.study_dir);
  outcome.missing = table.missing;
  outcome.ok = table.ok;
  outcome.table_written = true;
  outcome.table_csv = outcome.study_dir / "doe.csv";
  outcome.table_json = outcome.study_dir / "doe.json";
  write_design_history(outcome.study_dir, a);
  outcome.design_history = outcome.study_dir / "design_history.json";
  return outcome;
}

}  // namespace demcal::study
