#include "study/adaptive_campaign.hpp"

#include "io/atomic_file.hpp"
#include "config/observables.hpp"
#include "config/study_config.hpp"
#include "study/calibration_targets.hpp"
#include "study/doe_table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <utility>

namespace demcal::study {

using config::ConfigError;
using config::observable_names;
using config::StudyConfig;

namespace {

using RunId = std::pair<std::size_t, std::size_t>;  // (batch, slot)

// Per request, the value of each recording from the stored runs: NaN where a run failed,
// did not measure it, or is not stored yet; `complete` says whether every run is stored.
struct BatchValues {
  std::map<RunId, std::vector<double>> values;
  std::map<RunId, bool> stored;
};

BatchValues read_values(const DoePlan& plan, const RunStore& store,
                        const std::vector<calibrate::Recording>& recordings) {
  std::vector<std::optional<nlohmann::json>> records;
  records.reserve(plan.runs.size());
  for (const PlannedRun& run : plan.runs) records.push_back(store.load(run.key.hash, run.key.digest));
  // The table's rows carry the observables as doe.csv has them (series ones derived).
  const DoeTable table = make_doe_table(plan, records);
  BatchValues out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto& rows = table.json.at("rows");
  for (std::size_t i = 0; i < plan.rows.size(); ++i) {
    const PlanRow& row = plan.rows[i];
    const RunId id{*row.batch, *row.slot};
    auto& v = out.values.try_emplace(id, recordings.size(), nan).first->second;
    auto [st, fresh] = out.stored.try_emplace(id, true);
    const nlohmann::json& r = rows.at(i);
    const std::string status = r.at("status").get<std::string>();
    st->second = st->second && status != "missing";
    (void)fresh;
    if (status != "ok") continue;
    for (std::size_t k = 0; k < recordings.size(); ++k) {
      if (recordings[k].setup != row.apparatus) continue;
      const nlohmann::json& o = r.at("observables").value(recordings[k].observable, nlohmann::json());
      if (o.is_number()) v[k] = o.get<double>();
    }
  }
  return out;
}

}  // namespace

AdaptiveStudyDesign adaptive_study_design(const DoePlan& plan) {
  if (!plan.design.adaptive)
    throw std::logic_error("adaptive_study_design: the study's design is not adaptive");
  const StudyConfig study = build_study(plan.source.document());
  const std::string at = plan.file + ":" + std::to_string(plan.design.line) + ": design: ";
  if (!study.calibration)
    throw ConfigError(at + "kind = \"adaptive\" designs for the study's recordings: add "
                           "[calibration] recordings = \"...\"");
  if (!study.surrogate || study.surrogate->spec.model != "gaussian_process")
    throw ConfigError(at + "kind = \"adaptive\" needs [surrogate] model = \"gaussian_process\" "
                           "(the design uses the surrogates' predictive variance)");
  AdaptiveStudyDesign d;
  d.problem.parameters = design_bounds(study);
  d.problem.recordings = study_recordings(study);
  const std::vector<std::string>& columns = observable_names();
  for (const calibrate::Recording& r : d.problem.recordings) {
    const std::string where = r.file + ":" + std::to_string(r.line);
    if (std::find(plan.apparatus.begin(), plan.apparatus.end(), r.setup) == plan.apparatus.end())
      throw ConfigError(where + ": " + r.setup + " is recorded, but the campaign does not run it "
                                "(--apparatus); an adaptive design needs every recorded setup");
    if (std::find(columns.begin(), columns.end(), r.observable) == columns.end())
      throw ConfigError(where + ": " + r.observable +
                        " is not an observable of a design table; an adaptive design needs "
                        "recordings of scalar observables");
  }
  d.options = *plan.design.adaptive;
  d.options.surrogate = study.surrogate->spec;
  d.options.calibration = calibration_options(*study.calibration);
  // The region, not the posterior, steers the design (docs/adaptive_design.md).
  d.options.calibration.mcmc_samples = 0;
  return d;
}

AdaptiveCampaignOutcome run_adaptive_campaign(DoePlan& plan, const RunStore& store,
                                              const DesignRunOptions& options,
                                              ProgressObserver& observer, bool dry_run) {
  const AdaptiveStudyDesign d = adaptive_study_design(plan);
  calibrate::AdaptiveDesign design(d.problem, d.options);
  AdaptiveCampaignOutcome out;
  for (const auto& p : d.problem.parameters) out.parameter_names.push_back(p.name);

  std::vector<calibrate::RunRequest> asked;  // design order
  std::vector<calibrate::RunResult> done;
  for (;;) {
    const std::vector<calibrate::RunRequest> next = design.next_runs(done);
    if (next.empty()) {
      out.finished = true;
      break;
    }
    for (const calibrate::RunRequest& r : next) {
      const bool known = std::any_of(asked.begin(), asked.end(), [&](const auto& a) {
        return a.batch == r.batch && a.slot == r.slot;
      });
      if (!known) asked.push_back(r);
    }
    plan_adaptive_runs(plan, asked);
    BatchValues values = read_values(plan, store, d.problem.recordings);
    const auto missing = [&] {
      std::size_t n = 0;
      for (const auto& r : next) n += values.stored.at({r.batch, r.slot}) ? 0 : 1;
      return n;
    };
    std::size_t to_run = missing();
    out.reused += next.size() - to_run;
    if (to_run > 0) {
      if (dry_run) {
        out.not_run = to_run;
        out.waiting = "batch " + std::to_string(next.front().batch) + " has " +
                      std::to_string(to_run) + " runs to do (dry run: nothing was run)";
        break;
      }
      DesignRunOptions run_options = options;
      if (options.stop_after) {
        if (out.ran.executed >= *options.stop_after) {
          out.not_run = to_run;
          out.waiting = "stopped after " + std::to_string(out.ran.executed) + " runs (--stop-after)";
          break;
        }
        run_options.stop_after = *options.stop_after - out.ran.executed;
      }
      DesignRunner runner(plan, store, run_options);
      out.problems.insert(out.problems.end(), runner.share().problems.begin(),
                          runner.share().problems.end());
      const DesignRunResult ran = runner.run(observer);
      out.ran.executed += ran.executed;
      out.ran.failed += ran.failed;
      out.ran.executed_hashes.insert(out.ran.executed_hashes.end(), ran.executed_hashes.begin(),
                                     ran.executed_hashes.end());
      values = read_values(plan, store, d.problem.recordings);
      to_run = missing();
      if (to_run > 0) {
        out.not_run = to_run;
        out.waiting = "batch " + std::to_string(next.front().batch) + " has " +
                      std::to_string(to_run) + " runs not in the store yet" +
                      (options.shard ? " (other shards' share: run every shard again once they "
                                       "have finished, on one store)"
                                     : "");
        break;
      }
    }
    for (const calibrate::RunRequest& r : next) {
      const bool have = std::any_of(done.begin(), done.end(), [&](const auto& x) {
        return x.request.batch == r.batch && x.request.slot == r.slot;
      });
      if (!have) done.push_back({r, values.values.at({r.batch, r.slot})});
    }
  }
  out.history = design.history();
  plan_adaptive_runs(plan, asked);
  return out;
}

void write_design_history(const std::filesystem::path& study_dir,
                          const AdaptiveCampaignOutcome& outcome) {
  nlohmann::json j = outcome.history.to_json();
  j["parameters"] = outcome.parameter_names;
  j["text"] = outcome.history.to_text(outcome.parameter_names);
  std::filesystem::create_directories(study_dir);
  io::write_file_atomically(study_dir / "design_history.json", j.dump(2) + "\n");
}

}  // namespace demcal::study
