#pragma once
// The mismatch test when targets share DEM runs. A sandglass's discharge time, its m(t)
// segments (t25, t50, t75), bulk density and AoR are read off the same runs, so their DEM
// scatter -- the largest term of sigma_total -- is correlated (tests/concealed/truth/
// runs.csv: t25/t50/t75 0.8-0.9, with AoR 0.3-0.6). chi^2 = sum r_i^2 treats them as
// independent: it keeps the right mean but is not chi^2(n - p). Typical values fall low
// (p near 1: the null studies' chi2/dof of 0.15-0.66) while the tail grows heavy (false
// alarms above alpha), see tests/unit/test_detection_calibration.cpp.
//
// The corrected statistic: the standardized errors have correlation
//
//   C_ij = rho_ij (sigma_dem_i sigma_dem_j + sd_surr_i sd_surr_j) / (sigma_i sigma_j), i != j,
//
// rho_ij the replicate correlation of the two observables' runs (0 across setups: other
// runs), the surrogate term because surrogates fitted to the same runs err together. The
// residuals are whitened, w = L^-1 r with C = L L^T, theta is refitted to w by Gauss-Newton
// from the base fit (generalized least squares), and min |w|^2 is tested against
// chi^2(n - p).

#include "calibrate/calibration_problem.hpp"
#include "calibrate/mismatch_detection.hpp"
#include "calibrate/scatter_budget.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace demcal::calibrate {

// Correlation of the runs behind two targets, from their replicated designs: the
// within-point deviations of the two observables, paired run by run. replicates holds one
// set per target, points and runs in the same order for targets measured on the same runs;
// pairs with a different setup, or whose point and run counts differ, get 0. Diagonal 1.
// A correlation is kept only when Fisher's z = atanh|r| sqrt(dof - 3) >= min_z (dof: runs
// minus points): whitening by spurious correlations makes the test anti-conservative (with a
// 4 x 4 x 2 design, every |r| < 0.46 is set to 0 at min_z = 2).
// Throws std::invalid_argument when setups and replicates differ in length.
Eigen::MatrixXd replicate_correlation(const std::vector<std::vector<ReplicatePoint>>& replicates,
                                      const std::vector<std::string>& setups, double min_z = 2.0);

// C above at theta (parameter units). Throws std::invalid_argument when the correlation is
// not target_count() square.
Eigen::MatrixXd error_correlation(const CalibrationProblem& problem, const Eigen::VectorXd& theta,
                                  const Eigen::MatrixXd& run_correlation);

// The DEM scatter is itself estimated, from `degrees_of_freedom` replicate pairs' worth of
// runs; targets read off the same runs err together. Taking sigma_dem as known then makes
// the test anti-conservative (one low estimate shrinks every sigma of a setup at once).
// With degrees_of_freedom > 0 the p-value is the predictive one: Monte Carlo over
// sigma_dem^2 = estimate * nu / chi^2(nu) (the Jeffreys posterior of a variance), one draw
// per group of correlated targets (connected by a kept correlation), the standardized
// errors drawn with that scatter and the statistic projected as the fit would.
struct ScatterUncertainty {
  int degrees_of_freedom = 0;  // nu of the replicate scatter estimate; 0: taken as known
  int draws = 4000;            // Monte Carlo draws of the reference distribution (>= 100)
  std::uint64_t seed = 1;
};

struct CorrelatedFit {
  Eigen::VectorXd theta;               // the generalized-least-squares refit, inside the bounds
  double chi_square = 0.0;             // |L^-1 r(theta)|^2
  MismatchDetection detection;         // its p_value is the predictive one when nu > 0
  double p_value_known_scatter = 0.0;  // P(chi^2(n - p) >= chi_square)
};

// Gauss-Newton on the whitened residuals from theta_start (the base fit), at most
// `iterations` steps, each clipped to the bounds. Throws std::invalid_argument on sizes,
// std::runtime_error when C is not positive definite.
CorrelatedFit correlated_mismatch(const CalibrationProblem& problem,
                                  const Eigen::VectorXd& theta_start,
                                  const Eigen::MatrixXd& run_correlation,
                                  const DetectionOptions& options = {}, int iterations = 20,
                                  const ScatterUncertainty& scatter = {});

}  // namespace demcal::calibrate
