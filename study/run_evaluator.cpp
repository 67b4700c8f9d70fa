#include "study/run_evaluator.hpp"

#include "study/engine_evaluator.hpp"

#include <utility>

namespace demcal::study {
namespace {

// demcal's own engine: the apparatus runs its protocol.
class DemRun final : public PreparedRun {
 public:
  DemRun(dem::Apparatus& apparatus, const dem::StepObserver& observe)
      : apparatus_(apparatus), observe_(observe) {}
  dem::ApparatusResult run() override { return apparatus_.run(observe_); }

 private:
  dem::Apparatus& apparatus_;
  const dem::StepObserver& observe_;
};

}  // namespace

std::unique_ptr<PreparedRun> DemRunEvaluator::prepare(const RunRequest& r) const {
  // The engine is polled with the runner's observer, so that a stop request
  // (which it throws) ends the engine's processes too. No phase of demcal's:
  // the record's "phase" stays empty for an engine run, as before.
  const dem::StepObserver& observe = r.observe;
  const dem::Simulation& sim = r.apparatus.apparatus->simulation();
  std::optional<EngineEvaluator> engine = EngineEvaluator::for_run(
      r.study, r.apparatus, r.work_directory, [&observe, &sim] { observe(sim, ""); });
  if (engine) return std::make_unique<EngineEvaluator>(std::move(*engine));
  return std::make_unique<DemRun>(*r.apparatus.apparatus, r.observe);
}

const RunEvaluator& default_run_evaluator() {
  static const DemRunEvaluator dem;
  return dem;
}

}  // namespace demcal::study
