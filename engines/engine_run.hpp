#pragma once
// Runs a deck with the user's launch command ("lmp", "mpirun -np 4 lmp",
// "srun -n 8 liggghts", ...) in a directory: writes the deck, starts
// `<launch> -in <script> -log <log> -screen none` there, and reports the
// exit status and the engine's version from its log. A failed run throws with
// the engine's own ERROR line and the log's path.

#include "engines/deck.hpp"

#include <filesystem>
#include <string>

namespace demcal::engines {

struct EngineLaunch {
  std::string command = "lmp";  // everything before "-in": the executable, or an MPI/Slurm line
  std::string log_name = "log.engine";
};

struct EngineRunResult {
  std::filesystem::path directory;
  std::filesystem::path log;
  std::string engine_version;  // "LAMMPS (29 Sep 2021 - Update 2)", from the log's first line
  double wall_time_s = 0.0;
};

// Throws std::runtime_error when the engine exits non-zero or writes no final dump.
EngineRunResult run_engine(const Deck& deck, const EngineLaunch& launch,
                           const std::filesystem::path& directory);

// The first line of an engine log that names it ("LAMMPS (...)" or "LIGGGHTS (...)"); empty if
// none.
std::string engine_version_from_log(const std::filesystem::path& log);

// Whether `executable` is found on PATH (or is a path to an executable file).
bool executable_available(const std::string& executable);

}  // namespace demcal::engines
