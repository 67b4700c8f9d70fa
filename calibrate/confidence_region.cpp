#include "calibrate/confidence_region.hpp"

#include <ceres/ceres.h>
#include <gsl/gsl_cdf.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace demcal::calibrate {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Grid points evaluated per predict() call: large enough that a GP's per-call overhead
// vanishes, small enough that its cross-covariance matrix stays a few tens of MB.
constexpr Eigen::Index kGridChunk = 4096;
// Distinct node positions per axis below which the region counts as unresolved.
constexpr std::size_t kResolvedNodes = 5;

// A deterministic sign for a direction: its first clearly non-zero entry positive.
Eigen::VectorXd oriented(Eigen::VectorXd v) {
  const double n = v.norm();
  if (!(n > 0.0)) return v;
  v /= n;
  for (Eigen::Index j = 0; j < v.size(); ++j)
    if (std::abs(v(j)) > 1e-12) {
      if (v(j) < 0.0) v = -v;
      break;
    }
  return v;
}

std::vector<double> linspace(double a, double b, int n) {
  std::vector<double> x(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) x[static_cast<std::size_t>(i)] = a + (b - a) * i / (n - 1.0);
  x.back() = b;
  return x;
}

}  // namespace

GaussNewtonUncertainty gauss_newton_uncertainty(const CalibrationProblem& problem,
                                                const Eigen::VectorXd& theta,
                                                const CalibrationOptions& options) {
  const Eigen::Index p = problem.parameter_count();
  const Eigen::Index n = problem.target_count();
  if (theta.size() != p)
    throw std::invalid_argument("calibrate: theta has " + std::to_string(theta.size()) +
                                " values but " + std::to_string(p) + " parameters are calibrated");
  const Eigen::VectorXd range = problem.range();
  const Eigen::VectorXd u0 = problem.to_unit(theta);
  std::vector<double> u(u0.data(), u0.data() + p);

  ceres::Problem cp;
  cp.AddResidualBlock(problem.make_cost_function().release(), nullptr, u.data());
  double cost = 0.0;
  ceres::CRSMatrix crs;
  if (!cp.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, &crs))
    throw std::runtime_error("calibrate: the Jacobian cannot be evaluated at the minimum");
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n, p);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[static_cast<std::size_t>(row)]; k < crs.rows[static_cast<std::size_t>(row) + 1]; ++k)
      j(row, crs.cols[static_cast<std::size_t>(k)]) = crs.values[static_cast<std::size_t>(k)];

  GaussNewtonUncertainty g;
  // Full V: with fewer targets than parameters its extra columns span the null space,
  // which JacobiSVD's min(n, p) singular values alone would not reveal.
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(j, Eigen::ComputeFullV);
  g.singular_values = Eigen::VectorXd::Zero(p);
  g.singular_values.head(svd.singularValues().size()) = svd.singularValues();
  const double largest = g.singular_values(0);
  const double ratio = largest > 0.0 ? g.singular_values(p - 1) / largest : 0.0;
  g.rank_deficient = !(ratio >= options.rank_condition_threshold);
  g.weakest_direction = oriented(range.asDiagonal() * svd.matrixV().col(p - 1));

  g.covariance = Eigen::MatrixXd::Constant(p, p, kNaN);
  g.standard_errors.assign(static_cast<std::size_t>(p), kNaN);
  if (!g.rank_deficient) {
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    // Ceres fails when s_min / s_max < sqrt(min_reciprocal_condition_number): the same
    // test as above, so the two never disagree.
    co.min_reciprocal_condition_number =
        options.rank_condition_threshold * options.rank_condition_threshold;
    co.null_space_rank = 0;
    co.num_threads = 1;
    ceres::Covariance covariance(co);
    const std::vector<std::pair<const double*, const double*>> blocks{{u.data(), u.data()}};
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> cu(p, p);
    if (covariance.Compute(blocks, &cp) &&
        covariance.GetCovarianceBlock(u.data(), u.data(), cu.data()) && cu.allFinite()) {
      g.covariance = range.asDiagonal() * cu * range.asDiagonal();
      g.covariance_available = true;
      for (Eigen::Index k = 0; k < p; ++k)
        g.standard_errors[static_cast<std::size_t>(k)] = std::sqrt(std::max(g.covariance(k, k), 0.0));
    }
  }
  return g;
}

std::vector<double> grid_cell_measures(const std::vector<std::vector<double>>& axes) {
  std::size_t total = 1;
  for (const auto& a : axes) total *= a.size();
  std::vector<double> w(total, 1.0);
  std::size_t stride = 1;
  for (const auto& a : axes) {
    const std::size_t na = a.size();
    std::vector<double> cell(na, 0.0);
    for (std::size_t i = 0; i + 1 < na; ++i) {
      const double h = a[i + 1] - a[i];
      cell[i] += 0.5 * h;
      cell[i + 1] += 0.5 * h;
    }
    for (std::size_t k = 0; k < total; ++k) w[k] *= cell[(k / stride) % na];
    stride *= na;
  }
  return w;
}

LikelihoodRegion likelihood_region(const CalibrationProblem& problem,
                                   double chi_squared_at_optimum,
                                   const CalibrationOptions& options) {
  validate(options);
  const Eigen::Index p = problem.parameter_count();
  const auto nt = static_cast<std::size_t>(problem.target_count());
  LikelihoodRegion reg;
  reg.confidence = options.confidence;
  if (p > 3) return reg;
  reg.available = true;

  const int n_axis = p <= 2 ? options.grid_points_per_axis : options.grid_points_per_axis_3d;
  for (const ParameterBounds& b : problem.parameters())
    reg.axes.push_back(linspace(b.lower, b.upper, n_axis));
  std::size_t total = 1;
  for (Eigen::Index j = 0; j < p; ++j) total *= static_cast<std::size_t>(n_axis);

  reg.chi_squared.resize(total);
  reg.log_posterior.resize(total);
  reg.predicted_mean.assign(nt, std::vector<double>(total));
  const auto node = [&](std::size_t k, Eigen::Index j) {
    std::size_t index = k;
    for (Eigen::Index d = 0; d < j; ++d) index /= static_cast<std::size_t>(n_axis);
    return reg.axes[static_cast<std::size_t>(j)][index % static_cast<std::size_t>(n_axis)];
  };
  for (std::size_t start = 0; start < total; start += static_cast<std::size_t>(kGridChunk)) {
    const std::size_t count = std::min(total - start, static_cast<std::size_t>(kGridChunk));
    Eigen::MatrixXd points(static_cast<Eigen::Index>(count), p);
    for (std::size_t q = 0; q < count; ++q)
      for (Eigen::Index j = 0; j < p; ++j) points(static_cast<Eigen::Index>(q), j) = node(start + q, j);
    const TargetPredictions pred = problem.evaluate(points);
    for (std::size_t q = 0; q < count; ++q) {
      const auto row = static_cast<Eigen::Index>(q);
      reg.chi_squared[start + q] = pred.chi_squared(row);
      reg.log_posterior[start + q] = -0.5 * pred.chi_squared(row) - 0.5 * pred.log_variance_sum(row);
      for (std::size_t i = 0; i < nt; ++i)
        reg.predicted_mean[i][start + q] = pred.mean(row, static_cast<Eigen::Index>(i));
    }
  }

  std::size_t best = 0;
  for (std::size_t k = 1; k < total; ++k)
    if (reg.chi_squared[k] < reg.chi_squared[best]) best = k;
  reg.grid_minimum.resize(p);
  for (Eigen::Index j = 0; j < p; ++j) reg.grid_minimum(j) = node(best, j);
  reg.chi_squared_min = std::min(reg.chi_squared[best], chi_squared_at_optimum);
  reg.threshold = reg.chi_squared_min + gsl_cdf_chisq_Pinv(options.confidence, static_cast<double>(p));

  const std::vector<double> weights = grid_cell_measures(reg.axes);
  reg.inside.assign(total, false);
  std::vector<std::vector<bool>> seen(static_cast<std::size_t>(p), std::vector<bool>(static_cast<std::size_t>(n_axis), false));
  Eigen::VectorXd sum_w_x = Eigen::VectorXd::Zero(p);
  Eigen::MatrixXd sum_w_xx = Eigen::MatrixXd::Zero(p, p);
  double sum_w = 0.0;
  for (const ParameterBounds& b : problem.parameters()) {
    ParameterExtent e;
    e.name = b.name;
    e.lower = e.upper = kNaN;
    reg.extent.push_back(e);
  }
  for (std::size_t k = 0; k < total; ++k) {
    if (!(reg.chi_squared[k] <= reg.threshold)) continue;
    reg.inside[k] = true;
    ++reg.nodes_inside;
    reg.area += weights[k];
    Eigen::VectorXd x(p);
    std::size_t index = k;
    for (Eigen::Index j = 0; j < p; ++j) {
      const std::size_t i = index % static_cast<std::size_t>(n_axis);
      index /= static_cast<std::size_t>(n_axis);
      x(j) = reg.axes[static_cast<std::size_t>(j)][i];
      seen[static_cast<std::size_t>(j)][i] = true;
      ParameterExtent& e = reg.extent[static_cast<std::size_t>(j)];
      e.lower = std::isnan(e.lower) ? x(j) : std::min(e.lower, x(j));
      e.upper = std::isnan(e.upper) ? x(j) : std::max(e.upper, x(j));
      if (i == 0) e.touches_lower_bound = true;
      if (i + 1 == static_cast<std::size_t>(n_axis)) e.touches_upper_bound = true;
    }
    sum_w += weights[k];
    sum_w_x += weights[k] * x;
    sum_w_xx += weights[k] * x * x.transpose();
  }

  reg.resolved = true;
  for (const auto& s : seen)
    if (static_cast<std::size_t>(std::count(s.begin(), s.end(), true)) < kResolvedNodes) reg.resolved = false;

  reg.principal_axis = Eigen::VectorXd::Constant(p, kNaN);
  if (reg.nodes_inside >= 2) {
    const Eigen::VectorXd mean = sum_w_x / sum_w;
    const Eigen::MatrixXd cov = sum_w_xx / sum_w - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
    // Eigenvalues ascend: the last vector is the major axis.
    reg.principal_axis = oriented(eig.eigenvectors().col(p - 1));
  }
  return reg;
}

bool region_contains(const CalibrationProblem& problem, const LikelihoodRegion& region,
                     const Eigen::VectorXd& theta) {
  return problem.inside_bounds(theta) && problem.chi_squared(theta) <= region.threshold;
}

}  // namespace demcal::calibrate
