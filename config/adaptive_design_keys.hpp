#pragma once
// The keys of an adaptive [design] (kind = "adaptive"; docs/adaptive_design.md §8): each
// sets the calibrate::AdaptiveDesignOptions field of the same name, defaults there
// ([design.acquisition] grid_points_per_axis sets acquisition_grid_points_per_axis, and
// likewise weight_batches and tempering; space_filling sets space_filling_batch):
//
//   [design]
//   kind = "adaptive"
//   parameters = { mu_r = { lower = 0.05, upper = 0.6 }, ... }   # no levels
//   seed = 1                          # opt, integer >= 0: the start, run seeds, exploration
//   initial_points = 8                # opt, integer in [4, 1000]
//   initial_replicated_points = 4     # opt, integer in [1, initial_points]
//   batch_size = 4                    # opt, integer in [1, 1000]: runs busy at once
//   replicates_per_batch = 2          # opt, integer in [1, 1000]
//   scatter_degrees_of_freedom = 10   # opt, integer in [1, 1000]
//   max_runs = 48                     # opt, integer in [initial runs, 5000]; default
//                                     #   48, or the initial runs when they are more
//   max_batches = 12                  # opt, integer in [1, 1000]
//   min_separation = 0.03             # opt, number in (0, 0.5), bound-scaled
//   [design.acquisition]              # opt
//   grid_points_per_axis = 31         #   integer in [5, 201]
//   integration_points = 300          #   integer in [10, 100000]
//   candidate_points = 96             #   integer in [1, 100000]
//   exploration_points = 32           #   integer in [0, 100000]
//   weight_batches = 1                #   integer in [1, 2]: acquisition_weight_batches
//   tempering = 1.0                   #   number in (0, 1]: acquisition_tempering
//   space_filling = false             #   true or false: space_filling_batch
//   [design.stopping]                 # opt
//   area_tolerance = 0.15             #   number in (0, 1)
//   point_tolerance = 0.10            #   number in (0, 1)
//   surrogate_variance_tolerance = 0.25  # number > 0
//   stable_batches = 2                #   integer in [1, 100]
//   out_of_range_alpha = 1e-3         #   number in (0, 0.5)
//   out_of_range_batches = 2          #   integer in [1, 100]
//
// `points`, `values`, `skip` and `replicates` are refused here (`levels` by the [design]
// reader, config/design_config.cpp): the design chooses its points and replicates itself.
// After the keys, AdaptiveDesignOptions::Validate's checks apply. What this reader cannot
// see is checked by the campaign (study::adaptive_study_design, study/adaptive_campaign.hpp):
// the study needs [calibration] recordings (what it designs for) and a gaussian_process
// [surrogate], every recorded setup must be an apparatus the campaign runs, and every
// recorded observable a scalar column of doe.csv.

#include "calibrate/adaptive_design_options.hpp"
#include "config/toml_reader.hpp"

namespace demcal::config {

// Reads the adaptive keys of `design` (the [design] table; `kind` and `parameters` are the
// caller's) into options; ConfigError naming the key for any value out of range.
calibrate::AdaptiveDesignOptions read_adaptive_design_keys(reader::Table& design);

}  // namespace demcal::config
