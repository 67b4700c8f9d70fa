#pragma once
// Whether a simulator's run-to-run scatter changes over its inputs.
//
// The surrogates, the calibration's sigma_dem and the check of a surrogate against the
// scatter all use one scatter pooled over the replicated points (ReplicateScatter). That is
// right only when the scatter is the same everywhere. It is not always: on the Sandglass
// grids of this repository the discharge time's replicate sd grows about fivefold from
// mu_s = 0.2 to 0.9 while the angle of repose's does not change measurably
// (studies/quick/README.md, trial E). This test says which, so that a pooled scatter
// measured in one corner is not taken for the box's.
//
// Model: at replicated point k (n_k runs, nu_k = n_k - 1, sample variance s_k^2),
//   nu_k s_k^2 / sigma_k^2 ~ chi^2(nu_k),   log sigma_k^2 = b_0 + sum_j b_j u_kj,
// with u the inputs scaled to [0, 1] on the design box: a gamma GLM with log link (McCullagh
// & Nelder 1989, ch. 8 and 10; the classic model of variance functions from replicates),
// fitted by Fisher scoring, whose information sum_k nu_k / 2 u_k u_k^T does not depend on b.
// Against the constant sigma^2 (the pooled variance) by the likelihood ratio, chi^2 with one
// degree of freedom per input under the constant scatter (Wilks).
//
// A test, not an estimate of the scatter at a point: on the lined recovery grid the fitted
// sd of the discharge time at the study's truth is 0.0116 s where 200 runs there give
// 0.0166 s and the pooled value 0.0216 s (the replicate sd rises with mu_s and falls again,
// which a log-linear model cannot follow; studies/quick/README.md, trial F). So nothing uses
// the fitted coefficients as sigma_dem; the diagnosis's local rule is
// calibrate/scatter_budget.hpp.

#include <Eigen/Core>

#include <string>
#include <vector>

namespace demcal::surrogate {

struct ScatterTrend {
  // False when there are too few replicated points (at most inputs + 1) or the sample
  // variances are all zero; the other fields are then NaN or empty.
  bool tested = false;
  // b_0 then one coefficient per input, for log sigma^2 over the unit-scaled inputs.
  std::vector<double> log_variance_coefficients;
  double likelihood_ratio = 0.0;  // 2 (l_trend - l_constant), >= 0
  int degrees_of_freedom = 0;     // of the test: the number of inputs
  double p_value = 1.0;           // of the constant scatter
  // The fitted sd at the replicated points: smallest and largest.
  double sd_smallest = 0.0;
  double sd_largest = 0.0;
  int points = 0;  // replicated points used
};

// x_unit: one row per replicated point, the inputs scaled to [0, 1]; sample_variance and
// degrees_of_freedom per point (>= 0 and >= 1). Throws std::invalid_argument naming the
// argument when the sizes differ or a value is negative, NaN or a dof below 1.
ScatterTrend fit_scatter_trend(const Eigen::MatrixXd& x_unit,
                               const Eigen::VectorXd& sample_variance,
                               const Eigen::VectorXi& degrees_of_freedom);

// One line for a report: "the scatter changes over the inputs (p = ...): fitted sd from ...
// to ... at the replicated points", or "no change of the scatter over the inputs is
// detected (p = ...)", or why it was not tested. `alpha` is the level the line reads p at.
std::string describe(const ScatterTrend& trend, double alpha = 0.01);

}  // namespace demcal::surrogate
