#include "config/adaptive_design_keys.hpp"

#include <limits>
#include <string>

namespace demcal::config {

using reader::above;
using reader::between;
using reader::Table;

calibrate::AdaptiveDesignOptions read_adaptive_design_keys(Table& d) {
  calibrate::AdaptiveDesignOptions o;
  for (const char* key : {"points", "values", "skip", "replicates"})
    if (d.contains(key))
      d.fail(key, std::string("does not apply to kind = \"adaptive\": the design chooses its "
                              "points and replicates itself (initial_points, "
                              "initial_replicated_points, replicates_per_batch, max_runs)"));
  auto integer = [&](Table& t, const char* key, int fallback, int lo, int hi) {
    return static_cast<int>(t.integer_or(key, fallback, lo, hi));
  };
  o.seed = static_cast<std::uint64_t>(
      d.integer_or("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  o.initial_points = integer(d, "initial_points", o.initial_points, 4, 1000);
  o.initial_replicated_points =
      integer(d, "initial_replicated_points", o.initial_replicated_points, 1, o.initial_points);
  o.batch_size = integer(d, "batch_size", o.batch_size, 1, 1000);
  o.replicates_per_batch = integer(d, "replicates_per_batch", o.replicates_per_batch, 1, 1000);
  o.scatter_degrees_of_freedom =
      integer(d, "scatter_degrees_of_freedom", o.scatter_degrees_of_freedom, 1, 1000);
  const int initial_runs = o.initial_points + o.initial_replicated_points;
  o.max_runs = integer(d, "max_runs", std::max(o.max_runs, initial_runs), initial_runs, 5000);
  o.max_batches = integer(d, "max_batches", o.max_batches, 1, 1000);
  o.min_separation =
      d.number_or("min_separation", o.min_separation, between(0.0, true, 0.5, true));

  Table a = d.table_or_empty("acquisition");
  o.acquisition_grid_points_per_axis =
      integer(a, "grid_points_per_axis", o.acquisition_grid_points_per_axis, 5, 201);
  o.integration_points = integer(a, "integration_points", o.integration_points, 10, 100000);
  o.candidate_points = integer(a, "candidate_points", o.candidate_points, 1, 100000);
  o.exploration_points = integer(a, "exploration_points", o.exploration_points, 0, 100000);
  // The swing-damping variants (BENCHMARKS.md "Issue 16, evening"), off by default.
  o.acquisition_weight_batches = integer(a, "weight_batches", o.acquisition_weight_batches, 1, 2);
  o.acquisition_tempering =
      a.number_or("tempering", o.acquisition_tempering, between(0.0, true, 1.0, false));
  o.space_filling_batch = a.boolean_or("space_filling", o.space_filling_batch);
  a.finish();

  Table s = d.table_or_empty("stopping");
  o.area_tolerance = s.number_or("area_tolerance", o.area_tolerance, between(0.0, true, 1.0, true));
  o.point_tolerance =
      s.number_or("point_tolerance", o.point_tolerance, between(0.0, true, 1.0, true));
  o.surrogate_variance_tolerance =
      s.number_or("surrogate_variance_tolerance", o.surrogate_variance_tolerance, above(0.0));
  o.stable_batches = integer(s, "stable_batches", o.stable_batches, 1, 100);
  o.out_of_range_alpha =
      s.number_or("out_of_range_alpha", o.out_of_range_alpha, between(0.0, true, 0.5, true));
  o.out_of_range_batches = integer(s, "out_of_range_batches", o.out_of_range_batches, 1, 100);
  o.confirm_region_parts = s.boolean_or("confirm_region_parts", o.confirm_region_parts);
  s.finish();

  std::string error;
  if (!o.Validate(&error)) d.fail_here(error);
  return o;
}

}  // namespace demcal::config
