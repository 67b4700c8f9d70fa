#pragma once
// The adaptive design ([design] kind = "adaptive"): a small space-filling start with some
// replicates, then batches chosen where they shrink the 95 % region of the calibrated
// parameters the most (weighted_variance_acquisition.hpp), until the region and the
// calibrated point are stable, the recordings prove out of the model's range, or the budget
// is spent. Knows nothing of DEM: the caller runs what it asks for.
//
// Resumable by construction: what the design asks for next is a pure function of (problem,
// options, the runs already done). A campaign killed at any moment restarts by passing the
// runs it has; the design replays its batches from them (re-fitting and re-calibrating,
// deterministically) and asks for exactly the runs an uninterrupted design would.
//
//   AdaptiveDesign design(problem, options);
//   std::vector<RunResult> done = ...;             // from the run store, any order
//   for (auto next = design.next_runs(done); !next.empty(); next = design.next_runs(done))
//     for (... each finished run ...) done.push_back(result);
//   design.history().to_text(names);              // what it did and why

#include "calibrate/adaptive_design_history.hpp"
#include "calibrate/adaptive_design_options.hpp"
#include "calibrate/adaptive_design_runs.hpp"
#include "calibrate/recording.hpp"
#include "calibrate/runs_calibration.hpp"

#include <memory>
#include <vector>

namespace demcal::calibrate {

struct AdaptiveDesignProblem {
  std::vector<ParameterBounds> parameters;  // the design box
  // What the design calibrates against; a run returns one value per recording, in order.
  std::vector<Recording> recordings;
};

class AdaptiveDesign {
 public:
  // Throws std::invalid_argument with options.Validate's message, or naming the problem's
  // fault (not 1 to 3 parameters, no recordings, bounds not finite or lower >= upper, sigma <= 0).
  AdaptiveDesign(AdaptiveDesignProblem problem, AdaptiveDesignOptions options);

  // The runs of the current batch not yet in `done` (empty when the design has ended; see
  // history().status). `done` may hold the runs in any order and a batch partly. Throws
  // std::invalid_argument when a run is not one the design chose (another seed, options or
  // recordings), is given twice, or belongs to a batch after the one the design is at.
  std::vector<RunRequest> next_runs(const std::vector<RunResult>& done);

  // Of the last next_runs() call.
  const AdaptiveDesignHistory& history() const { return history_; }
  // The calibration on the runs of every complete batch (the last one the history
  // reports); nullptr until batch 0 is complete.
  const RunsCalibration* latest_calibration() const;

  const AdaptiveDesignProblem& problem() const { return problem_; }
  const AdaptiveDesignOptions& options() const { return options_; }

 private:
  struct Stage;
  std::vector<RunRequest> start_batch() const;
  const Stage& stage(std::size_t batch, const std::vector<RunResult>& runs_so_far,
                     const std::vector<RunRequest>& this_batch);
  Stage analyse(std::size_t batch, const std::vector<RunResult>& runs_so_far,
                const std::vector<RunRequest>& this_batch) const;

  AdaptiveDesignProblem problem_;
  AdaptiveDesignOptions options_;
  AdaptiveDesignHistory history_;
  // Memo of complete batches: re-used while the runs they were computed from are unchanged,
  // so a driver calling next_runs() after every batch does not re-fit every earlier batch.
  std::vector<std::shared_ptr<const Stage>> stages_;
  std::shared_ptr<const Stage> latest_;
};

struct AdaptiveDesignResult {
  AdaptiveDesignHistory history;
  std::vector<RunResult> runs;  // in design order
  RunsCalibration calibration;  // on all runs
};

// The loop: asks for a batch, has `evaluate` run it, repeats until the design ends.
// `done`: runs of an earlier, interrupted design to resume from. Throws as
// AdaptiveDesign, and std::runtime_error when `evaluate` returns the wrong number of results.
AdaptiveDesignResult run_adaptive_design(const AdaptiveDesignProblem& problem,
                                         const AdaptiveDesignOptions& options,
                                         const RunEvaluator& evaluate,
                                         std::vector<RunResult> done = {});

}  // namespace demcal::calibrate
