#pragma once
// Runs a deck with the user's launch command ("lmp", "mpirun -np 4 lmp",
// "srun -n 8 liggghts", ...) in a directory: writes the deck, starts
// `<launch> -in <script> -log <log> -screen none` there (engines/engine_process.hpp:
// a process group of its own, output to engine.stdout, cancellable), and
// reports the exit status and the engine's version from its log. A failed,
// timed-out or cancelled run throws with the engine, the launch line, the
// reason (the engine's own ERROR line when it wrote one) and the log's path.

#include "engines/deck.hpp"

#include <atomic>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace demcal::engines {

struct EngineLaunch {
  std::string command = "lmp";  // everything before "-in": the executable, or an MPI/Slurm line
  std::string log_name = "log.engine";
  std::optional<double> timeout_s;            // wall-clock limit of the run; none when absent
  const std::atomic<bool>* cancel = nullptr;  // set from elsewhere to end the run
  // Called while the engine runs (every 50 ms); may throw to cancel the run:
  // the engine's process group is ended and the exception passes through.
  std::function<void()> poll;
  double grace_period_s = 5.0;  // between SIGTERM and SIGKILL to the engine's group
};

struct EngineRunResult {
  std::filesystem::path directory;
  std::filesystem::path log;
  std::string engine_version;  // "LAMMPS (29 Sep 2021 - Update 2)", from the log's first line
  double wall_time_s = 0.0;
};

// Throws std::runtime_error when the engine exits non-zero, is killed, times
// out, is cancelled (cancel flag, SIGINT) or writes no final dump.
EngineRunResult run_engine(const Deck& deck, const EngineLaunch& launch,
                           const std::filesystem::path& directory);

// The first line of an engine log that names it ("LAMMPS (...)" or "LIGGGHTS (...)"); empty if
// none.
std::string engine_version_from_log(const std::filesystem::path& log);

// Whether `executable` is found on PATH (or is a path to an executable file).
bool executable_available(const std::string& executable);

}  // namespace demcal::engines
