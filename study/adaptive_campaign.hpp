#pragma once
// An adaptive design ([design] kind = "adaptive", docs/adaptive_design.md) run as a
// campaign: ask the design (calibrate/adaptive_design.hpp) for its next batch given the
// runs in the store, run the batch through the same content-hashed store and design runner
// as a grid (threads, shards, MPI: study/design_runner.hpp), repeat until the design ends.
//
// Resuming: a run's file is the hash of its inputs (theta, seed, apparatus ...), and the
// design's choices are a pure function of the runs done. So the campaign always starts
// from batch 0, finds each requested run in the store or runs it, and a campaign killed at
// any moment makes the same choices again and ends with the same store and history.
//
// Shards: each shard runs its share of the current batch; the next batch needs the whole
// batch, so a shard stops (finished = false, waiting set) until the other shards' runs are
// in the store (a shared store, or copied together) and it is started again. MPI ranks run
// the loop together: every rank asks the same design and waits for the batch.

#include "calibrate/adaptive_design.hpp"
#include "study/design_runner.hpp"
#include "study/doe_plan.hpp"
#include "study/progress_observer.hpp"
#include "study/run_store.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace demcal::study {

struct AdaptiveCampaignOutcome {
  DesignRunResult ran;                // over every batch
  std::size_t reused = 0;             // runs found in the store
  std::size_t not_run = 0;            // runs of the current batch left undone
  bool finished = false;              // the design has ended (history.status says how)
  std::string waiting;                // why it stopped before the end (empty when finished)
  std::vector<std::string> problems;  // store files redone (not a whole record), "<file>: <why>"
  calibrate::AdaptiveDesignHistory history;
  std::vector<std::string> parameter_names;
};

// The design problem of a study: its [design] box and its [calibration] recordings (every
// one needs an apparatus of `plan` and an observable of doe.csv). ConfigError when the
// study lacks [calibration] or a gaussian_process [surrogate], or a recording cannot be met.
struct AdaptiveStudyDesign {
  calibrate::AdaptiveDesignProblem problem;
  calibrate::AdaptiveDesignOptions options;  // [design]'s, with [surrogate] and [calibration]
};
AdaptiveStudyDesign adaptive_study_design(const DoePlan& plan);

// Runs the campaign (plan from plan_doe with design.adaptive). On return `plan` holds every
// run the design has asked for so far (the table's rows: write_doe_table). `dry_run`: asks
// for the batches the store can answer and stops at the first run it would have to do.
// Throws as DesignRunner::run and ConfigError for a study the design cannot run.
AdaptiveCampaignOutcome run_adaptive_campaign(DoePlan& plan, const RunStore& store,
                                              const DesignRunOptions& options,
                                              ProgressObserver& observer, bool dry_run = false);

// design_history.json: the history (calibrate::AdaptiveDesignHistory::to_json), its text and
// the parameter names; written atomically into `study_dir`.
void write_design_history(const std::filesystem::path& study_dir,
                          const AdaptiveCampaignOutcome& outcome);

}  // namespace demcal::study
