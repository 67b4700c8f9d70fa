#pragma once
// What an adaptive design did and why, batch by batch, in a form a report can print: the
// runs each batch asked for (with the reason and acquisition value), what the calibration
// on all runs so far said after it (95 % region area, calibrated point, chi^2), whether it
// was stable, and how the design ended.

#include "calibrate/adaptive_design_runs.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace demcal::calibrate {

enum class AdaptiveDesignStatus {
  running,           // more runs wanted
  converged,         // region and calibrated point stable (see AdaptiveDesignOptions)
  budget_exhausted,  // max_runs or max_batches reached first
  out_of_range,      // no parameter point reproduces the recordings
  no_candidates,     // every candidate point is within min_separation of a run
};
// "running", "converged", "budget_exhausted", "out_of_range", "no_candidates".
const char* to_string(AdaptiveDesignStatus status);

struct AdaptiveBatchRecord {
  std::size_t index = 0;         // 0: the space-filling start
  std::vector<RunRequest> runs;  // as planned, with reasons and acquisition values
  bool complete = false;         // every run of it is done; the fields below are set
  // The calibration on every run of batches 0..index:
  std::size_t runs_total = 0;
  double region_area = 0.0;  // parameter units (a product of two ranges for 2 parameters)
  bool region_resolved = false;
  std::vector<double> best_point;  // minima[0], parameter units
  // The posterior mean (weights of the acquisition's grid): the point whose stability the
  // stopping rule tests. Unlike minima[0] it does not jump between two near-equal minima.
  std::vector<double> posterior_mean;
  double best_chi_squared = 0.0;
  // |area - previous| / previous, and the posterior mean's move as a fraction of the 95 %
  // region's extent (the largest over the parameters); NaN for batch 0.
  double area_change = 0.0;
  double point_move = 0.0;
  // Posterior-weighted surrogate variance over the targets' noise variance (r), and the
  // fraction by which one more batch (the one planned next, full size) is expected to shrink
  // the region's area through the variance it removes (adaptive_design.cpp).
  double surrogate_variance_ratio = 0.0;
  double expected_area_gain = 0.0;
  int scatter_degrees_of_freedom = 0;  // pooled replicate scatter, the fewest over observables
  // Parts of the 95 % region that hold no design point (region_components.hpp), counted with
  // AdaptiveDesignOptions::confirm_region_parts (0 without): the next batch runs in each and
  // the region is not stable while one is left.
  int unconfirmed_parts = 0;
  bool stable = false;                 // all stopping tolerances held after this batch
  bool chi_squared_too_large = false;  // the out-of-range test failed after this batch
};

struct AdaptiveDesignHistory {
  std::vector<AdaptiveBatchRecord> batches;
  AdaptiveDesignStatus status = AdaptiveDesignStatus::running;
  std::string statement;  // one sentence on how the design ended (or where it is)
  std::size_t runs_done = 0;

  // One line per batch and the statement, for a report or a log.
  std::string to_text(const std::vector<std::string>& parameter_names) const;
  nlohmann::json to_json() const;  // NaN -> null
};

}  // namespace demcal::calibrate
