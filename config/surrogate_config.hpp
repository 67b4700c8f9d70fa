#pragma once
// The [surrogate] table of a study config: which model `demcal fit` fits to
// each observable of the design's runs. Every key is optional:
//
//   [surrogate]
//   model = "gaussian_process"        # | "polynomial"
//   observables = ["angle_of_repose_deg", "discharge_time_s"]
//                                     # default: every stable observable the runs measured
//   degree = 0                        # polynomial: total degree 1..4; 0 = by leave-one-out
//   kernel = "matern52"               # gaussian_process: | "squared_exponential"
//   mean = "constant"                 # gaussian_process: | "linear"
//   nugget = "replicates"             # gaussian_process: | "estimated" | "none"
//                                     #   (surrogate/surrogate_fit.hpp says what each does)
//   starts = 8                        # gaussian_process: maximum-likelihood starts, 1..100
//   seed = 1                          # gaussian_process: the starts' seed
//
// Keys that do not apply to the chosen model are refused, so a study never
// carries a setting that silently does nothing.

#include "config/toml_reader.hpp"
#include "surrogate/surrogate_fit.hpp"

#include <optional>
#include <string>
#include <vector>

namespace demcal::config {

struct SurrogateConfig {
  surrogate::SurrogateSpec spec;
  std::vector<std::string> observables;  // empty: every stable observable with data
};

// Reads [surrogate] if the document has one (build_study calls it).
std::optional<SurrogateConfig> read_surrogate(reader::Table& root);

}  // namespace demcal::config
