#pragma once
// `demcal doe`: runs every design point x replicate x apparatus of a study
// (its [design] table, config/design_config.hpp) into the run store
// (study/run_store.hpp) and writes the campaign's table (study/doe_table.hpp).
//
//   <output>/<study name>/runs/<hash>.json   one run record per distinct run
//                                            (or --run-store DIR/<hash>.json)
//   <output>/<study name>/doe.csv, doe.json  the table (not by a shard)
// <output> is --output, else "out" (as `demcal simulate` writes
// out/<study>/<apparatus>); the study's [output] directory names one run's
// directory and is not used here, nor VTK output.
//
// The campaign is study/doe_campaign.hpp (resuming, shards, MPI: a run's
// result depends only on its key); this command prints it. A run record is the
// one `demcal simulate` writes for the apparatus plus a "design" block (point,
// replicate, seed, parameters, hash, digest, status). Shards write no table:
// copy their run directories together (or share one) and use --collect.

#include "study/doe_campaign.hpp"

#include <ostream>
#include <string>

namespace demcal::cli {

using study::ProcessGroup;
using study::Shard;

// "i/N" with 0 <= i < N; ConfigError otherwise.
Shard parse_shard(const std::string& text);

struct DoeOptions : study::DoeCampaignOptions {
  bool quiet = false;     // no line per run
  bool progress = false;  // a progress bar on `log` (a terminal) instead of lines per run
};

using DoeOutcome = study::DoeCampaignOutcome;

// Throws ConfigError for input problems (before anything runs or is written)
// and other exceptions when the store cannot be written.
DoeOutcome run_doe(const DoeOptions& options, std::ostream& out, std::ostream& log);

}  // namespace demcal::cli
