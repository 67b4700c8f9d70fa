#include "config/engine_config.hpp"

#include <algorithm>
#include <cctype>

namespace demcal::config {

const std::vector<std::string>& known_engine_kinds() {
  static const std::vector<std::string> kinds{"demcal", "liggghts", "lammps"};
  return kinds;
}

std::string EngineConfig::where() const { return file + ":" + std::to_string(line) + ": engine"; }

std::optional<EngineConfig> read_engine(reader::Table& root, const std::string& file) {
  if (!root.has("engine")) return std::nullopt;
  reader::Table t = root.table("engine");
  EngineConfig c;
  c.line = t.line();
  c.file = file;
  c.kind = t.choice_or("kind", known_engine_kinds(), "demcal");
  if (c.is_demcal()) {
    // demcal runs inside this process: a launch line would be silently ignored.
    for (const char* key : {"launch", "timeout_s"})
      if (t.has(key))
        t.fail(key, "is for kind = \"liggghts\" or \"lammps\" only (demcal runs in process)");
  } else {
    c.launch = t.string_or("launch", c.kind == "lammps" ? "lmp" : "liggghts");
    const bool blank = std::all_of(c.launch.begin(), c.launch.end(),
                                   [](unsigned char ch) { return std::isspace(ch) != 0; });
    if (blank)
      t.fail("launch", "expected the command that starts " + c.kind + " (e.g. \"" +
                           (c.kind == "lammps" ? "lmp" : "mpirun -np 2 liggghts") +
                           "\"), not an empty string");
    // The line is given to /bin/sh with " -in <deck>" appended: a newline or
    // a trailing ';', '&' or '|' would run the engine without its deck.
    if (c.launch.find_first_of("\n\r") != std::string::npos)
      t.fail("launch", "expected one command line (it holds a line break)");
    const std::size_t last = c.launch.find_last_not_of(" \t");
    if (std::string(";&|").find(c.launch[last]) != std::string::npos)
      t.fail("launch", "expected a command that takes \"-in <deck>\" after it; it ends in '" +
                           std::string(1, c.launch[last]) + "'");
    // Absent: no limit, and nothing written into the resolved config.
    if (t.has("timeout_s"))
      c.timeout_s = t.number("timeout_s", reader::Range{0.0, reader::kInf, true, false});
  }
  // Substitutions only the LAMMPS mapping makes (engines/parameter_mapping.hpp): on another
  // kind they would be silently ignored.
  for (const char* key : {"allow_rolling_substitute", "allow_dry_walls"})
    if (t.has(key) && c.kind != "lammps")
      t.fail(key, "is for kind = \"lammps\" only (the substitutions of its mapping, "
                  "engines/parameter_mapping.hpp); kind is \"" + c.kind + "\"");
  if (c.kind == "lammps") {
    c.allow_rolling_substitute = t.boolean_or("allow_rolling_substitute", false);
    c.allow_dry_walls = t.boolean_or("allow_dry_walls", false);
  }
  t.finish();
  return c;
}

}  // namespace demcal::config
