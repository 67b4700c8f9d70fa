#include "calibrate/weighted_variance_acquisition.hpp"

#include "surrogate/gaussian_process.hpp"
#include "surrogate/sobol_design.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace demcal::calibrate {
namespace {

// The weight the integral keeps: the rest (0.1 %) is the far tail, where a variance
// reduction cannot change the region.
constexpr double kKeptWeight = 0.999;

Eigen::MatrixXd grid_points(const CalibrationProblem& problem, int per_axis) {
  const auto p = problem.parameter_count();
  Eigen::Index nodes = 1;
  for (Eigen::Index j = 0; j < p; ++j) nodes *= per_axis;
  Eigen::MatrixXd u(nodes, p);
  for (Eigen::Index n = 0; n < nodes; ++n) {
    Eigen::Index rest = n;
    for (Eigen::Index j = 0; j < p; ++j) {  // first parameter fastest, as the region's grid
      u(n, j) = static_cast<double>(rest % per_axis) / static_cast<double>(per_axis - 1);
      rest /= per_axis;
    }
  }
  Eigen::MatrixXd theta(nodes, p);
  for (Eigen::Index n = 0; n < nodes; ++n)
    theta.row(n) = problem.from_unit(u.row(n).transpose()).transpose();
  return theta;
}

Eigen::VectorXd noise_variances(const CalibrationProblem& problem) {
  Eigen::VectorXd s2(problem.target_count());
  for (Eigen::Index i = 0; i < s2.size(); ++i) {
    const Target& t = problem.targets()[static_cast<std::size_t>(i)];
    s2(i) = t.sigma_measured * t.sigma_measured + t.sigma_dem * t.sigma_dem;
  }
  return s2;
}

std::shared_ptr<const surrogate::GaussianProcess> as_gp(const Target& t, std::size_t i) {
  auto gp = std::dynamic_pointer_cast<const surrogate::GaussianProcess>(t.model);
  if (!gp)
    throw std::invalid_argument("choose_batch: target " + std::to_string(i + 1) + " (" + t.setup +
                                " " + t.observable + ") has a " + t.model->kind() +
                                " surrogate; the acquisition needs a gaussian_process");
  return gp;
}

// The believer: the same GP with one more observation at x, valued at the predicted mean,
// hyperparameters held. Its variance is the GP's after a run at x, whatever the run returns.
surrogate::GaussianProcess with_point(const surrogate::GaussianProcess& gp,
                                      const Eigen::RowVectorXd& x, double noise_variance) {
  const auto& s = gp.state();
  Eigen::MatrixXd xa(s.x.rows() + 1, s.x.cols());
  xa << s.x, x;
  Eigen::VectorXd ya(s.y.size() + 1);
  ya << s.y, gp.predict_mean(x)(0);
  surrogate::GaussianProcessOptions go;
  go.kernel = s.kernel;
  go.mean = s.mean;
  go.nugget = s.nugget_mode;
  go.input_names = s.input_names;
  go.lower.assign(s.lower.data(), s.lower.data() + s.lower.size());
  go.upper.assign(s.upper.data(), s.upper.data() + s.upper.size());
  go.hyperparameters = gp.hyperparameters();
  if (s.nugget_mode == surrogate::NuggetMode::fixed) {
    const Eigen::VectorXd v = gp.point_nugget_variances();
    go.nugget_variances.assign(v.data(), v.data() + v.size());
    go.nugget_variances.push_back(noise_variance);
  }
  return surrogate::GaussianProcess::fit(xa, ya, go);
}

}  // namespace

PosteriorWeights posterior_weights(const CalibrationProblem& problem,
                                   const AdaptiveDesignOptions& options, double exponent) {
  if (!(exponent > 0.0 && exponent <= 1.0))
    throw std::invalid_argument("posterior_weights: exponent must be in (0, 1], got " +
                                std::to_string(exponent));
  const Eigen::MatrixXd grid = grid_points(problem, options.acquisition_grid_points_per_axis);
  const TargetPredictions pred = problem.evaluate(grid);
  Eigen::VectorXd log_post = -0.5 * (pred.chi_squared + pred.log_variance_sum);
  if (exponent != 1.0) log_post *= exponent;
  const double top = log_post.maxCoeff();
  Eigen::VectorXd w = (log_post.array() - top).exp().matrix();
  w /= w.sum();
  std::vector<Eigen::Index> order(static_cast<std::size_t>(grid.rows()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  // Ties (flat posteriors) keep the grid order, so the choice is the same on every platform.
  std::stable_sort(order.begin(), order.end(),
                   [&w](Eigen::Index a, Eigen::Index b) { return w(a) > w(b); });
  std::size_t kept = 0;
  double mass = 0.0;
  while (kept < order.size() && kept < static_cast<std::size_t>(options.integration_points) &&
         mass < kKeptWeight)
    mass += w(order[kept++]);
  PosteriorWeights out;
  out.points.resize(static_cast<Eigen::Index>(kept), grid.cols());
  out.weights.resize(static_cast<Eigen::Index>(kept));
  for (std::size_t k = 0; k < kept; ++k) {
    out.points.row(static_cast<Eigen::Index>(k)) = grid.row(order[k]);
    out.weights(static_cast<Eigen::Index>(k)) = w(order[k]) / mass;
  }
  return out;
}

PosteriorWeights average_weights(const PosteriorWeights& a, const PosteriorWeights& b) {
  if (a.points.cols() != b.points.cols())
    throw std::invalid_argument("average_weights: the weightings have different parameters");
  // Nodes of one grid: equal rows are the same node, bit for bit.
  std::map<std::vector<double>, double> sum;
  auto add = [&sum](const PosteriorWeights& w) {
    for (Eigen::Index g = 0; g < w.points.rows(); ++g) {
      const Eigen::RowVectorXd row = w.points.row(g);
      sum[std::vector<double>(row.data(), row.data() + row.size())] += 0.5 * w.weights(g);
    }
  };
  add(a);
  add(b);
  std::vector<std::pair<std::vector<double>, double>> nodes(sum.begin(), sum.end());
  // By decreasing weight (the candidates are every k-th node in this order); the map's order
  // breaks ties, so the result is the same on every platform.
  std::stable_sort(nodes.begin(), nodes.end(),
                   [](const auto& x, const auto& y) { return x.second > y.second; });
  PosteriorWeights out;
  out.points.resize(static_cast<Eigen::Index>(nodes.size()), a.points.cols());
  out.weights.resize(static_cast<Eigen::Index>(nodes.size()));
  double total = 0.0;
  for (const auto& n : nodes) total += n.second;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    for (std::size_t j = 0; j < nodes[k].first.size(); ++j)
      out.points(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(j)) = nodes[k].first[j];
    out.weights(static_cast<Eigen::Index>(k)) = nodes[k].second / total;
  }
  return out;
}

double weighted_surrogate_variance(const CalibrationProblem& problem,
                                   const PosteriorWeights& weights) {
  const Eigen::VectorXd s2 = noise_variances(problem);
  double total = 0.0;
  for (Eigen::Index i = 0; i < problem.target_count(); ++i) {
    const auto& t = problem.targets()[static_cast<std::size_t>(i)];
    const Eigen::VectorXd v = t.model->predict(weights.points).variance;
    total += weights.weights.dot(v) / s2(i);
  }
  return total / static_cast<double>(problem.target_count());
}

double batch_variance_drop(const CalibrationProblem& problem, const PosteriorWeights& weights,
                           const std::vector<double>& new_run_noise_variance,
                           const Eigen::MatrixXd& points) {
  const auto n_targets = static_cast<std::size_t>(problem.target_count());
  if (new_run_noise_variance.size() != n_targets)
    throw std::invalid_argument("batch_variance_drop: new_run_noise_variance has " +
                                std::to_string(new_run_noise_variance.size()) +
                                " entries, the problem has " + std::to_string(n_targets) +
                                " targets");
  const Eigen::VectorXd s2 = noise_variances(problem);
  double drop = 0.0;
  for (std::size_t i = 0; i < n_targets; ++i) {
    surrogate::GaussianProcess gp = *as_gp(problem.targets()[i], i);
    const Eigen::VectorXd before = gp.predict(weights.points).variance;
    for (Eigen::Index r = 0; r < points.rows(); ++r)
      gp = with_point(gp, points.row(r), new_run_noise_variance[i]);
    drop += weights.weights.dot(before - gp.predict(weights.points).variance) /
            s2(static_cast<Eigen::Index>(i));
  }
  return drop;
}

std::vector<AcquisitionChoice> choose_batch(const CalibrationProblem& problem,
                                            const PosteriorWeights& weights,
                                            const std::vector<double>& new_run_noise_variance,
                                            const Eigen::MatrixXd& design_points, int count,
                                            const AdaptiveDesignOptions& options) {
  const auto n_targets = static_cast<std::size_t>(problem.target_count());
  if (new_run_noise_variance.size() != n_targets)
    throw std::invalid_argument("choose_batch: new_run_noise_variance has " +
                                std::to_string(new_run_noise_variance.size()) +
                                " entries, the problem has " + std::to_string(n_targets) +
                                " targets");
  std::vector<surrogate::GaussianProcess> gps;
  for (std::size_t i = 0; i < n_targets; ++i) gps.push_back(*as_gp(problem.targets()[i], i));
  const Eigen::VectorXd s2 = noise_variances(problem);

  // Candidates: every k-th integration node (by weight), then Sobol points over the box.
  std::vector<Eigen::VectorXd> candidates;
  const Eigen::Index m = weights.points.rows();
  const Eigen::Index stride =
      std::max<Eigen::Index>(1, (m + options.candidate_points - 1) / options.candidate_points);
  for (Eigen::Index g = 0; g < m; g += stride)
    candidates.push_back(weights.points.row(g).transpose());
  if (options.exploration_points > 0) {
    std::vector<surrogate::ParameterRange> ranges;
    for (const auto& b : problem.parameters()) ranges.push_back({b.name, b.lower, b.upper, 2});
    for (const auto& row :
         surrogate::sobol_design(ranges, static_cast<std::size_t>(options.exploration_points)))
      candidates.push_back(
          Eigen::Map<const Eigen::VectorXd>(row.data(), static_cast<Eigen::Index>(row.size())));
  }

  std::vector<Eigen::VectorXd> taken_unit;  // design points and earlier choices
  for (Eigen::Index r = 0; r < design_points.rows(); ++r)
    taken_unit.push_back(problem.to_unit(design_points.row(r).transpose()));
  auto far_enough = [&](const Eigen::VectorXd& theta) {
    const Eigen::VectorXd u = problem.to_unit(theta);
    for (const auto& t : taken_unit)
      if ((u - t).norm() < options.min_separation) return false;
    return true;
  };

  // Current variances at the integration nodes, per target.
  std::vector<Eigen::VectorXd> variance(n_targets);
  for (std::size_t i = 0; i < n_targets; ++i) variance[i] = gps[i].predict(weights.points).variance;

  std::vector<AcquisitionChoice> chosen;
  for (int slot = 0; slot < count; ++slot) {
    double best_value = -1.0;
    std::size_t best = candidates.size();
    std::vector<surrogate::GaussianProcess> best_gps;
    std::vector<Eigen::VectorXd> best_variance;
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      if (!far_enough(candidates[c])) continue;
      double value = 0.0;
      std::vector<surrogate::GaussianProcess> refitted;
      std::vector<Eigen::VectorXd> after(n_targets);
      for (std::size_t i = 0; i < n_targets; ++i) {
        refitted.push_back(
            with_point(gps[i], candidates[c].transpose(), new_run_noise_variance[i]));
        after[i] = refitted.back().predict(weights.points).variance;
        value += weights.weights.dot(variance[i] - after[i]) / s2(static_cast<Eigen::Index>(i));
      }
      // Strictly greater: ties go to the earlier candidate (the heavier node).
      if (value > best_value) {
        best_value = value;
        best = c;
        best_gps = std::move(refitted);
        best_variance = std::move(after);
      }
    }
    if (best == candidates.size()) break;  // every candidate is too close to a taken point
    chosen.push_back({candidates[best], best_value});
    taken_unit.push_back(problem.to_unit(candidates[best]));
    gps = std::move(best_gps);
    variance = std::move(best_variance);
  }
  return chosen;
}

}  // namespace demcal::calibrate
