// Calibration of the mismatch test (issue 19): when the base model is right, is the
// chi-square p-value of detect_mismatch uniform, and does it raise false alarms at the rate
// alpha it claims? Checked at surrogate level over many synthetic null studies built the
// way the real pipeline builds them:
//
//   design    4 x 4 grid in (mu_r, mu_s), 2 DEM runs per point (tests/concealed's base
//             study), each run = response(theta) + DEM scatter;
//   surrogate fitted to that replicated design by surrogate::fit_surrogate (the pooled
//             replicate scatter is its ReplicateScatter::sd);
//   recording at a true point: the mean of 3 DEM runs plus the instrument's Gaussian
//             error, recorded with its sigma and repeats = 3;
//   budget    sigma_dem = pooled scatter / sqrt(repeats), plus the surrogate's variance
//             (cli/calibration_targets.cpp's rule), dof = targets - parameters.
//
// Criteria, fixed before measuring (N null cases per scenario):
//   - Kolmogorov-Smirnov distance of the p-values from U(0, 1) below 1.63 / sqrt(N)
//     (the KS test's 1 % critical value);
//   - false alarms at alpha = 0.05 within 3.3 binomial standard deviations of N alpha
//     (two-sided: too few alarms means the noise model is too generous and costs power);
//   - mean chi2/dof within 0.1 of 1.
#include "calibrate/calibration_problem.hpp"
#include "calibrate/correlated_detection.hpp"
#include "calibrate/mismatch_detection.hpp"
#include "calibrate/scatter_budget.hpp"
#include "surrogate/surrogate_fit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace demcal::calibrate {
namespace {

constexpr int kObservables = 8;
constexpr int kLevels = 4;
constexpr int kDesignReplicates = 2;
constexpr int kRecordingRepeats = 3;

// How the DEM's run-to-run scatter depends on theta.
enum class Scatter {
  constant,  // the same everywhere: the pooled replicate sd is the scatter at the truth
  growing,   // 0.4 to 1.6 times that from one end of mu_r to the other: pooled sd is an average
};

// Quadratic responses in unit coordinates u in [0, 1]^2, so that a degree-2 polynomial
// is exact and the surrogate's error is its estimation error alone.
struct Response {
  double a, b, c, d, e;
  double operator()(double u1, double u2) const {
    return a + b * u1 + c * u2 + d * u1 * u2 + e * u1 * u1;
  }
};

std::vector<Response> responses() {
  std::vector<Response> r;
  for (int k = 0; k < kObservables; ++k) {
    const double s = 1.0 + 0.3 * k;
    r.push_back({10.0 * s, 6.0 * s * ((k % 2) ? 1.0 : -0.5), 8.0 * s * ((k % 3) ? 1.0 : 0.4),
                 3.0 * s, 2.0 * s * ((k % 2) ? -1.0 : 1.0)});
  }
  return r;
}

struct Scenario {
  Scatter scatter = Scatter::constant;
  std::string surrogate = "polynomial";  // | "gaussian_process"
  bool local_scatter = false;            // the corrected rule of scatter_budget.hpp
  // The first four observables come from the same runs (a sandglass's discharge time and
  // its m(t) segments): one draw of the DEM scatter for all four.
  bool shared_runs = false;
  // The test of correlated_detection.hpp: replicate correlation, whitened GLS refit.
  bool correlated_test = false;
  // Diagnostic: sigma_dem from the true scatter at the truth instead of the pooled estimate.
  bool oracle_scatter = false;
  // The predictive p-value of correlated_mismatch (ScatterUncertainty, nu = 16).
  bool scatter_uncertainty = false;
  // Range of the truth's first unit coordinate (the one the growing scatter grows with).
  double truth_low = 0.15, truth_high = 0.85;
  int cases = 1000;
  std::uint64_t seed = 1;
};

struct NullStatistics {
  std::vector<double> p;
  double mean_chi2_per_dof = 0.0, median_chi2_per_dof = 0.0;
  double ks = 0.0;
  int alarms_05 = 0, alarms_01 = 0;
};

double ks_uniform(std::vector<double> p) {
  std::sort(p.begin(), p.end());
  const double n = static_cast<double>(p.size());
  double d = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    d = std::max({d, (static_cast<double>(i) + 1.0) / n - p[i], p[i] - static_cast<double>(i) / n});
  return d;
}

NullStatistics run_null_cases(const Scenario& sc) {
  const auto f = responses();
  const std::vector<ParameterBounds> bounds = {{"mu_r", 0.05, 0.4}, {"mu_s", 0.2, 0.8}};
  std::mt19937_64 rng(sc.seed);
  std::normal_distribution<double> z(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.15, 0.85);
  CalibrationOptions co;
  co.multistart_points = 2;
  co.grid_points_per_axis = 3;
  co.mcmc_samples = 0;

  // Scatter of one run at unit point (u1, u2): about 8 % of the response's mean over the
  // box, constant or growing fourfold along mu_r.
  auto scatter = [&](int k, double u1, double /*u2*/) {
    const double typical = 0.08 * f[static_cast<std::size_t>(k)](0.5, 0.5);
    if (sc.scatter == Scatter::constant) return typical;
    return typical * (0.4 + 1.2 * u1);
  };

  NullStatistics out;
  double chi2_per_dof_sum = 0.0;
  std::vector<double> chi2_per_dof;
  for (int c = 0; c < sc.cases; ++c) {
    const double t1 = sc.truth_low + (sc.truth_high - sc.truth_low) * (uni(rng) - 0.15) / 0.7;
    const double t2 = uni(rng);
    std::vector<Target> targets;
    std::vector<std::vector<ReplicatePoint>> replicates;
    std::vector<double> shared_design, shared_recording;
    for (int r = 0; r < kLevels * kLevels * kDesignReplicates; ++r) shared_design.push_back(z(rng));
    for (int r = 0; r < kRecordingRepeats; ++r) shared_recording.push_back(z(rng));
    for (int k = 0; k < kObservables; ++k) {
      surrogate::ReplicatedData data;
      data.input_names = {"mu_r", "mu_s"};
      data.lower = {0.05, 0.2};
      data.upper = {0.4, 0.8};
      data.output_name = "obs" + std::to_string(k);
      const int rows = kLevels * kLevels * kDesignReplicates;
      data.x.resize(rows, 2);
      data.y.resize(rows);
      int row = 0, group = 0;
      std::vector<ReplicatePoint> points;
      for (int i = 0; i < kLevels; ++i)
        for (int j = 0; j < kLevels; ++j, ++group) {
          const double u1 = i / (kLevels - 1.0), u2 = j / (kLevels - 1.0);
          ReplicatePoint pt;
          pt.x = Eigen::Vector2d(0.05 + 0.35 * u1, 0.2 + 0.6 * u2);
          for (int r = 0; r < kDesignReplicates; ++r, ++row) {
            data.x(row, 0) = pt.x(0);
            data.x(row, 1) = pt.x(1);
            data.y(row) = f[static_cast<std::size_t>(k)](u1, u2) +
                          scatter(k, u1, u2) * (sc.shared_runs && k < 4
                                                    ? shared_design[static_cast<std::size_t>(row)]
                                                    : z(rng));
            data.group.push_back(group);
            pt.values.push_back(data.y(row));
          }
          points.push_back(pt);
        }
      surrogate::SurrogateSpec spec;
      spec.model = sc.surrogate;
      spec.degree = 2;
      spec.starts = 2;
      const bool shared = sc.shared_runs && k < 4;
      const auto fit = surrogate::fit_surrogate(data, spec);

      const double sd_truth = scatter(k, t1, t2);
      double mean = 0.0;
      for (int r = 0; r < kRecordingRepeats; ++r)
        mean += f[static_cast<std::size_t>(k)](t1, t2) +
                sd_truth * (shared ? shared_recording[static_cast<std::size_t>(r)] : z(rng));
      mean /= kRecordingRepeats;
      // The instrument: half the DEM term, as in tests/concealed (AoR 0.5 deg against
      // 1.9 deg / sqrt(3)).
      const double sigma_m = 0.5 * scatter(k, 0.5, 0.5) / std::sqrt(double(kRecordingRepeats));
      Target t;
      // The first four share a setup (and, with shared_runs, its runs).
      t.setup = k < 4 ? "sandglass" : "setup_" + std::to_string(k);
      t.observable = data.output_name;
      t.measured = mean + sigma_m * z(rng);
      t.sigma_measured = sigma_m;
      t.model = fit.model;
      t.sigma_dem =
          (sc.oracle_scatter ? sd_truth : fit.scatter.sd) / std::sqrt(double(kRecordingRepeats));
      targets.push_back(t);
      replicates.push_back(points);
    }
    CalibrationProblem problem(bounds, targets);
    auto minima = find_minima(problem, co);
    if (sc.local_scatter) {
      const auto local = with_local_scatter(targets, replicates,
                                            std::vector<int>(targets.size(), kRecordingRepeats),
                                            minima.front().theta, bounds);
      CalibrationProblem second(bounds, local);
      minima = find_minima(second, co);
    }
    ScatterUncertainty uncertainty;
    if (sc.scatter_uncertainty) {
      uncertainty.degrees_of_freedom = kLevels * kLevels * (kDesignReplicates - 1);
      uncertainty.draws = 1000;
      uncertainty.seed = sc.seed + static_cast<std::uint64_t>(c);
    }
    std::vector<std::string> setups;
    for (const auto& t : targets) setups.push_back(t.setup);
    const auto d =
        sc.correlated_test
            ? correlated_mismatch(CalibrationProblem(bounds, targets), minima.front().theta,
                                  replicate_correlation(replicates, setups), {}, 20, uncertainty)
                  .detection
            : detect_mismatch(minima.front().chi_squared, kObservables, 2);
    chi2_per_dof.push_back(d.chi_square_per_dof);
    out.p.push_back(d.p_value);
    chi2_per_dof_sum += d.chi_square_per_dof;
    out.alarms_05 += d.p_value < 0.05 ? 1 : 0;
    out.alarms_01 += d.p_value < 0.01 ? 1 : 0;
  }
  out.mean_chi2_per_dof = chi2_per_dof_sum / sc.cases;
  out.ks = ks_uniform(out.p);
  std::nth_element(chi2_per_dof.begin(), chi2_per_dof.begin() + sc.cases / 2, chi2_per_dof.end());
  out.median_chi2_per_dof = chi2_per_dof[static_cast<std::size_t>(sc.cases / 2)];
  return out;
}

void report(const char* name, const Scenario& sc, const NullStatistics& s) {
  std::printf(
      "[detection calibration] %s: N = %d, KS D = %.4f (1%% critical %.4f), alarms at 0.05: %d "
      "(%.3f), at 0.01: "
      "%d (%.3f), mean chi2/dof = %.3f, median %.3f (chi2(6): 0.891)\n",
      name, sc.cases, s.ks, 1.63 / std::sqrt(double(sc.cases)), s.alarms_05,
      s.alarms_05 / double(sc.cases), s.alarms_01, s.alarms_01 / double(sc.cases),
      s.mean_chi2_per_dof, s.median_chi2_per_dof);
}

void expect_calibrated(const Scenario& sc, const NullStatistics& s) {
  const double n = sc.cases;
  EXPECT_LT(s.ks, 1.63 / std::sqrt(n));
  const double sd = std::sqrt(n * 0.05 * 0.95);
  EXPECT_NEAR(s.alarms_05, n * 0.05, 3.3 * sd);
  EXPECT_NEAR(s.mean_chi2_per_dof, 1.0, 0.1);
}

// Measured, not asserted: the figures docs/detection_calibration.md quotes for the rule of
// today under scatter that varies over the box, and with observables that share runs. About
// 20 s, so disabled; run with --gtest_also_run_disabled_tests.
TEST(DetectionCalibration, DISABLED_Figures) {
  Scenario rel;
  rel.scatter = Scatter::growing;
  report("growing scatter, polynomial, pooled sd (today)", rel, run_null_cases(rel));
  rel.local_scatter = true;
  report("growing scatter, polynomial, local sd (corrected)", rel, run_null_cases(rel));
  // Conditional on where the truth lies: at the low-scatter end the pooled sd overstates.
  Scenario low;
  low.scatter = Scatter::growing;
  low.truth_low = 0.0;
  low.truth_high = 0.2;
  low.cases = 500;
  report("growing scatter, truth at the low-scatter end, pooled sd (today)", low,
         run_null_cases(low));
  low.local_scatter = true;
  report("growing scatter, truth at the low-scatter end, local sd", low, run_null_cases(low));
  Scenario shared;
  shared.shared_runs = true;
  report("constant scatter, 4 observables sharing runs, pooled sd", shared, run_null_cases(shared));
  shared.correlated_test = true;
  report("constant scatter, 4 observables sharing runs, correlated test", shared,
         run_null_cases(shared));
  shared.oracle_scatter = true;
  report("constant scatter, 4 observables sharing runs, correlated test, true scatter", shared,
         run_null_cases(shared));
  Scenario gp;
  gp.surrogate = "gaussian_process";
  gp.cases = 200;
  report("constant scatter, gaussian process, pooled sd", gp, run_null_cases(gp));
}

TEST(DetectionCalibration, ConstantScatterPolynomialSurrogate) {
  Scenario sc;
  const auto s = run_null_cases(sc);
  report("constant scatter, polynomial, pooled sd", sc, s);
  expect_calibrated(sc, s);
}

// The sandglass case with the scatter estimated, as in the pipeline: the predictive
// p-value (ScatterUncertainty) must meet the p-value criteria. The chi2/dof criterion is
// left out here, after measuring (1.13): the statistic is the same as the plain
// correlated test's, inflated by nu / (nu - 2) = 1.14 on its DEM part by the estimated
// scatter; it is the reference distribution that accounts for that, not the statistic.
TEST(DetectionCalibration, SharedRunsEstimatedScatterPredictivePValue) {
  Scenario sc;
  sc.shared_runs = true;
  sc.correlated_test = true;
  sc.scatter_uncertainty = true;
  sc.cases = 600;
  const auto s = run_null_cases(sc);
  report("shared runs, correlated test, predictive p (scatter estimated)", sc, s);
  const double n = sc.cases;
  EXPECT_LT(s.ks, 1.63 / std::sqrt(n));
  EXPECT_NEAR(s.alarms_05, n * 0.05, 3.3 * std::sqrt(n * 0.05 * 0.95));
}

// Scatter growing fourfold along mu_r: the pooled sd fails the criteria (KS D 0.073, see
// Figures); the local rule of scatter_budget.hpp, a second pass at the base fit, meets them.
TEST(DetectionCalibration, GrowingScatterLocalRule) {
  Scenario sc;
  sc.scatter = Scatter::growing;
  sc.local_scatter = true;
  const auto s = run_null_cases(sc);
  report("growing scatter, local sd", sc, s);
  expect_calibrated(sc, s);
}

// The sandglass case: four observables read off the same runs. The corrected statistic is
// calibrated by the same criteria when the scatter is known (oracle). With the scatter
// estimated from the 16 replicate pairs it is not yet: measured KS D 0.054, alarms 8.0 % at
// 0.05 and 2.9 % at 0.01 (Figures) -- one scatter estimate shared by four targets errs for
// all four at once, a t-like tail the chi-square reference ignores. The plain test there:
// KS D 0.163, median chi2/dof 0.70 against 0.89, alarms 2.2 % at 0.01.
TEST(DetectionCalibration, SharedRunsCorrelatedTestKnownScatter) {
  Scenario sc;
  sc.shared_runs = true;
  sc.correlated_test = true;
  sc.oracle_scatter = true;
  const auto s = run_null_cases(sc);
  report("shared runs, correlated test", sc, s);
  expect_calibrated(sc, s);
}

// The corrected test must not cost anything where the targets are independent.
TEST(DetectionCalibration, CorrelatedTestOnIndependentTargets) {
  Scenario sc;
  sc.correlated_test = true;
  const auto s = run_null_cases(sc);
  report("independent runs, correlated test", sc, s);
  expect_calibrated(sc, s);
}

}  // namespace
}  // namespace demcal::calibrate
