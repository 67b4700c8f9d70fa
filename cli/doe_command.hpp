#pragma once
// `demcal doe`: runs every design point x replicate x apparatus of a study
// (its [design] table, config/design_config.hpp) into the run store
// (study/run_store.hpp) and writes the campaign's table (study/doe_table.hpp).
//
//   <output>/<study name>/runs/<hash>.json   one run record per distinct run
//                                            (or --run-store DIR/<hash>.json)
//   <output>/<study name>/doe.csv, doe.json  the table (not by a shard)
// <output> is --output, else "out" (as `demcal simulate` writes
// out/<study>/<apparatus>); the study's [output] directory names one run's
// directory and is not used here, nor VTK output.
//
// Execution, shards and MPI: study/design_runner.hpp (jobs worker threads,
// shard i/N, MPI ranks; a run's result depends only on its key). A run record
// is the one `demcal simulate` writes for the apparatus plus a "design" block
// (point, replicate, seed, parameters, hash, digest, status).
//
// Resuming: runs already in the store are reused, not rerun; an interrupted
// run left nothing but possibly a temporary file, which is never read and is
// cleaned up (study/run_store.hpp). So a campaign killed at any moment and
// started again ends with the same store as one never interrupted. Shards
// write no table: copy their run directories together (or share one) and use
// collect. Under MPI rank 0 writes the table once every rank has stored its runs.

#include "study/design_runner.hpp"
#include "study/doe_plan.hpp"

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace demcal::cli {

using study::ProcessGroup;
using study::Shard;

// "i/N" with 0 <= i < N; ConfigError otherwise.
Shard parse_shard(const std::string& text);

struct DoeOptions {
  std::filesystem::path study;
  std::vector<std::string> overrides;  // --set, applied before the design values
  int jobs = 2;                        // worker threads
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
  bool quiet = false;     // no line per run
  bool progress = false;  // a progress bar on `log` (a terminal) instead of lines per run
  bool dry_run = false;   // list the runs and what the store holds; write nothing
  bool collect = false;   // run nothing; write the table from the store
  bool retry_failed = false;
  // Testing resumption: store at most this many runs, then stop as if killed
  // (runs in progress are abandoned without a trace).
  std::optional<std::size_t> stop_after;
  // Set from elsewhere to stop the same way (runs in progress are abandoned).
  const std::atomic<bool>* cancel = nullptr;
  ProcessGroup group;
  const study::RunEvaluator* evaluator = nullptr;  // null: the DEM (DesignRunOptions)
};

struct DoeOutcome {
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
  std::vector<std::string> executed_hashes;  // in the order stored
  bool complete() const { return not_run == 0 && missing == 0; }
};

// Throws ConfigError for input problems (before anything runs or is written)
// and other exceptions when the store cannot be written.
DoeOutcome run_doe(const DoeOptions& options, std::ostream& out, std::ostream& log);

}  // namespace demcal::cli
