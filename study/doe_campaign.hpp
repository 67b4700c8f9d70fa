#pragma once
// A study's whole design of experiments, run into the run store and tabled:
// what `demcal doe` does (cli/doe_command.hpp prints it). Reads and plans the
// study (study/doe_plan.hpp), runs this process's share of the runs
// (study/design_runner.hpp; an adaptive design's batches through
// study/adaptive_campaign.hpp), then writes
//   <output>/<study name>/doe.csv, doe.json   (study/doe_table.hpp; not by a
//                                              shard, only by MPI rank 0)
//   <output>/<study name>/design_history.json (adaptive designs)
// Runs already in the store are reused; a campaign killed at any moment and
// started again ends with the same store as one never interrupted.
//
// Errors: the constructor throws config::ConfigError for bad options or a
// study that cannot be read (on every MPI rank when one rank cannot read it),
// before anything runs or is written; run() throws as DesignRunner::run when
// the store cannot be written or another process failed.
//
// Progress goes to a ProgressObserver: each run as it finishes, the design's
// progress, on_warning("<file>: <why>; the run will be redone") for a store
// file that is not a whole record ("...; the run was redone" for an adaptive
// design, reported after its batches), and on_message for notes ("note: ...",
// already prefixed with "rank r/n: " under MPI where the note concerns this
// rank's share).

#include "study/adaptive_campaign.hpp"
#include "study/design_runner.hpp"
#include "study/doe_plan.hpp"
#include "study/progress_observer.hpp"
#include "study/run_evaluator.hpp"

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demcal::study {

struct DoeCampaignOptions {
  std::filesystem::path study;
  std::vector<std::string> overrides;  // --set, applied before the design values
  int jobs = 2;                        // worker threads; >= 1
  std::vector<std::string> apparatus;  // empty: every apparatus of the study
  std::optional<Shard> shard;
  std::filesystem::path output_dir = "out";
  // Where the run records go; empty: <output>/<study name>/runs. A run's file
  // is named by the hash of everything that determines it, and [study] (name,
  // seed, threads) is not in that hash, so several studies of the same
  // apparatus (a study and its variants, the diagnosis' derived studies, the
  // concealed-effect studies) can share one store and run each point once.
  std::filesystem::path run_store;
  int threads_per_run = 1;
  bool dry_run = false;  // say what the store holds of each run; run and write nothing
  bool collect = false;  // run nothing; write the table from the store (no shard, no dry run)
  bool retry_failed = false;
  // Testing resumption: store at most this many runs, then stop as if killed
  // (runs in progress are abandoned without a trace).
  std::optional<std::size_t> stop_after;
  // Set from elsewhere to stop the same way (runs in progress are abandoned).
  const std::atomic<bool>* cancel = nullptr;
  ProcessGroup group;
  const RunEvaluator* evaluator = nullptr;  // null: the DEM (DesignRunOptions)
};

struct DoeCampaignOutcome {
  std::filesystem::path study_dir;  // <output>/<study name>
  std::filesystem::path runs_dir;
  std::filesystem::path table_csv;  // empty when no table was written
  std::filesystem::path table_json;
  std::size_t rows = 0;      // design points x replicates x apparatus
  std::size_t runs = 0;      // distinct runs in the plan
  std::size_t assigned = 0;  // this process's share (shard, rank)
  std::size_t reused = 0;    // of the share: already in the store
  std::size_t executed = 0;  // run and stored now
  std::size_t failed = 0;    // of the executed: stored as failed
  std::size_t not_run = 0;   // of the share: left undone (stopped, cancelled, an error)
  std::size_t missing = 0;   // table rows without a result (when a table was written)
  std::size_t ok = 0;        // table rows with an ok result (when a table was made)
  bool table_written = false;
  // The table was due (no shard, rank 0) but --collect found rows missing and
  // left the old one as it was.
  bool table_withheld = false;
  std::vector<std::string> executed_hashes;  // in the order stored
  double wall_time_s = 0.0;                  // of the runs and the table (grid designs)
  // Dry runs: per plan row, what the store holds of its run ("stored (ok)",
  // "to run", "to run (another shard)", ...).
  std::vector<std::string> row_states;
  // Adaptive designs only.
  bool adaptive = false;
  std::size_t adaptive_runs_done = 0;
  std::size_t adaptive_batches = 0;
  bool adaptive_finished = false;        // the design has ended
  std::string adaptive_statement;        // how it ended, or why it stopped before the end
  std::filesystem::path design_history;  // design_history.json, when written
  bool complete() const { return not_run == 0 && missing == 0; }
};

class DoeCampaign {
 public:
  // Reads and plans the study on every process of options.group; nothing
  // runs yet. Throws ConfigError (see the top of this file).
  explicit DoeCampaign(DoeCampaignOptions options);

  // The plan; an adaptive design adds rows to it while run() goes on.
  const DoePlan& plan() const { return plan_; }
  const DoeCampaignOptions& options() const { return options_; }

  // Runs (or, for a dry run, surveys) this process's share and writes the
  // tables; call once.
  DoeCampaignOutcome run(ProgressObserver& observer);

 private:
  DoeCampaignOutcome run_grid(ProgressObserver& observer, DoeCampaignOutcome outcome);
  DoeCampaignOutcome run_adaptive(ProgressObserver& observer, DoeCampaignOutcome outcome);

  DoeCampaignOptions options_;
  DoePlan plan_;
};

}  // namespace demcal::study
