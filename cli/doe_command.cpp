#include "cli/doe_command.hpp"

#include "study/doe_table.hpp"
#include "study/run_record.hpp"
#include "config/study_config.hpp"
#include "dem/simulation.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>
#include <utility>

namespace demcal::cli {

using namespace demcal::config;
using namespace demcal::study;
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string duration_text(double s) {
  char buf[64];
  if (s < 60.0)
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 3600.0)
    std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%dh%02dm", static_cast<int>(s) / 3600,
                  (static_cast<int>(s) / 60) % 60);
  return buf;
}

std::string seconds_text(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f s", s);
  return buf;
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
                        const std::function<bool()>& should_stop) {
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

  dem::Apparatus& apparatus = *chosen.apparatus;
  const dem::Simulation& sim = apparatus.simulation();
  std::string phase;
  const dem::StepObserver observe = [&](const dem::Simulation&, std::string_view p) {
    if (p != phase) phase = p;
    if (should_stop()) throw RunCancelled{};
  };

  ExecutedRun out;
  RunResults res;
  dem::ApparatusResult result;
  const Clock::time_point start = Clock::now();
  try {
    result = apparatus.run(observe);
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
  return out;
}

}  // namespace

Shard parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  auto number = [&](const std::string& s, std::size_t& v) {
    if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos)
      return false;
    v = static_cast<std::size_t>(std::stoul(s));
    return true;
  };
  Shard sh;
  if (slash == std::string::npos || !number(text.substr(0, slash), sh.index) ||
      !number(text.substr(slash + 1), sh.count) || sh.count < 1 || sh.index >= sh.count)
    throw ConfigError("--shard " + text + ": expected i/N with 0 <= i < N, e.g. --shard 0/2");
  return sh;
}

DoeOutcome run_doe(const DoeOptions& options, std::ostream& out, std::ostream& log) {
  const ProcessGroup& group = options.group;
  if (options.jobs < 1)
    throw ConfigError("--jobs " + std::to_string(options.jobs) + ": expected an integer >= 1");
  if (options.collect && (options.shard || options.dry_run))
    throw ConfigError("--collect runs nothing and writes the whole table; it takes no --shard or "
                      "--dry-run");

  // Every process reads the study; if one cannot, none goes on.
  DoePlan plan;
  std::exception_ptr plan_error;
  try {
    plan = plan_doe(options.study, options.overrides, options.apparatus, options.threads_per_run);
  } catch (...) {
    plan_error = std::current_exception();
  }
  if (!group.agree(!plan_error)) {
    if (plan_error) std::rethrow_exception(plan_error);
    throw ConfigError("another MPI rank could not read " + options.study.string() +
                      "; see its message");
  }

  const bool mpi = group.size > 1;
  const std::string who = mpi ? "rank " + std::to_string(group.rank) + "/" +
                                    std::to_string(group.size) + ": "
                              : "";
  DoeOutcome outcome;
  outcome.study_dir = options.output_dir / plan.study_name;
  outcome.runs_dir = options.run_store.empty() ? outcome.study_dir / "runs" : options.run_store;
  outcome.rows = plan.rows.size();
  outcome.runs = plan.runs.size();
  const RunStore store(outcome.runs_dir);

  // This process's share.
  std::vector<std::size_t> share;
  if (!options.collect) {
    std::size_t position = 0;
    for (std::size_t i = 0; i < plan.runs.size(); ++i) {
      if (options.shard && i % options.shard->count != options.shard->index) continue;
      if (position++ % static_cast<std::size_t>(group.size) == static_cast<std::size_t>(group.rank))
        share.push_back(i);
    }
  }
  outcome.assigned = share.size();

  // What the store holds already.
  std::vector<std::size_t> queue;
  std::vector<std::string> state(plan.runs.size());
  for (std::size_t i : share) {
    const PlannedRun& run = plan.runs[i];
    std::string problem;
    const std::optional<nlohmann::json> stored = store.load(run.key.hash, run.key.digest, &problem);
    if (stored) {
      const std::string status = stored->at("design").at("status").get<std::string>();
      if (status == "ok" || !options.retry_failed) {
        ++outcome.reused;
        state[i] = "stored (" + status + ")";
        continue;
      }
      state[i] = "to rerun (stored failed)";
    } else {
      state[i] = "to run";
      if (!problem.empty() && !options.dry_run)
        log << "demcal doe: " << who << "warning: " << problem << "; the run will be redone\n";
    }
    queue.push_back(i);
  }

  const std::string study_line =
      plan.study_name + ": " + std::to_string(plan.rows.size()) + " rows (" +
      std::to_string(plan.generated.points.size()) + " design points x " +
      std::to_string(plan.design.replicates) +
      (plan.design.replicates == 1 ? " replicate x " : " replicates x ") +
      std::to_string(plan.apparatus.size()) + " apparatus), " + std::to_string(plan.runs.size()) +
      " distinct runs";

  if (options.dry_run) {
    if (group.rank == 0) {
      out << "demcal doe: " << study_line << "\n";
      out << "store: " << outcome.runs_dir.string() << "\n";
      for (const PlanRow& row : plan.rows) {
        const PlannedRun& run = plan.runs[row.run];
        std::string s = state[row.run];
        if (s.empty()) {
          // Not this process's share: say what the store holds all the same.
          const auto stored = store.load(run.key.hash, run.key.digest);
          s = stored ? "stored (" + stored->at("design").at("status").get<std::string>() + ")"
                     : "to run (another shard)";
        }
        out << "  point " << row.point << " replicate " << row.replicate << " seed " << row.seed
            << " " << row.apparatus << " (" << describe_point(plan, row.point)
            << "): " << run.key.hash << " " << s << "\n";
      }
      out << "this process would run " << queue.size() << " of its " << share.size()
          << " runs (" << outcome.reused << " stored); nothing was written\n";
    }
    outcome.not_run = queue.size();
    return outcome;
  }

  if (plan.study_asks_for_vtk && group.rank == 0 && !options.quiet)
    log << "demcal doe: note: [output] vtk = true is ignored; a campaign writes no snapshots\n";
  const unsigned cores = std::thread::hardware_concurrency();
  if (!options.quiet && cores > 0 && queue.size() > 1 &&
      static_cast<unsigned>(options.jobs) * static_cast<unsigned>(plan.threads_per_run) > cores)
    log << "demcal doe: " << who << "note: " << options.jobs << " jobs x "
        << plan.threads_per_run << " threads per run exceed the " << cores
        << " cores of this machine\n";

  // ------------------------------------------------------------- execution
  std::exception_ptr run_error;
  const Clock::time_point start = Clock::now();
  if (!queue.empty()) {
    std::filesystem::create_directories(outcome.runs_dir);
    remove_stale_temporaries(outcome.runs_dir);

    struct Event {
      std::size_t run;
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
    const int workers = static_cast<int>(std::min<std::size_t>(
        static_cast<std::size_t>(options.jobs), queue.size()));

    const std::function<bool()> should_stop = [&] {
      return stop.load(std::memory_order_relaxed) ||
             (options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed));
    };
    auto worker = [&] {
      try {
        while (!should_stop()) {
          const std::size_t k = next.fetch_add(1);
          if (k >= queue.size()) break;
          const PlannedRun& run = plan.runs[queue[k]];
          ExecutedRun done = execute_run(plan, run, should_stop);
          if (done.cancelled) break;
          if (options.stop_after) {
            // At most stop_after runs are stored; the one that reaches it stops the others.
            const std::size_t n = stored_count.fetch_add(1);
            if (n >= *options.stop_after) {
              stop = true;
              break;
            }
            if (n + 1 == *options.stop_after) stop = true;
          }
          store.store(run.key.hash, done.record);
          std::lock_guard<std::mutex> lock(mutex);
          outcome.executed_hashes.push_back(run.key.hash);
          events.push_back({queue[k], done.ok, done.error, done.wall_time_s});
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

    // Report from this thread: a bar on a terminal, else a line per run.
    const std::size_t total = share.size();
    double run_seconds = 0.0;
    std::size_t bar_width = 0;
    bool bar_shown = false;
    double last_eta_s = 0.0;
    auto draw_bar = [&] {
      const std::size_t done = outcome.reused + outcome.executed;
      const double elapsed = seconds_since(start);
      constexpr std::size_t kCells = 24;
      const std::size_t filled = total > 0 ? done * kCells / total : kCells;
      std::string line = who + plan.study_name + " [" + std::string(filled, '#') +
                         std::string(kCells - filled, '.') + "] " + std::to_string(done) + "/" +
                         std::to_string(total) + " done, " + std::to_string(outcome.failed) +
                         " failed | " + duration_text(elapsed) + " elapsed | ETA ";
      if (outcome.executed > 0) {
        const double mean = run_seconds / static_cast<double>(outcome.executed);
        line += duration_text(mean * static_cast<double>(total - done) / options.jobs);
      } else {
        line += "?";
      }
      if (line.size() < bar_width) line.append(bar_width - line.size(), ' ');
      bar_width = line.size();
      log << '\r' << line << std::flush;
      bar_shown = true;
    };
    {
      std::unique_lock<std::mutex> lock(mutex);
      while (true) {
        wake.wait_for(lock, std::chrono::milliseconds(500),
                      [&] { return !events.empty() || workers_done == workers; });
        while (!events.empty()) {
          const Event e = std::move(events.front());
          events.pop_front();
          ++outcome.executed;
          if (!e.ok) ++outcome.failed;
          run_seconds += e.wall_time_s;
          if (!options.progress && !options.quiet) {
            const PlannedRun& run = plan.runs[e.run];
            log << "demcal doe: " << who << "[" << outcome.reused + outcome.executed << "/"
                << total << "] point " << run.point << " replicate " << run.replicate << " "
                << run.apparatus << " (" << describe_point(plan, run.point) << "): "
                << (e.ok ? "ok" : "failed") << " in " << seconds_text(e.wall_time_s)
                << (e.ok ? "" : ": " + e.error) << " -> runs/" << run.key.hash << ".json\n";
            // The ETA in a log too (no terminal, no bar): at most every 30 s and at the end.
            const double elapsed = seconds_since(start);
            const std::size_t done = outcome.reused + outcome.executed;
            if (elapsed - last_eta_s >= 30.0 || done == total) {
              last_eta_s = elapsed;
              const double mean = run_seconds / static_cast<double>(outcome.executed);
              log << "demcal doe: " << who << done << "/" << total << " done, " << outcome.failed << " failed, "
                  << duration_text(elapsed) << " elapsed"
                  << (done < total ? ", ETA " + duration_text(mean * static_cast<double>(total - done) / options.jobs)
                                   : std::string())
                  << "\n";
            }
            log << std::flush;
          }
        }
        if (options.progress) draw_bar();
        if (workers_done == workers) break;
      }
    }
    for (auto& t : threads) t.join();
    if (bar_shown) log << '\n' << std::flush;
  }
  outcome.not_run = share.size() - outcome.reused - outcome.executed;

  // Every process has stored its runs (or failed) before rank 0 reads the store.
  const bool all_ok = group.agree(!run_error);
  if (run_error) std::rethrow_exception(run_error);
  if (!all_ok)
    throw std::runtime_error("another MPI rank failed (see its message); the store keeps every "
                             "run that finished: run again to complete it");

  const bool writes_table = !options.shard && group.rank == 0;
  if (writes_table) {
    std::filesystem::create_directories(outcome.study_dir);
    remove_stale_temporaries(outcome.study_dir);
    // --collect writes only a whole table: one with a row missing would replace
    // the table the store was collected into before (a run file lost, a store
    // not yet merged) with a less complete one.
    const DoeTable table = write_doe_table(plan, store, outcome.study_dir, options.collect);
    outcome.missing = table.missing;
    outcome.ok = table.ok;
    outcome.table_written = !(options.collect && table.missing > 0);
    if (outcome.table_written) {
      outcome.table_csv = outcome.study_dir / "doe.csv";
      outcome.table_json = outcome.study_dir / "doe.json";
    }
  }

  // Summary.
  std::string share_text;
  if (options.shard)
    share_text += "shard " + std::to_string(options.shard->index) + "/" +
                  std::to_string(options.shard->count) + ": ";
  out << "demcal doe: " << who << share_text << study_line << "\n";
  if (!options.collect)
    out << "demcal doe: " << who << share.size() << " runs here: " << outcome.reused
        << " already stored, " << outcome.executed << " run (" << outcome.failed << " failed)"
        << (outcome.not_run > 0 ? ", " + std::to_string(outcome.not_run) + " not run" : "")
        << " in " << seconds_text(seconds_since(start)) << "\n";
  if (group.rank == 0) out << "store: " << outcome.runs_dir.string() << "\n";
  if (writes_table && !outcome.table_written) {
    out << "table: not written: " << outcome.missing << " of " << plan.rows.size()
        << " rows have no run in the store " << outcome.runs_dir.string() << "; "
        << (outcome.study_dir / "doe.csv").string() << " is left as it was\n";
  } else if (writes_table) {
    out << "table: " << outcome.table_csv.string() << " (" << plan.rows.size() << " rows";
    if (outcome.missing > 0) out << ", " << outcome.missing << " without a result yet";
    out << ")\n";
  } else if (options.shard && group.rank == 0) {
    out << "once every shard has finished: demcal doe " << options.study.string()
        << " --collect" << (options.output_dir != "out" ? " --output " + options.output_dir.string() : "")
        << "\n";
  }
  return outcome;
}

}  // namespace demcal::cli
