#pragma once
// A study derived from another by `demcal diagnose`: the base study with a
// candidate's physics switched on and a [design] of its own (a probe at the
// base fit, or a design extended into the candidate's parameter), as typed
// values, and the one serialiser that writes it as a study file.
//
// The [design] table is written by hand, not through toml++: a TOML table is
// ordered by key, and a design's columns follow the order written.

#include "config/design_config.hpp"

#include <toml++/toml.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace demcal::study {

// One design parameter of a derived study: the study key it sets, its range,
// and the keys set to the same value (the grains' and the walls' surface energy).
struct DerivedParameter {
  std::string key;
  double lower = 0.0, upper = 1.0;
  std::vector<std::string> also_sets;
};

// The [design] of a derived study. Keys written only where set, in this order:
// kind, points, replicates, seed, values, parameters.
struct DerivedDesignTable {
  std::string kind;  // "list" | "latin_hypercube" (config/design_config.hpp)
  std::optional<int> points;
  int replicates = 1;
  std::optional<std::uint64_t> seed;
  std::vector<std::vector<double>> values;  // kind "list": one row per point
  std::vector<DerivedParameter> parameters;
};

struct DerivedStudyFile {
  std::vector<std::string> header;  // comment lines, without the leading "# "
  toml::table study;                // every table but [design]
  DerivedDesignTable design;
};

// The base study's [design] parameters as a derived study writes them: name, range and
// every key that follows the parameter (also_sets), in the written order.
std::vector<DerivedParameter> base_design_parameters(const config::DesignConfig& design);

// The file's text: the header comments, the study's tables, then [design].
std::string derived_study_text(const DerivedStudyFile& file);

}  // namespace demcal::study
