#include "calibrate/correlated_detection.hpp"

#include "calibrate/detail/number_text.hpp"

#include <gsl/gsl_cdf.h>
#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace demcal::calibrate {

Eigen::MatrixXd replicate_correlation(const std::vector<std::vector<ReplicatePoint>>& replicates,
                                      const std::vector<std::string>& setups, double min_z) {
  if (replicates.size() != setups.size())
    throw std::invalid_argument("replicate_correlation: one setup per replicate set is needed");
  const auto n = static_cast<Eigen::Index>(replicates.size());
  Eigen::MatrixXd c = Eigen::MatrixXd::Identity(n, n);
  // Within-point deviations, concatenated; empty when the sets cannot be paired.
  auto deviations = [](const std::vector<ReplicatePoint>& pts) {
    std::vector<double> d;
    for (const auto& p : pts) {
      double m = 0.0;
      for (double v : p.values) m += v;
      m /= static_cast<double>(std::max<std::size_t>(p.values.size(), 1));
      for (double v : p.values) d.push_back(p.values.size() > 1 ? v - m : 0.0);
    }
    return d;
  };
  std::vector<std::vector<double>> dev;
  for (const auto& r : replicates) dev.push_back(deviations(r));
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j) {
      const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(j);
      if (setups[a] != setups[b] || dev[a].size() != dev[b].size() || dev[a].empty()) continue;
      bool paired = replicates[a].size() == replicates[b].size();
      for (std::size_t k = 0; paired && k < replicates[a].size(); ++k)
        paired = replicates[a][k].values.size() == replicates[b][k].values.size();
      if (!paired) continue;
      double sxy = 0.0, sx = 0.0, sy = 0.0;
      int dof = 0;
      for (const auto& pt : replicates[a])
        dof += static_cast<int>(pt.values.size()) - (pt.values.empty() ? 0 : 1);
      for (std::size_t k = 0; k < dev[a].size(); ++k) {
        sxy += dev[a][k] * dev[b][k];
        sx += dev[a][k] * dev[a][k];
        sy += dev[b][k] * dev[b][k];
      }
      if (!(sx > 0.0 && sy > 0.0)) continue;
      const double r = std::clamp(sxy / std::sqrt(sx * sy), -1.0, 1.0);
      // Whitening by a noisy correlation inflates chi^2 (spurious correlations are
      // "explained away" as if real): keep only those that stand out of their noise by
      // Fisher's z, atanh(r) sqrt(dof - 3) >= min_z.
      const double z =
          std::atanh(std::min(std::abs(r), 1.0 - 1e-12)) * std::sqrt(std::max(dof - 3, 0));
      if (z >= min_z) c(i, j) = c(j, i) = r;
    }
  return c;
}

Eigen::MatrixXd error_correlation(const CalibrationProblem& problem, const Eigen::VectorXd& theta,
                                  const Eigen::MatrixXd& rho) {
  const Eigen::Index n = problem.target_count();
  if (rho.rows() != n || rho.cols() != n)
    throw std::invalid_argument("error_correlation: the run correlation must be " +
                                std::to_string(n) + " x " + std::to_string(n));
  const TargetPredictions pred = problem.evaluate(theta.transpose());
  Eigen::VectorXd dem(n), surr(n), sigma(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Target& t = problem.targets()[static_cast<std::size_t>(i)];
    sigma(i) = pred.sigma_total(0, i);
    dem(i) = t.sigma_dem;
    const double rest =
        sigma(i) * sigma(i) - t.sigma_measured * t.sigma_measured - t.sigma_dem * t.sigma_dem;
    surr(i) = std::sqrt(std::max(rest, 0.0));
  }
  Eigen::MatrixXd c = Eigen::MatrixXd::Identity(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      if (i != j)
        c(i, j) = rho(i, j) * (dem(i) * dem(j) + surr(i) * surr(j)) / (sigma(i) * sigma(j));
  return c;
}

CorrelatedFit correlated_mismatch(const CalibrationProblem& problem,
                                  const Eigen::VectorXd& theta_start, const Eigen::MatrixXd& rho,
                                  const DetectionOptions& options, int iterations,
                                  const ScatterUncertainty& scatter) {
  if (scatter.degrees_of_freedom < 0 || (scatter.degrees_of_freedom > 0 && scatter.draws < 100))
    throw std::invalid_argument(
        "correlated_mismatch: ScatterUncertainty needs degrees_of_freedom >= 0 and draws >= 100");
  if (theta_start.size() != problem.parameter_count())
    throw std::invalid_argument("correlated_mismatch: theta_start has the wrong size");
  // C is held at the start: it changes slowly with theta, and a fixed metric keeps the
  // Gauss-Newton steps those of one least-squares problem.
  const Eigen::LLT<Eigen::MatrixXd> llt(error_correlation(problem, theta_start, rho));
  if (llt.info() != Eigen::Success)
    throw std::runtime_error("correlated_mismatch: C is not positive definite");
  const Eigen::VectorXd lo = problem.lower(), hi = problem.upper();
  auto whitened = [&](const Eigen::VectorXd& th, Eigen::MatrixXd* jw) {
    Eigen::MatrixXd j;
    const Eigen::VectorXd r = problem.residuals(th, jw ? &j : nullptr);
    if (jw) *jw = llt.matrixL().solve(j);
    return Eigen::VectorXd(llt.matrixL().solve(r));
  };
  CorrelatedFit f;
  f.theta = theta_start;
  Eigen::MatrixXd jw;
  Eigen::VectorXd w = whitened(f.theta, &jw);
  double chi2 = w.squaredNorm();
  for (int it = 0; it < iterations; ++it) {
    const Eigen::VectorXd step = -jw.colPivHouseholderQr().solve(w);
    // Halve a step that does not lower chi^2 (a Gauss-Newton step can overshoot).
    bool improved = false;
    for (double scale = 1.0; scale > 1e-4 && !improved; scale *= 0.5) {
      const Eigen::VectorXd trial = (f.theta + scale * step).cwiseMax(lo).cwiseMin(hi);
      const Eigen::VectorXd wt = whitened(trial, nullptr);
      if (wt.squaredNorm() < chi2) {
        f.theta = trial;
        chi2 = wt.squaredNorm();
        improved = true;
      }
    }
    if (!improved) break;
    w = whitened(f.theta, &jw);
  }
  f.chi_square = chi2;
  const auto n = problem.target_count(), p = problem.parameter_count();
  f.detection = detect_mismatch(chi2, static_cast<int>(n), static_cast<int>(p), options);
  f.p_value_known_scatter = f.detection.p_value;
  if (scatter.degrees_of_freedom == 0 || f.detection.verdict == MismatchVerdict::untestable)
    return f;

  // The parts of each standardized error: DEM scatter a, surrogate s, instrument m.
  const TargetPredictions pred = problem.evaluate(theta_start.transpose());
  Eigen::VectorXd a(n), sv(n), m(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Target& t = problem.targets()[static_cast<std::size_t>(i)];
    const double sig = pred.sigma_total(0, i);
    a(i) = t.sigma_dem / sig;
    m(i) = t.sigma_measured / sig;
    sv(i) = std::sqrt(std::max(1.0 - a(i) * a(i) - m(i) * m(i), 0.0));
  }
  // A square root of the run correlation (eigenvalues clipped at 0: thresholding may
  // leave it slightly indefinite).
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(rho);
  const Eigen::MatrixXd root =
      eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  // Groups: connected by a non-zero correlation.
  std::vector<int> group(static_cast<std::size_t>(n), -1);
  int groups = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (group[static_cast<std::size_t>(i)] >= 0) continue;
    std::vector<Eigen::Index> stack = {i};
    group[static_cast<std::size_t>(i)] = groups;
    while (!stack.empty()) {
      const Eigen::Index k = stack.back();
      stack.pop_back();
      for (Eigen::Index j = 0; j < n; ++j)
        if (group[static_cast<std::size_t>(j)] < 0 && j != k && rho(k, j) != 0.0) {
          group[static_cast<std::size_t>(j)] = groups;
          stack.push_back(j);
        }
    }
    ++groups;
  }
  // The fit's projection in the whitened metric: T = |w|^2 - |Q^T w|^2.
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(jw);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(n, p);
  std::mt19937_64 rng(scatter.seed);
  std::normal_distribution<double> z(0.0, 1.0);
  std::chi_squared_distribution<double> chi(static_cast<double>(scatter.degrees_of_freedom));
  const double nu = scatter.degrees_of_freedom;
  int exceed = 0;
  Eigen::VectorXd u1(n), u2(n), e(n), g(groups);
  for (int b = 0; b < scatter.draws; ++b) {
    for (int k = 0; k < groups; ++k) g(k) = std::sqrt(nu / chi(rng));  // true / estimated sd
    for (Eigen::Index i = 0; i < n; ++i) {
      u1(i) = z(rng);
      u2(i) = z(rng);
    }
    const Eigen::VectorXd dem = root * u1, surr = root * u2;
    for (Eigen::Index i = 0; i < n; ++i)
      e(i) =
          a(i) * g(group[static_cast<std::size_t>(i)]) * dem(i) + sv(i) * surr(i) + m(i) * z(rng);
    const Eigen::VectorXd w = llt.matrixL().solve(e);
    const double t = w.squaredNorm() - (q.transpose() * w).squaredNorm();
    exceed += t >= chi2 ? 1 : 0;
  }
  // (exceed + 1) / (draws + 1): never 0, as a Monte Carlo p-value must not be.
  const double pv = (exceed + 1.0) / (scatter.draws + 1.0);
  MismatchDetection& d = f.detection;
  d.p_value = pv;
  const std::string numbers = "(chi2/dof = " + detail::fmt(d.chi_square_per_dof, 2) + ", " +
                              p_value_text(pv) + ", DEM scatter estimated)";
  d.verdict = pv < options.alpha ? MismatchVerdict::mismatch : MismatchVerdict::reproduced;
  d.statement =
      d.verdict == MismatchVerdict::mismatch
          ? "The recordings are not reproduced " + numbers + "."
          : "The base model reproduces the recordings " + numbers + ": no physics is added.";
  return f;
}

}  // namespace demcal::calibrate
