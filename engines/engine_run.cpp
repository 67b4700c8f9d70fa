#include "engines/engine_run.hpp"

#include "engines/engine_process.hpp"

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

namespace demcal::engines {
namespace {

// Single-quoted for /bin/sh: the directory may hold spaces.
std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string last_error_line(const std::filesystem::path& log) {
  std::ifstream in(log);
  std::string line, error;
  while (std::getline(in, line))
    if (line.rfind("ERROR", 0) == 0) error = line;
  return error;
}

}  // namespace

std::string engine_version_from_log(const std::filesystem::path& log) {
  std::ifstream in(log);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("LAMMPS (", 0) == 0 || line.rfind("LIGGGHTS (", 0) == 0) return line;
  return "";
}

bool executable_available(const std::string& executable) {
  if (executable.find('/') != std::string::npos) return ::access(executable.c_str(), X_OK) == 0;
  const char* path = std::getenv("PATH");
  if (path == nullptr) return false;
  std::istringstream dirs(path);
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && ::access((std::filesystem::path(dir) / executable).c_str(), X_OK) == 0)
      return true;
  return false;
}

EngineRunResult run_engine(const Deck& deck, const EngineLaunch& launch,
                           const std::filesystem::path& directory) {
  write_deck_files(deck, directory);
  EngineRunResult r;
  r.directory = directory;
  r.log = directory / launch.log_name;
  ProcessOptions p;
  p.command_line = launch.command + " -in " + quoted(deck.script_name) + " -log " +
                   quoted(launch.log_name) +
                   // LIGGGHTS 3.8 crashes writing its warnings with -screen none.
                   (deck.engine == "liggghts" ? "" : " -screen none");
  p.working_directory = directory;
  p.output = "engine.stdout";  // in the directory (which may be relative to ours)
  p.timeout_s = launch.timeout_s;
  p.cancel = launch.cancel;
  p.poll = launch.poll;
  p.grace_period_s = launch.grace_period_s;
  const ProcessOutcome outcome = run_process(p);
  r.wall_time_s = outcome.wall_time_s;
  r.engine_version = engine_version_from_log(r.log);
  if (!outcome.succeeded()) {
    // A run cut short has no ERROR of its own to report: its reason is the cut.
    const bool cut = outcome.ended == ProcessOutcome::Ended::timed_out ||
                     outcome.ended == ProcessOutcome::Ended::cancelled;
    const std::string error = cut ? "" : last_error_line(r.log);
    throw std::runtime_error(deck.engine + " run " + (cut ? "stopped" : "failed") +
                             " (launch line \"" + launch.command + "\", in " + directory.string() +
                             "): " + outcome.describe() + (error.empty() ? "" : ": " + error) +
                             "; see " + r.log.string() + " and " + (directory / p.output).string());
  }
  if (!std::filesystem::exists(directory / deck.final_dump_name))
    throw std::runtime_error(deck.engine + " run wrote no " + deck.final_dump_name + "; see " +
                             r.log.string());
  return r;
}

}  // namespace demcal::engines
