#pragma once
// From a table of runs to a calibration: one surrogate per recording fitted to the runs
// (replicates grouped by identical theta), the recordings turned into targets the way the
// command line does it (sigma_dem = replicate scatter / sqrt(repeats)), and calibrate().
// The adaptive design calls it after every batch; a test calls it on a grid design's runs,
// so both are judged by the same code.

#include "calibrate/adaptive_design_runs.hpp"
#include "calibrate/calibration.hpp"
#include "calibrate/recording.hpp"
#include "surrogate/surrogate_fit.hpp"

#include <vector>

namespace demcal::calibrate {

struct RunsCalibration {
  std::vector<surrogate::FittedSurrogate> surrogates;  // one per recording
  std::vector<Target> targets;                         // one per recording
  CalibrationResult result;
};

// Runs are taken in (batch, slot) order whatever their order in `runs`, so that the fits do
// not depend on the order the caller kept them in. Throws std::invalid_argument when a run
// has the wrong number of observables or theta values, or a fit or the calibration rejects
// its input (too few runs, no replicates with nugget = "replicates", ...).
RunsCalibration calibrate_runs(const std::vector<ParameterBounds>& parameters,
                               const std::vector<Recording>& recordings,
                               const std::vector<RunResult>& runs,
                               const surrogate::SurrogateSpec& surrogate_spec,
                               const CalibrationOptions& calibration_options);

// `runs` sorted by (batch, slot).
std::vector<RunResult> runs_in_design_order(std::vector<RunResult> runs);

}  // namespace demcal::calibrate
