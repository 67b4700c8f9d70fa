#pragma once
// The plan of `demcal doe`: a study with a [design] table -> the rows of the
// campaign (design point x replicate x apparatus, in that order) and the
// distinct runs behind them, each with its run key (study/run_store.hpp).
// Making the plan builds the study at every design point, so every input
// problem is a ConfigError before anything runs or touches the store.

#include "calibrate/adaptive_design_runs.hpp"
#include "config/design_config.hpp"
#include "config/toml_reader.hpp"
#include "study/run_store.hpp"
#include "surrogate/design.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace demcal::study {

struct PlannedRun {
  RunKey key;
  // The first row that asks for it (rows with identical inputs share a run).
  std::size_t point = 0;
  int replicate = 0;
  std::uint64_t seed = 0;
  std::string apparatus;
  // Adaptive designs: the design's run (batch, slot) it belongs to; absent for the others.
  std::optional<std::size_t> batch, slot;
};

struct PlanRow {
  std::size_t point = 0;
  int replicate = 0;
  std::uint64_t seed = 0;
  std::string apparatus;
  std::size_t run = 0;  // index into DoePlan::runs
  std::optional<std::size_t> batch, slot;  // adaptive designs only
};

struct DoePlan {
  config::StudySource source;  // the study and the --set overrides
  std::string file;
  std::string study_name;
  std::uint64_t study_seed = 0;
  int threads_per_run = 1;
  config::DesignConfig design;
  surrogate::Design generated;
  std::vector<std::string> apparatus;  // run, in the study's order
  bool study_asks_for_vtk = false;     // [output] vtk = true (doe writes none)
  std::vector<PlanRow> rows;           // (point, replicate, apparatus) order
  std::vector<PlannedRun> runs;        // distinct, in order of first row
};

// `apparatus` empty: every apparatus the study defines; else those (each must
// be defined). Throws ConfigError for any input problem.
DoePlan plan_doe(const std::filesystem::path& study, const std::vector<std::string>& overrides,
                 const std::vector<std::string>& apparatus, int threads_per_run);

// An adaptive design (design.adaptive): `plan` as plan_doe made it (no points yet) given the
// design's requests so far, in design order: a point per distinct theta (replicates share
// it), a row per request and apparatus, rows carrying batch and slot. The DEM seed of a
// request is dem_seed(request.seed). Throws ConfigError when a point does not build.
void plan_adaptive_runs(DoePlan& plan, const std::vector<calibrate::RunRequest>& requests);

// The seed the DEM runs with for an adaptive design's run seed: its top 53 bits (a seed in
// doe.csv and in the run key must be below 2^53).
std::uint64_t dem_seed(std::uint64_t design_run_seed);

// The study with run `run`'s design values, seed and threads set: what is built and run.
config::ConfigDocument run_document(const DoePlan& plan, const PlannedRun& run);

// "mu_r = 0.1, mu_s = 0.3"
std::string describe_point(const DoePlan& plan, std::size_t point);

}  // namespace demcal::study
