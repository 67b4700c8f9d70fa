#pragma once
// The apparatus path of `demcal simulate`: a study config (config/study_config.hpp)
// -> one apparatus, chosen with --apparatus when the study defines several ->
// its own protocol, run to the end of the event (fill, settle, release, come to
// rest) -> run.json with the observables under their stable names, the series
// and the details, plus VTK snapshots when [output] vtk = true.

#include "cli/simulate_command.hpp"
#include "config/toml_reader.hpp"

#include <ostream>

namespace demcal::cli {

// `doc` is the study config as read (no overrides applied yet): the overrides,
// --output and --threads of `options` are applied here, with the study's
// aliases (mu_s, mu_r). Every input problem is a ConfigError raised before
// anything runs, including an existing run.json without --overwrite; a failed
// run rethrows after writing run.json with stopped_because = "error".
SimulateOutcome simulate_apparatus(const SimulateOptions& options, config::ConfigDocument&& doc,
                                   std::ostream& out, std::ostream& progress_stream);

}  // namespace demcal::cli
