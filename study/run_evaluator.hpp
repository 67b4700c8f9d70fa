#pragma once
// What evaluates one planned run of a design: the study built for the run's
// point (its design values, seed and threads written in) and the apparatus to
// run -> that apparatus' result (observables, series, details), which the
// design runner (study/design_runner.hpp) turns into the run record it stores.
//
// Three evaluators implement it:
//   - DemRunEvaluator (below), the default: demcal's own DEM runs the
//     apparatus, or, when the study has an [engine] table naming another
//     engine, that engine runs it (study/engine_evaluator.hpp);
//   - AnalyticEvaluator (study/analytic_evaluator.hpp): closed-form
//     observables with seeded noise, so that the whole workflow (`study`,
//     `diagnose`) runs end to end in seconds in the tests.
// The run key (study/run_store.hpp) is not the evaluator's business: it is the
// hash of the study, so a store must not mix evaluators (the analytic one
// marks its records with "evaluator" so that such a store can be told apart).
//
// An evaluation has two steps, so that a fault is told apart from a failed
// run: prepare() throws for a run that cannot be attempted at all (an engine
// that cannot run the apparatus: the campaign stops), PreparedRun::run()
// throws for a run that failed (an instability: stored with status "failed").

#include "config/study_config.hpp"
#include "dem/apparatus/apparatus.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>

namespace demcal::study {

// One planned run as the design runner asks for it.
struct RunRequest {
  config::StudyConfig& study;           // built for the run's point and seed
  config::StudyApparatus& apparatus;    // of `study`: the one to run
  std::uint64_t seed = 0;               // the run's seed (also in study.resolved)
  int threads = 1;                      // OpenMP threads the run may use
  std::filesystem::path work_directory;  // for evaluators that write files (another engine's deck)
  const dem::StepObserver& observe;     // to be called as the run advances (it may throw to cancel)
  // study, apparatus and observe outlive the PreparedRun made from the request.
};

// A run ready to go.
class PreparedRun {
 public:
  virtual ~PreparedRun() = default;
  // Runs it. Throws (std::exception) when the run fails; an exception of
  // another type thrown by the request's observer (a cancellation) must pass through.
  virtual dem::ApparatusResult run() = 0;
  // Adds to the run's record what says how it was evaluated (called after
  // run(), whether it succeeded or threw). Nothing, for demcal's own DEM.
  virtual void describe(nlohmann::json& record) const { (void)record; }
};

class RunEvaluator {
 public:
  virtual ~RunEvaluator() = default;
  // Called from the design runner's worker threads at once: must be thread-safe.
  // Throws for a run that cannot be attempted (the campaign stops).
  virtual std::unique_ptr<PreparedRun> prepare(const RunRequest& request) const = 0;
};

// demcal's own DEM, or the study's [engine] when it names another engine: what
// `demcal doe` has always run. Its records are those it always wrote.
class DemRunEvaluator final : public RunEvaluator {
 public:
  std::unique_ptr<PreparedRun> prepare(const RunRequest& request) const override;
};

// The evaluator used when none is given.
const RunEvaluator& default_run_evaluator();

}  // namespace demcal::study
