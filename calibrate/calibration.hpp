#pragma once
// One entry point for the inverse problem: from bounds, measured targets and their
// surrogates to the minima, the likelihood-ratio region, the posterior, the goodness of
// fit, which parameters the data identify, and plain-language notes saying so.

#include "calibrate/calibration_problem.hpp"
#include "calibrate/confidence_region.hpp"
#include "calibrate/goodness_of_fit.hpp"
#include "calibrate/posterior_sampling.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace demcal::calibrate {

// A target's scalar fields, kept so that a result needs no model to be read or saved.
struct TargetSummary {
  std::string setup, observable;
  double measured = 0.0, sigma_measured = 0.0, sigma_dem = 0.0;
  bool include_surrogate_variance = true;
  std::string model_kind, model_description;
};

struct CalibrationResult {
  std::vector<ParameterBounds> parameters;
  std::vector<TargetSummary> targets;
  CalibrationOptions options;
  std::vector<Minimum> minima;  // distinct, by increasing chi^2; minima[0] is the best
  LikelihoodRegion region;      // available for 1 to 3 parameters
  PosteriorSummary posterior;   // available when options.mcmc_samples > 0
  // Of minima[0]. dof = targets - parameters; when dof < 1 only chi_square and
  // degrees_of_freedom are meaningful (chi_square_per_dof and p_value are NaN): the fit
  // can then match any data and tests nothing.
  GoodnessOfFit fit;
  // Per parameter: the likelihood-ratio region stays off both bounds (above 3 parameters:
  // the posterior interval stays more than (1 - confidence) of the range from them;
  // without samples either: the covariance interval lies inside the bounds), and the
  // parameter has no share (>= 0.1, bound-scaled) in a rank-deficient direction of the
  // best minimum's Jacobian -- AoR alone identifies neither mu_r nor mu_s, even where the
  // box cuts the region short along one of them.
  std::vector<bool> identified;
  // Plain-language statements for the report, e.g. "mu_s is not identified: the 95 %
  // region reaches both of its bounds ...".
  std::vector<std::string> notes;

  // Grids (per-node vectors) and posterior samples are large; leave them out for a
  // summary. NaN becomes null.
  nlohmann::json to_json(bool include_grids = true, bool include_samples = false) const;
};

// Throws std::invalid_argument naming the offending parameter, target or option (see
// CalibrationProblem and validate(CalibrationOptions)).
CalibrationResult calibrate(const std::vector<ParameterBounds>& parameters,
                            const std::vector<Target>& targets,
                            const CalibrationOptions& options = {});

// How much one calibration narrows the parameters compared with another (e.g. AoR alone
// against AoR with the discharge time).
struct RegionComparison {
  double area_a = 0.0, area_b = 0.0;
  double ratio = 0.0;  // area_a / area_b (infinity when area_b is 0 and area_a is not)
  // Both regions on the same grid (same parameters, bounds and nodes): then the area of
  // their intersection and what fraction of each it is; NaN otherwise.
  bool same_grid = false;
  double overlap_area = 0.0;
  double overlap_fraction_a = 0.0, overlap_fraction_b = 0.0;
  // Per parameter: width of a's extent over width of b's (NaN where either is empty).
  std::vector<double> extent_ratio;
  // HPD credible regions, when both posteriors were sampled on their grids; else NaN.
  double credible_area_a = 0.0, credible_area_b = 0.0, credible_ratio = 0.0;
  nlohmann::json to_json() const;
};

// Throws std::invalid_argument when the two have different parameter names (in order) or
// either region is not available.
RegionComparison compare_regions(const CalibrationResult& a, const CalibrationResult& b);

}  // namespace demcal::calibrate
