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
  std::optional<EngineEvaluator> engine =
      EngineEvaluator::for_run(r.study, r.apparatus, r.work_directory);
  if (engine) return std::make_unique<EngineEvaluator>(std::move(*engine));
  return std::make_unique<DemRun>(*r.apparatus.apparatus, r.observe);
}

const RunEvaluator& default_run_evaluator() {
  static const DemRunEvaluator dem;
  return dem;
}

}  // namespace demcal::study
