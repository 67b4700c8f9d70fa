#pragma once
// How an adaptive design ([design] kind = "adaptive") chooses its runs and when it stops.
// Defaults suit two parameters and two or three observables; docs/adaptive_design.md
// gives the maths and why each tolerance is what it is.

#include "calibrate/calibration_problem.hpp"
#include "surrogate/surrogate_fit.hpp"

#include <cstdint>
#include <string>

namespace demcal::calibrate {

struct AdaptiveDesignOptions {
  AdaptiveDesignOptions();

  // --- The start (batch 0) -------------------------------------------------------------
  // Maximin Latin hypercube points over the box (>= parameters + 2, so that a linear-mean
  // GP has residual degrees of freedom).
  int initial_points = 8;
  // Of them, the ones nearest the box centre get a second run (>= 1 and <= initial_points):
  // the surrogates' nugget comes from the pooled replicate scatter, which needs some.
  int initial_replicated_points = 4;

  // --- The batches ---------------------------------------------------------------------
  // Runs per batch (>= 1): the runs that can be busy at once.
  int batch_size = 4;
  // While the pooled replicate scatter has fewer degrees of freedom than this (in the
  // observable that has the fewest), up to `replicates_per_batch` runs of a batch (>= 1)
  // repeat the design points nearest the calibrated point: the scatter is measured where it
  // matters (>= 1). The scatter sets sigma_dem and with it the region's size: with nu
  // degrees of freedom its variance is uncertain by sqrt(2 / nu) (45 % at 10).
  int scatter_degrees_of_freedom = 10;
  int replicates_per_batch = 2;
  // Nodes per axis of the grid the acquisition integrates over (>= 5).
  int acquisition_grid_points_per_axis = 31;
  // Of those nodes, at most this many (by posterior weight) carry the integral (>= 10), and
  // at most `candidate_points` of them (every k-th by weight) are candidates (>= 1) ...
  int integration_points = 300;
  int candidate_points = 96;
  // ... together with this many Sobol points over the whole box (>= 0), so that the
  // design can still look away from where the current posterior is.
  int exploration_points = 32;
  // A candidate closer than this (Euclidean, bound-scaled units) to a design point or to a
  // point already in the batch is not taken: runs do not pile into one spot (a replicate is
  // the only way to repeat a point). In (0, 0.5).
  double min_separation = 0.03;
  // Damping the region's batch-to-batch swing (issue 16, BENCHMARKS.md "Issue 16, evening";
  // both off by default). Late in a design the posterior, which carries the surrogates'
  // variance, spreads into an arm of the region where the GP is unsure, the next batch runs
  // there, the posterior contracts, the next batch runs in the core, and so on.
  //  acquisition_weight_batches (1 or 2): 2 integrates the acquisition over the mean of this
  //    batch's and the previous batch's posterior weights, so a batch still serves the arm the
  //    posterior has just left. 1: this batch's posterior only.
  //  acquisition_tempering (in (0, 1]): the acquisition's weights are posterior^tempering; at
  //    0.5 the 95 % region's boundary (chi^2 5.99 above the best for 2 parameters) weighs
  //    exp(-1.5) = 0.22 of the peak instead of exp(-3) = 0.05, so the batch covers the whole
  //    high-posterior set, arms included, before the posterior spreads there. 1: the posterior.
  // The stopping rule's share, posterior mean and expected gain stay on this batch's
  // posterior (the gain: the chosen runs' joint variance drop under those weights).
  int acquisition_weight_batches = 1;
  double acquisition_tempering = 1.0;
  // space_filling_batch: instead of the weighted-IMSE maximizers, the batch's new points fill
  // the high-posterior set (the heaviest acquisition-weight nodes carrying 95 % of it) by
  // greedy maximin: each is the node of that set farthest (bound-scaled) from every run and
  // earlier choice, so the whole set, its edges and arms included, gets runs at once.
  // Off by default.
  bool space_filling_batch = false;

  // --- Stopping ------------------------------------------------------------------------
  // After a batch the design is stable when (all of):
  //   |area - previous area| / previous area <= area_tolerance              (in (0, 1))
  //   the posterior mean moved by <= point_tolerance of the 95 % region's extent along
  //   every parameter (the mean, not the best minimum, which can jump between two
  //   near-equal minima along an iso-line)                                 (in (0, 1))
  //   the posterior-weighted surrogate variance is <= surrogate_variance_tolerance of the
  //   targets' noise variance (the region is set by the data, not by the surrogate) (> 0),
  //   OR the next batch is expected to shrink the area by <= area_tolerance (the region,
  //   computed with noise x (1 + share), already carries the share; what matters is
  //   whether more runs would still shrink it)
  //   the replicate scatter has >= scatter_degrees_of_freedom (sigma_dem sets the region)
  //   the region is resolved on the calibration grid.
  // confirm_region_parts: a part of the 95 % region that holds no design point (only the
  // surrogates' variance between runs admits it; region_components.hpp) gets one run of the
  // next batch at its most probable node, and the design is not stable while one is left.
  // Off by default: on the analytic near-bound test it raised the median runs from 32 to 40
  // (tests/unit/test_adaptive_design.cpp). On the quick study an arm of the region that no
  // run had seen decided whether mu_s was identified (studies/quick/README.md, 2026-12-06).
  bool confirm_region_parts = false;
  double area_tolerance = 0.15;
  double point_tolerance = 0.10;
  double surrogate_variance_tolerance = 0.25;
  // Converged after this many consecutive stable batches (>= 1).
  int stable_batches = 2;
  // Out of range: the best chi^2 exceeds the chi^2(targets) quantile 1 - alpha (no point
  // reproduces the recordings even though chi^2 at the truth would pass) after this many
  // consecutive batches. alpha in (0, 0.5).
  double out_of_range_alpha = 1e-3;
  int out_of_range_batches = 2;
  // Budget: the design stops when these many runs (>= initial runs) or batches after the
  // start (>= 1) are done; the last batch is cut to fit.
  int max_runs = 48;
  int max_batches = 12;

  // --- What the design runs on ---------------------------------------------------------
  // Seeds the start, the run seeds and the Sobol exploration offset.
  std::uint64_t seed = 1;
  // The surrogates fitted after each batch: model must be "gaussian_process" (the
  // acquisition needs its predictive variance and a refit with fixed hyperparameters).
  // Default: linear mean, nugget from replicates, 4 likelihood starts.
  surrogate::SurrogateSpec surrogate;
  // The calibration after each batch: its 95 % region is what the design shrinks.
  // Default: the CalibrationOptions defaults without posterior sampling (mcmc_samples = 0).
  CalibrationOptions calibration;

  // True when every option is in range; otherwise false and *error (if given) names the
  // first one out of range and its allowed values.
  bool Validate(std::string* error) const;
};

}  // namespace demcal::calibrate
