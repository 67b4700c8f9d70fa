#pragma once
// Step 2 of the missing-physics workflow (docs/design.md): where the base model fails. From the
// standardized residuals at the best minimum,
//
//   (a) their chi-square summed per observable and per setup, with each group's share of
//       the total and its own (approximate) p-value;
//   (b) per numeric setup variable (orifice_diameter_m, thickness_d, ...) and observable,
//       a straight line through the standardized residuals: do they follow the variable?
//   (c) calibrations on each setup's targets alone, and whether two setups' parameter
//       estimates disagree beyond their Gauss-Newton uncertainty;
//
// and one sentence that says it, e.g. "The mismatch is in discharge_time_s at the setups
// orifice_10mm and orifice_14mm (78 % of chi^2); the residuals follow orifice_diameter_m
// (t = 4.1)."
//
// A time series needs nothing special: its segments arrive as separate targets whose
// observable names share a prefix ("mass_discharged_fraction_t1", "..._t2"), so the
// per-observable groups already say which part of the series is off.

#include "calibrate/calibration.hpp"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

namespace demcal::calibrate {

// Numeric description of each setup: setup -> {variable name -> value}, e.g.
// {"orifice_10mm", {{"orifice_diameter_m", 0.010}}}. Setups may have different variables;
// a setup without a variable takes no part in that variable's trends.
using SetupVariables = std::map<std::string, std::map<std::string, double>>;

struct LocationOptions {
  // Significance level of the group, trend and subset tests; (0, 1).
  double alpha = 0.01;
  // A trend is fitted only where an observable has targets at this many distinct values
  // of the variable (>= 3: two points always lie on a line).
  int min_distinct_values = 3;
  // The sentence names the leading observables, then the leading setups within them,
  // until they hold this fraction of their chi-square; (0, 1].
  double named_share = 0.7;
  // Calibrate each setup alone (c). Setups with fewer targets than parameters are skipped;
  // with exactly as many (dof 0) the estimate is still a point with a covariance.
  bool subset_calibrations = true;
  // Of the subset calibrations (find_minima only: no grid, no sampling).
  CalibrationOptions calibration;
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const LocationOptions& options);

// A target's standardized residual at the base model's best minimum.
struct TargetResidual {
  std::string setup, observable;
  double measured = 0.0, predicted = 0.0, sigma_total = 0.0;
  double residual = 0.0;  // (measured - predicted) / sigma_total
};

// The targets sharing one observable, or one setup.
struct ResidualGroup {
  std::string name;
  int count = 0;
  double chi_square = 0.0;  // sum of the members' squared residuals
  double share = 0.0;       // of the total chi-square (NaN when the total is 0)
  // P(chi^2(count) >= chi_square). Approximate: the fit used up p degrees of freedom
  // spread over all targets, so a group's residuals are slightly smaller than unit
  // normals and the test is slightly conservative.
  double p_value = 1.0;
  bool significant = false;  // p_value < alpha
};

// Straight line r = a + b x through the standardized residuals r_i of one observable
// against one setup variable. Each r_i has unit variance, so this is the weighted fit of
// the raw residuals with their own sigmas as the scale: a relative mismatch (discharge
// times of 4 s and 22 s measured to 1 %) counts alike at every setup.
struct ResidualTrend {
  std::string variable, observable;
  int points = 0, distinct_values = 0;
  double intercept = 0.0;
  double slope = 0.0;  // standardized residual per variable unit
  // 1 / sqrt(sum (x - mean x)^2): the residuals' unit variance taken as known. t tests
  // "no trend" against the noise alone; whether the residuals also scatter about the line
  // (a mismatch that does not follow the variable, or not linearly) is the line's own
  // chi-square below, reported beside it rather than folded into the standard error,
  // which with 3 points would cost most of the test's power.
  double slope_standard_error = 0.0;
  double t = 0.0;
  double p_value = 1.0;  // two-sided, normal; approximate (the fit's p dof are ignored)
  bool significant = false;
  double line_chi_square = 0.0;     // of the residuals about the line
  int line_degrees_of_freedom = 0;  // points - 2
  double line_p_value = 1.0;        // P(chi^2(points - 2) >= line_chi_square); 1 for 2 points
  // slope * (largest - smallest value): how many sigma the residual moves across the setups.
  double change_over_range = 0.0;
};

// One setup calibrated on its own targets.
struct SubsetFit {
  std::string setup;
  int targets = 0;
  bool fitted = false;  // false: fewer targets than parameters
  Eigen::VectorXd theta;
  double chi_squared = 0.0;
  bool covariance_available = false;
  Eigen::MatrixXd covariance;  // parameter units
  std::string note;            // why not fitted, or why no covariance
};

// d = theta_a - theta_b, statistic = d^T (C_a + C_b)^-1 d ~ chi^2(p) when both setups obey
// the same parameters (the subsets share no targets, so their estimates are independent).
struct SubsetDisagreement {
  std::string setup_a, setup_b;
  Eigen::VectorXd difference;
  double statistic = 0.0;
  int degrees_of_freedom = 0;
  double p_value = 1.0;
  // p_value < alpha, each pair on its own: with k setups there are k (k - 1) / 2 tests and
  // no correction for their number, so one disagreement among many pairs is weak evidence.
  bool significant = false;
};

struct MismatchLocation {
  std::vector<TargetResidual> residuals;  // per target, in the targets' order
  double chi_square = 0.0;
  // Largest chi-square first.
  std::vector<ResidualGroup> by_observable, by_setup;
  // Every fitted (variable, observable) pair, largest |t| first.
  std::vector<ResidualTrend> trends;
  std::vector<SubsetFit> subsets;                  // in the order the setups first appear
  std::vector<SubsetDisagreement> disagreements;   // every pair with both covariances
  // What the sentence names.
  std::vector<std::string> named_observables, named_setups;
  double named_share = 0.0;  // of the total chi-square held by the named cells
  std::string statement;

  nlohmann::json to_json() const;  // NaN -> null
};

// (a)
std::vector<TargetResidual> target_residuals(const CalibrationResult& base);
// by_observable true: group by observable, else by setup; largest chi-square first.
std::vector<ResidualGroup> residual_groups(const std::vector<TargetResidual>& residuals,
                                           bool by_observable, double alpha);
// (b) Throws std::invalid_argument naming a setup variable whose value is not finite.
std::vector<ResidualTrend> residual_trends(const std::vector<TargetResidual>& residuals,
                                           const SetupVariables& setup_variables,
                                           const LocationOptions& options);
// (c) Throws std::invalid_argument as CalibrationProblem does.
std::vector<SubsetFit> subset_fits(const std::vector<ParameterBounds>& parameters,
                                   const std::vector<Target>& targets,
                                   const CalibrationOptions& options);
std::vector<SubsetDisagreement> subset_disagreements(const std::vector<SubsetFit>& fits, double alpha);

// All of it. `targets` are those `base` was calibrated on, in the same order (only needed
// for the subset calibrations). Throws std::invalid_argument naming the target whose
// setup or observable differs from the result's, a non-finite setup variable, or an
// option out of range.
MismatchLocation locate_mismatch(const std::vector<ParameterBounds>& parameters,
                                 const std::vector<Target>& targets, const CalibrationResult& base,
                                 const SetupVariables& setup_variables,
                                 const LocationOptions& options = {});

}  // namespace demcal::calibrate
