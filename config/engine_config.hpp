#pragma once
// The [engine] table of a study config: which DEM engine runs the study's
// design points. Absent (or kind = "demcal"): demcal's own engine, and nothing
// changes: the table is not part of any run key (study/run_store.hpp). Another
// engine is driven through study/engine_evaluator.hpp: demcal writes its input
// deck from the same apparatus description, runs it with `launch`, reads the
// dumps back and measures them with its own code.
//
//   [engine]                          # opt
//   kind = "liggghts"                 # "demcal" (default) | "liggghts" | "lammps"
//   launch = "mpirun -np 2 liggghts"  # opt, liggghts/lammps only: the command line the
//                                     #   deck is run with (everything before "-in"; an
//                                     #   srun line on a cluster); default "liggghts" or
//                                     #   "lmp". Not in the run key: where and on how many
//                                     #   ranks a run went is recorded in the run file,
//                                     #   the engine and its version are in the key.
//   allow_rolling_substitute = true   # opt, lammps only (default false): run demcal's
//                                     #   "cdt" rolling as LAMMPS's "rolling sds" (same
//                                     #   limiting torque, an elastic phase below it)
//                                     #   instead of refusing it
//   allow_dry_walls = true            # opt, lammps only (default false): with adhesion
//                                     #   "jkr", run the walls without adhesion instead of
//                                     #   refusing a particle_wall surface energy (LAMMPS
//                                     #   29Sep2021's wall JKR fails; engines/README.md)
//   Both change the engine's run, so when true they are in its run key; the mapping
//   record of every run lists each substitution made.
//   timeout_s = 3600.0                # opt, liggghts/lammps only, s, > 0 (default: none):
//                                     #   wall-clock limit of one engine run; the engine's
//                                     #   processes are then ended (SIGTERM, SIGKILL after
//                                     #   5 s) and the run is stored as failed ("timed out
//                                     #   after N s"). Not in the run key: it does not change
//                                     #   what a run that finishes computes, and a run that
//                                     #   timed out is redone by --retry-failed with a larger one.

#include "config/toml_reader.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace demcal::config {

// "demcal", "liggghts", "lammps".
const std::vector<std::string>& known_engine_kinds();

struct EngineConfig {
  std::string kind = "demcal";
  std::string launch;  // empty for demcal
  bool allow_rolling_substitute = false;  // engines::MappingOptions of the same names
  bool allow_dry_walls = false;
  std::optional<double> timeout_s;  // s; none when absent
  std::size_t line = 0;
  std::string file;  // the study file, for messages

  bool is_demcal() const { return kind == "demcal"; }
  // "study.toml:12: engine" — the prefix of messages about this table.
  std::string where() const;
};

// Reads [engine] if present (nullopt when absent). An unknown kind, an empty
// launch line, or a launch line with kind = "demcal" is a ConfigError naming
// the key.
std::optional<EngineConfig> read_engine(reader::Table& root, const std::string& file);

}  // namespace demcal::config
