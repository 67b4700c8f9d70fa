#pragma once
// The tables of a campaign, written from the run store without running anything:
//   <study dir>/doe.csv   one row per design point x replicate x apparatus, in
//                         that order: point, replicate, seed, apparatus, one
//                         column per parameter (in the design's order), then
//                         angle_of_repose_deg, discharge_time_s,
//                         mass_flow_rate_kg_s, bulk_density_kg_m3 (empty where
//                         not measured), status ("ok" | "failed" | "missing":
//                         no result in the store yet), hash (runs/<hash>.json)
//   <study dir>/doe.json  the design (kind, parameters with their keys and
//                         bounds, points, replicates, the point matrix, the
//                         seed rule) and the same rows with their parameter
//                         values, observables, run files and, for failed
//                         runs, the error
// Numbers are written in the shortest text that reads back exactly. Both files
// hold nothing that depends on when or where they were written, so the same
// store gives the same tables.

#include "study/doe_plan.hpp"
#include "study/run_store.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demcal::study {

struct DoeTable {
  std::string csv;
  nlohmann::json json;
  std::size_t ok = 0;
  std::size_t failed = 0;
  std::size_t missing = 0;  // rows
};

// `records[i]` is the stored record of plan.runs[i], if there is one.
DoeTable make_doe_table(const DoePlan& plan,
                        const std::vector<std::optional<nlohmann::json>>& records);

// Loads each run of the plan from `store` (a file that is not a valid record
// counts as missing) and writes doe.csv and doe.json into `study_dir`
// atomically. Returns the table.
// With `complete_only`, a table with rows still missing is returned but not
// written (`demcal doe --collect` never replaces a table with a less complete one).
DoeTable write_doe_table(const DoePlan& plan, const RunStore& store,
                         const std::filesystem::path& study_dir, bool complete_only = false);

// A CSV field: quoted when it holds a comma, quote or line break.
std::string csv_field(const std::string& text);

}  // namespace demcal::study
