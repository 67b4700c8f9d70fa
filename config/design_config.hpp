#pragma once
// The [design] table of a study config (config/study_config.hpp): which parameter
// points `demcal doe` runs, how many replicates of each, and how the points are
// made. Read as strictly as the rest of the study:
//
//   [design]
//   kind = "latin_hypercube"        # "full_factorial" | "latin_hypercube" | "sobol" | "list"
//                                   #   | "adaptive" (its own keys: config/adaptive_design_keys.hpp)
//   points = 20                     # latin_hypercube and sobol only: integer in [1, 100000]
//   values = [[0.3, 0.52], ...]     # list only: the points, one value per parameter in the
//                                   #   parameters' written order, each inside its bounds
//   replicates = 2                  # opt, integer in [1, 1000]; runs per point
//   seed = 1                        # opt, integer >= 0; latin_hypercube's generator seed
//                                   #   (accepted and unused by the other kinds)
//   skip = 0                        # opt, sobol only: sequence points dropped first
//   parameters = { mu_r = { lower = 0.05, upper = 0.6 }, mu_s = { lower = 0.2, upper = 0.9 } }
//     each: lower < upper (finite numbers), and with full_factorial only
//     levels = 5 (integer in [2, 1000], required); at most 1e6 factorial points;
//     opt also_sets = ["interaction.particle_wall.surface_energy_j_m2"]: other keys
//     given the parameter's value at every point (one physical quantity that the
//     config writes in several places, e.g. a surface energy of the grains and of
//     the walls); the column is the parameter's
//
// A parameter name is any key `demcal simulate --set` accepts in the study:
// mu_r, mu_s, or a dotted path such as "apparatus.sandglass.orifice_diameter_m"
// (quoted in TOML because of the dots). Keys under study (the seed and threads
// are the campaign's), output (no effect on a run) and design are refused, and
// so are two names for one key (mu_r and interaction.particle_particle.rolling_friction).
// Columns are in the order the parameters are written. Whether the study
// accepts a value is checked by setting it the way --set does and building the
// study (check_design_bounds, and `demcal doe` builds every point before it
// runs anything), so there is one way to set a value.
//
// Seeds: replicate r (0-based) of every point runs with seed = study.seed + r.
// Points of a replicate share a seed (common random numbers: the difference
// between two points is not blurred by a different packing).

#include "calibrate/adaptive_design_options.hpp"
#include "config/toml_reader.hpp"
#include "surrogate/design.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demcal::config {

struct DesignConfig {
  surrogate::DesignSpec spec;                        // parameter names as written
  std::vector<std::string> parameter_paths;          // the dotted key each sets (aliases resolved)
  std::vector<std::vector<std::string>> tied_paths;  // per parameter: its also_sets keys
  std::vector<std::size_t> parameter_lines;          // where each is written, for messages
  int replicates = 1;
  std::size_t line = 0;  // of [design]
  // kind = "adaptive": how it chooses its runs (spec.kind is then kList with no values:
  // the campaign fills the points in, study/adaptive_campaign.hpp). Absent for the others.
  std::optional<calibrate::AdaptiveDesignOptions> adaptive;
};

// Reads [design] if the document has one (build_study calls it; `root` is the
// document's top level and `top` its table).
std::optional<DesignConfig> read_design(const reader::Context& ctx, reader::Table& root,
                                        toml::table& top);

// Sets parameter i of `design` (and its also_sets keys) to `value` in `doc`.
void set_parameter(ConfigDocument& doc, const DesignConfig& design, std::size_t i, double value,
                   const std::string& origin);

// A TOML key as it would be written: bare when it can be, else quoted.
std::string toml_key_text(const std::string& key);

// The shortest decimal text that reads back as exactly `v` ("0.1", "1e-05", "3").
std::string shortest_decimal(double v);

// "file:12: rest" -> "rest": a message nested in another names the file once.
std::string without_file_prefix(const std::string& message, const std::string& file);

// Sets each parameter of `design` to `values` (same order) in `doc`, through
// the override machinery of --set (study aliases), as floating-point values.
// `origin` names the source in messages, e.g. "design point 3".
void apply_design_values(ConfigDocument& doc, const DesignConfig& design,
                         const std::vector<double>& values, const std::string& origin);

// A study config that can be read again and again, each time with its line
// numbers: a parsed table loses them when copied (toml++ copies no source
// regions), and every message names file:line. The text is read once.
struct StudySource {
  std::string file;
  std::string text;
  std::vector<std::string> overrides;  // --set, with the study aliases

  // Throws ConfigError when the file cannot be read.
  static StudySource read(const std::filesystem::path& path, std::vector<std::string> overrides);
  // Parsed, with the overrides applied.
  ConfigDocument document() const;
};

// Each parameter at its lower and then its upper bound (the others as the
// study has them) must give a study that builds; otherwise a ConfigError at
// the parameter's line: "study.toml:58: design.parameters.mu_r: lower = -0.1
// is refused: interaction.particle_particle.rolling_friction: expected a number >= 0, ...".
void check_design_bounds(const StudySource& source, const DesignConfig& design);

// The seed of replicate r: study_seed + r.
std::uint64_t replicate_seed(std::uint64_t study_seed, int replicate);

}  // namespace demcal::config
