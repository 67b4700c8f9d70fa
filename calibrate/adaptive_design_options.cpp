#include "calibrate/adaptive_design_options.hpp"

#include <cmath>
#include <stdexcept>

namespace demcal::calibrate {

AdaptiveDesignOptions::AdaptiveDesignOptions() {
  surrogate.model = "gaussian_process";
  surrogate.mean = surrogate::MeanFunction::linear;
  surrogate.nugget = "replicates";
  // Four starts find the same optimum as eight on designs this size; the fit is repeated
  // after every batch.
  surrogate.starts = 8;
  // The region, not the posterior, steers the design; sampling would cost seconds per batch.
  calibration.mcmc_samples = 0;
}

bool AdaptiveDesignOptions::Validate(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error) *error = "adaptive design: " + message;
    return false;
  };
  if (initial_points < 4)
    return fail("initial_points must be >= 4, got " + std::to_string(initial_points));
  if (initial_replicated_points < 1 || initial_replicated_points > initial_points)
    return fail("initial_replicated_points must be in [1, initial_points = " +
                std::to_string(initial_points) + "], got " +
                std::to_string(initial_replicated_points));
  if (batch_size < 1) return fail("batch_size must be >= 1, got " + std::to_string(batch_size));
  if (scatter_degrees_of_freedom < 1)
    return fail("scatter_degrees_of_freedom must be >= 1, got " +
                std::to_string(scatter_degrees_of_freedom));
  if (replicates_per_batch < 1)
    return fail("replicates_per_batch must be >= 1, got " + std::to_string(replicates_per_batch));
  if (acquisition_grid_points_per_axis < 5)
    return fail("acquisition_grid_points_per_axis must be >= 5, got " +
                std::to_string(acquisition_grid_points_per_axis));
  if (integration_points < 10)
    return fail("integration_points must be >= 10, got " + std::to_string(integration_points));
  if (candidate_points < 1)
    return fail("candidate_points must be >= 1, got " + std::to_string(candidate_points));
  if (exploration_points < 0)
    return fail("exploration_points must be >= 0, got " + std::to_string(exploration_points));
  if (!(min_separation > 0.0 && min_separation < 0.5))
    return fail("min_separation must be in (0, 0.5) (bound-scaled units), got " +
                std::to_string(min_separation));
  if (acquisition_weight_batches < 1 || acquisition_weight_batches > 2)
    return fail("acquisition_weight_batches must be 1 or 2, got " +
                std::to_string(acquisition_weight_batches));
  if (!(acquisition_tempering > 0.0 && acquisition_tempering <= 1.0))
    return fail("acquisition_tempering must be in (0, 1], got " +
                std::to_string(acquisition_tempering));
  if (!(area_tolerance > 0.0 && area_tolerance < 1.0))
    return fail("area_tolerance must be in (0, 1), got " + std::to_string(area_tolerance));
  if (!(point_tolerance > 0.0 && point_tolerance < 1.0))
    return fail("point_tolerance must be in (0, 1), got " + std::to_string(point_tolerance));
  if (!(surrogate_variance_tolerance > 0.0) || !std::isfinite(surrogate_variance_tolerance))
    return fail("surrogate_variance_tolerance must be > 0 and finite, got " +
                std::to_string(surrogate_variance_tolerance));
  if (stable_batches < 1)
    return fail("stable_batches must be >= 1, got " + std::to_string(stable_batches));
  if (!(out_of_range_alpha > 0.0 && out_of_range_alpha < 0.5))
    return fail("out_of_range_alpha must be in (0, 0.5), got " +
                std::to_string(out_of_range_alpha));
  if (out_of_range_batches < 1)
    return fail("out_of_range_batches must be >= 1, got " + std::to_string(out_of_range_batches));
  const int initial_runs = initial_points + initial_replicated_points;
  if (max_runs < initial_runs)
    return fail("max_runs must be >= the start's " + std::to_string(initial_runs) +
                " runs (initial_points + initial_replicated_points), got " +
                std::to_string(max_runs));
  if (max_batches < 1) return fail("max_batches must be >= 1, got " + std::to_string(max_batches));
  if (surrogate.model != "gaussian_process")
    return fail(
        "surrogate.model must be \"gaussian_process\" (the acquisition needs its "
        "predictive variance), got \"" +
        surrogate.model + "\"");
  if (surrogate.nugget != "replicates" && surrogate.nugget != "estimated" &&
      surrogate.nugget != "none")
    return fail("surrogate.nugget must be \"replicates\", \"estimated\" or \"none\", got \"" +
                surrogate.nugget + "\"");
  if (surrogate.starts < 1)
    return fail("surrogate.starts must be >= 1, got " + std::to_string(surrogate.starts));
  try {
    validate(calibration);
  } catch (const std::invalid_argument& e) {
    return fail(std::string("calibration: ") + e.what());
  }
  return true;
}

}  // namespace demcal::calibrate
