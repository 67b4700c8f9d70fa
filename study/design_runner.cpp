#include "study/design_runner.hpp"

#include "config/study_config.hpp"
#include "dem/simulation.hpp"
#include "study/run_evaluator.hpp"
#include "study/run_record.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <utility>

namespace demcal::study {

using config::select_apparatus;
using config::StudyApparatus;
using config::StudyConfig;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Thrown from the step observer to abandon a run; not a std::exception, so
// nothing on the way up mistakes it for a failed run.
struct RunCancelled {};

struct ExecutedRun {
  nlohmann::json record;
  bool ok = false;
  bool cancelled = false;
  std::string error;
  double wall_time_s = 0.0;
};

ExecutedRun execute_run(const DoePlan& plan, const PlannedRun& run,
                        const std::function<bool()>& should_stop,
                        const std::filesystem::path& engine_runs, const RunEvaluator& evaluator) {
  // The plan built this study already (with the study's seed); a failure now
  // is not a result of the run but a fault, and stops the campaign.
  std::optional<StudyConfig> built;
  try {
    built.emplace(build_study(run_document(plan, run)));
  } catch (const std::exception& e) {
    throw std::runtime_error("doe: point " + std::to_string(run.point) + " replicate " +
                             std::to_string(run.replicate) + " (seed " + std::to_string(run.seed) +
                             "): the study does not build: " + e.what());
  }
  StudyConfig& study = *built;
  StudyApparatus& chosen = select_apparatus(study, run.apparatus);
  // The file is named by the key: the study run must be the one planned.
  if (run_key_for(study, chosen.name, run.seed, plan.threads_per_run).digest != run.key.digest)
    throw std::logic_error("doe: run " + run.key.hash + " (point " + std::to_string(run.point) +
                           ") does not rebuild with the key it was planned with");
  // As for `demcal simulate`: no parallel region may start more threads than
  // allowed. The default is this worker thread's own.
  omp_set_num_threads(plan.threads_per_run);

  const dem::Simulation& sim = chosen.apparatus->simulation();
  std::string phase;
  const dem::StepObserver observe = [&](const dem::Simulation&, std::string_view p) {
    if (p != phase) phase = p;
    if (should_stop()) throw RunCancelled{};
  };

  // The DEM, another engine ([engine]) or an analytic model (study/run_evaluator.hpp).
  const std::unique_ptr<PreparedRun> prepared = evaluator.prepare(
      {study, chosen, run.seed, plan.threads_per_run, engine_runs / run.key.hash, observe});
  ExecutedRun out;
  RunResults res;
  dem::ApparatusResult result;
  const Clock::time_point start = Clock::now();
  try {
    result = prepared->run();
    out.ok = true;
    res.stopped_because = "finished";
  } catch (const RunCancelled&) {
    out.cancelled = true;
    return out;
  } catch (const std::exception& e) {
    res.stopped_because = "error";
    res.error = out.error = e.what();
  }
  res.phase = phase;
  res.wall_time_s = out.wall_time_s = seconds_since(start);
  res.time_step_s =
      sim.step_count() > 0 ? sim.time_s() / static_cast<double>(sim.step_count()) : 0.0;

  out.record = make_apparatus_run_record(study, chosen, res, out.ok ? &result : nullptr);
  out.record["inputs"].erase("output");  // not part of the run (run_store.hpp)
  prepared->describe(out.record);
  nlohmann::json values = nlohmann::json::object();
  const auto& params = plan.design.spec.parameters;
  for (std::size_t i = 0; i < params.size(); ++i)
    values[params[i].name] = plan.generated.points[run.point][i];
  out.record["design"] = {{"status", out.ok ? "ok" : "failed"},
                          {"hash", run.key.hash},
                          {"digest", run.key.digest},
                          {"key_version", kRunKeyVersion},
                          {"kind", surrogate::design_kind_name(plan.design.spec.kind)},
                          {"point", run.point},
                          {"replicate", run.replicate},
                          {"seed", run.seed},
                          {"threads_per_run", plan.threads_per_run},
                          {"parameters", values}};
  if (plan.design.adaptive) {
    // Which run of the design it is; a store shared with other studies keeps the first
    // study's (the run key, the hash of the inputs, does not hold them).
    out.record["design"]["kind"] = "adaptive";
    if (run.batch) out.record["design"]["batch"] = *run.batch;
    if (run.slot) out.record["design"]["slot"] = *run.slot;
  }
  return out;
}

}  // namespace

DesignRunner::DesignRunner(const DoePlan& plan, const RunStore& store, DesignRunOptions options,
                           bool collect)
    : plan_(plan), store_(store), options_(std::move(options)) {
  const ProcessGroup& group = options_.group;
  if (!collect) {
    std::size_t position = 0;
    for (std::size_t i = 0; i < plan.runs.size(); ++i) {
      if (options_.shard && i % options_.shard->count != options_.shard->index) continue;
      if (position++ % static_cast<std::size_t>(group.size) == static_cast<std::size_t>(group.rank))
        share_.assigned.push_back(i);
    }
  }
  share_.state.resize(plan.runs.size());
  for (std::size_t i : share_.assigned) {
    const PlannedRun& run = plan.runs[i];
    std::string problem;
    const std::optional<nlohmann::json> stored = store.load(run.key.hash, run.key.digest, &problem);
    if (stored) {
      const std::string status = stored->at("design").at("status").get<std::string>();
      if (status == "ok" || !options_.retry_failed) {
        ++share_.reused;
        share_.state[i] = "stored (" + status + ")";
        continue;
      }
      share_.state[i] = "to rerun (stored failed)";
    } else {
      share_.state[i] = "to run";
      if (!problem.empty()) share_.problems.push_back(problem);
    }
    share_.queue.push_back(i);
  }
}

DesignRunResult DesignRunner::run(ProgressObserver& observer) {
  const std::vector<std::size_t>& queue = share_.queue;
  DesignRunResult result;
  std::exception_ptr run_error;
  if (!queue.empty()) {
    std::filesystem::create_directories(store_.directory());
    remove_stale_temporaries(store_.directory());

    // What the workers tell the reporting thread (this one).
    struct Event {
      std::size_t run;
      bool finished;  // else started
      bool ok;
      std::string error;
      double wall_time_s;
    };
    std::mutex mutex;
    std::condition_variable wake;
    std::deque<Event> events;
    std::atomic<std::size_t> next{0};
    std::atomic<std::size_t> stored_count{0};
    std::atomic<bool> stop{false};
    int workers_done = 0;
    const int workers = static_cast<int>(
        std::min<std::size_t>(static_cast<std::size_t>(options_.jobs), queue.size()));
    const Clock::time_point start = Clock::now();

    const std::function<bool()> should_stop = [&] {
      return stop.load(std::memory_order_relaxed) ||
             (options_.cancel != nullptr && options_.cancel->load(std::memory_order_relaxed));
    };
    auto worker = [&] {
      try {
        while (!should_stop()) {
          const std::size_t k = next.fetch_add(1);
          if (k >= queue.size()) break;
          const PlannedRun& run = plan_.runs[queue[k]];
          {
            std::lock_guard<std::mutex> lock(mutex);
            events.push_back({queue[k], false, false, {}, 0.0});
          }
          ExecutedRun done =
              execute_run(plan_, run, should_stop, store_.directory().parent_path() / "engine-runs",
                          options_.evaluator != nullptr ? *options_.evaluator
                                                        : default_run_evaluator());
          if (done.cancelled) break;
          if (options_.stop_after) {
            // At most stop_after runs are stored; the one that reaches it stops the others.
            const std::size_t n = stored_count.fetch_add(1);
            if (n >= *options_.stop_after) {
              stop = true;
              break;
            }
            if (n + 1 == *options_.stop_after) stop = true;
          }
          store_.store(run.key.hash, done.record);
          std::lock_guard<std::mutex> lock(mutex);
          result.executed_hashes.push_back(run.key.hash);
          events.push_back({queue[k], true, done.ok, done.error, done.wall_time_s});
          wake.notify_all();
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!run_error) run_error = std::current_exception();
        stop = true;
      }
      std::lock_guard<std::mutex> lock(mutex);
      ++workers_done;
      wake.notify_all();
    };
    std::vector<std::thread> threads;
    for (int w = 0; w < workers; ++w) threads.emplace_back(worker);

    // Report from this thread, so that the observer need not be thread-safe.
    DesignProgress progress;
    progress.total = share_.assigned.size();
    progress.reused = share_.reused;
    {
      std::unique_lock<std::mutex> lock(mutex);
      while (true) {
        wake.wait_for(lock, std::chrono::milliseconds(500),
                      [&] { return !events.empty() || workers_done == workers; });
        while (!events.empty()) {
          const Event e = std::move(events.front());
          events.pop_front();
          if (!e.finished) {
            observer.on_run_started(plan_.runs[e.run]);
            continue;
          }
          ++progress.executed;
          if (!e.ok) ++progress.failed;
          progress.run_seconds += e.wall_time_s;
          progress.elapsed_s = seconds_since(start);
          observer.on_run_finished({&plan_.runs[e.run], e.ok, e.error, e.wall_time_s}, progress);
        }
        progress.elapsed_s = seconds_since(start);
        observer.on_progress(progress);
        if (workers_done == workers) break;
      }
    }
    for (auto& t : threads) t.join();
    result.executed = progress.executed;
    result.failed = progress.failed;
  }

  // Every process has stored its runs (or failed) before any reads the store.
  const bool all_ok = options_.group.agree(!run_error);
  if (run_error) std::rethrow_exception(run_error);
  if (!all_ok)
    throw std::runtime_error(
        "another MPI rank failed (see its message); the store keeps every "
        "run that finished: run again to complete it");
  return result;
}

}  // namespace demcal::study
