#pragma once
// Running a design's runs into the run store: the part of `demcal doe` that
// executes (study/doe_campaign.hpp is the whole campaign).
//
// Threads. Runs execute inside this process on `jobs` worker threads, each
// running one simulation at a time with the plan's threads_per_run OpenMP
// threads (the engine keeps no global mutable state; a worker sets its own
// OpenMP default). A run's record is stored atomically the moment it ends; a
// run that fails (dem::InstabilityError, ...) is stored with status "failed"
// and its message, and is not run again unless retry_failed.
//
// Shards and MPI. The distinct runs are numbered in plan order
// (study/doe_plan.hpp); shard i/N takes those with number % N == i, and within
// a shard, rank r of a process group of size s takes every s-th
// (position % s == r). After its share, every process waits for the others
// (ProcessGroup::agree), so that the store is whole before anyone reads it.
//
// Determinism: a run's result depends only on its key (inputs, seed, threads
// per run), never on jobs, shards or ranks.

#include "study/doe_plan.hpp"
#include "study/progress_observer.hpp"
#include "study/run_evaluator.hpp"
#include "study/run_store.hpp"

#include <atomic>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace demcal::study {

// The processes a design is split over: MPI's world, or just this process.
struct ProcessGroup {
  int rank = 0;
  int size = 1;
  // Collective: blocks until every process calls it, then says whether every
  // one passed true. Empty for a single process.
  std::function<bool(bool)> all_true;

  bool agree(bool ok) const { return all_true ? all_true(ok) : ok; }
};

struct Shard {
  std::size_t index = 0;
  std::size_t count = 1;
};

struct DesignRunOptions {
  int jobs = 2;  // worker threads
  std::optional<Shard> shard;
  ProcessGroup group;
  bool retry_failed = false;  // run again the runs stored as failed
  // Testing resumption: store at most this many runs, then stop as if killed
  // (runs in progress are abandoned without a trace).
  std::optional<std::size_t> stop_after;
  // Set from elsewhere to stop the same way (runs in progress are abandoned).
  const std::atomic<bool>* cancel = nullptr;
  // What evaluates each run (study/run_evaluator.hpp); null: demcal's DEM, or
  // the study's [engine]. Not part of the run key: a store holds one evaluator's runs.
  const RunEvaluator* evaluator = nullptr;
};

// This process's share of a plan and what the store holds of it.
struct DesignShare {
  std::vector<std::size_t> assigned;  // indices into DoePlan::runs
  std::vector<std::size_t> queue;     // of those, the ones to run now
  std::size_t reused = 0;             // of those, already stored
  // Per plan run: "stored (ok)", "stored (failed)", "to run",
  // "to rerun (stored failed)"; empty outside the share.
  std::vector<std::string> state;
  // Store files of the share that are not a whole record of their run (each
  // will be redone and replaced), as "<file>: <why>".
  std::vector<std::string> problems;
};

struct DesignRunResult {
  std::size_t executed = 0;                  // run and stored now
  std::size_t failed = 0;                    // of the executed: stored as failed
  std::vector<std::string> executed_hashes;  // in the order stored
};

class DesignRunner {
 public:
  // Surveys the store for this process's share (nothing runs yet). `collect`:
  // the share is empty (a table is to be written from the store alone).
  DesignRunner(const DoePlan& plan, const RunStore& store, DesignRunOptions options,
               bool collect = false);

  const DesignShare& share() const { return share_; }

  // Runs the queue on the worker threads, reporting to `observer` from this
  // thread; then waits for every process of the group. Throws the first
  // error of this process (a run that cannot be stored, a study that no
  // longer builds), or std::runtime_error when another process failed: the
  // store keeps every run that finished.
  DesignRunResult run(ProgressObserver& observer);

 private:
  const DoePlan& plan_;
  const RunStore& store_;
  DesignRunOptions options_;
  DesignShare share_;
};

}  // namespace demcal::study
