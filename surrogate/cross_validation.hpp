#pragma once
// Validation of a surrogate from its leave-one-out predictions: how well it predicts a DEM
// run it has not seen, and whether that error is small next to the DEM's own scatter.

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace demcal::surrogate {

// Each training point predicted by the model fitted without it (hyperparameters, if any,
// held fixed). `variance` is the predictive variance of a new *observation* at that point,
// i.e. it includes the observation noise, so (observed - mean) / sqrt(variance) should be
// roughly standard normal when the model is right.
struct LeaveOneOut {
  Eigen::VectorXd observed;
  Eigen::VectorXd mean;
  Eigen::VectorXd variance;
};

struct ValidationMetrics {
  double press = 0.0;      // sum of squared leave-one-out residuals
  double q_squared = 0.0;  // 1 - PRESS / SS_tot; NaN when the observations are all equal
  double rmse = 0.0;       // sqrt(PRESS / n), in output units
  // (observed - mean) / sqrt(variance); NaN where the variance is not positive and finite.
  Eigen::VectorXd standardized_residuals;
  double max_abs_standardized_residual = 0.0;  // over the finite entries
};

// Throws std::invalid_argument when the three vectors differ in size or are empty.
ValidationMetrics validation_metrics(const LeaveOneOut& loo);

// Verdict for the caller to print; the library never writes to a stream itself.
struct ScatterCheck {
  bool within_scatter = true;
  double surrogate_error = 0.0;  // estimated error of the surrogate alone, output units
  double scatter_bound = 0.0;    // what surrogate_error is compared with (see below)
  std::string message;           // one line, always filled
};

// Flags a surrogate whose error exceeds the DEM run-to-run scatter (standard deviation of
// one run), i.e. one that is worse than just running the DEM again.
// A leave-one-out residual also contains the noise of the held-out value, whose variance is
// scatter² / replicates_per_point when each training value averages that many runs; it is
// removed before comparing, else a surrogate fitted to single runs would always be flagged.
// A scatter estimated from nu > 0 degrees of freedom is itself uncertain by about
// sqrt(1/(2 nu)) relative (29 % at 6): the error is then compared with the one-sided 95 %
// upper confidence bound of the scatter, sd sqrt(nu / chi²_0.05(nu)) (1.92 sd at 6 dof,
// 1.35 at 21, 1.13 at 100), so that a scatter that came out low does not flag a surrogate
// by itself; nu = 0 compares with sd as given (a scatter known exactly).
// Throws std::invalid_argument naming the argument when one is negative, NaN or zero
// replicates.
ScatterCheck check_against_scatter(double loo_rmse, double run_to_run_sd,
                                   const std::string& output_name = "output",
                                   int replicates_per_point = 1,
                                   int scatter_degrees_of_freedom = 0);

// Fold (0..folds-1) of each of n points: balanced (sizes differ by at most one) and shuffled
// by a fixed, platform-independent generator so that a seed reproduces the split anywhere.
// Throws std::invalid_argument when folds < 2 or folds > n.
std::vector<int> k_fold_assignment(std::size_t n, int folds, std::uint64_t seed);

}  // namespace demcal::surrogate
