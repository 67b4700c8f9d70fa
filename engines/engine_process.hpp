#pragma once
// Starts one engine process from a user's shell line ("lmp -in deck ...",
// "mpirun -np 2 lmp ...", "srun -n 32 liggghts ...") and waits for it in a way
// that can be cut short: `/bin/sh -c <line>` is spawned in a process group of
// its own, its stdout and stderr go to one file, and the wait polls, so that a
// wall-clock limit, a cancel flag set by another thread, a caller's poll
// callback (the design runner's stop request) or a SIGINT / SIGTERM sent to
// demcal ends the whole group: SIGTERM to every process of it (mpirun passes it
// on to its ranks), a grace period, then SIGKILL, and the leader reaped. Nothing
// started here outlives the call.
//
// SIGINT and SIGTERM: while at least one process runs, demcal catches them (the
// group being its own, the terminal's Ctrl-C no longer reaches the engine);
// every running launch ends its group, and when the last has, the disposition
// demcal had is restored and the signal raised again, so demcal ends as it
// would have (no run is then recorded). If that disposition does not end the
// process, the launch reports "interrupted by SIGINT".

#include <atomic>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace demcal::engines {

struct ProcessOptions {
  std::string command_line;                   // run by /bin/sh -c, in `working_directory`
  std::filesystem::path working_directory;    // must exist
  std::filesystem::path output;               // stdout and stderr (truncated); a relative path is
                                              // taken in `working_directory`
  std::optional<double> timeout_s;            // wall-clock limit; none when absent
  const std::atomic<bool>* cancel = nullptr;  // set from elsewhere to end the process
  // Called at each poll; it may throw to cancel: the group is ended and the
  // exception passes through unchanged.
  std::function<void()> poll;
  double grace_period_s = 5.0;  // between SIGTERM and SIGKILL
  double poll_interval_s = 0.05;
};

struct ProcessOutcome {
  enum class Ended { exited, signalled, timed_out, cancelled };
  Ended ended = Ended::exited;
  int exit_code = 0;  // when exited
  int signal = 0;     // when signalled (or the signal that interrupted demcal)
  double wall_time_s = 0.0;
  std::string reason;  // "cancelled", "interrupted by SIGINT", "timed out after 2 s"

  bool succeeded() const { return ended == Ended::exited && exit_code == 0; }
  // "exited with status 1", "killed by SIGSEGV", "timed out after 2 s", ...
  std::string describe() const;
};

// Runs the line to its end (or its cancellation). Throws std::runtime_error
// when the process cannot be started (the output file cannot be opened, spawn fails).
ProcessOutcome run_process(const ProcessOptions& options);

// "SIGSEGV" for SIGSEGV, "signal 40" for one without a common name.
std::string signal_name(int signal);

}  // namespace demcal::engines
