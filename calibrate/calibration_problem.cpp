#include "calibrate/calibration_problem.hpp"

#include "calibrate/confidence_region.hpp"
#include "surrogate/latin_hypercube_design.hpp"
#include "surrogate/sobol_design.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace demcal::calibrate {
namespace {

// Central-difference step of the variance derivative, relative to each parameter's range:
// near the cube root of machine epsilon, which balances truncation against rounding.
constexpr double kVarianceStep = 1e-5;
// Bound-scaled distance within which a minimum counts as lying on a bound.
constexpr double kAtBoundTolerance = 1e-6;
// Points per segment when testing whether two converged points share a valley.
constexpr int kBarrierPoints = 15;
constexpr std::size_t kPairsPerBatch = 256;

std::string quoted(const std::string& s) { return "'" + s + "'"; }

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

void check_prediction(const std::string& label, const surrogate::Prediction& pred, Eigen::Index rows) {
  if (pred.mean.size() != rows || pred.variance.size() != rows)
    throw std::runtime_error("calibrate: the model of " + label + " returned " +
                             std::to_string(pred.mean.size()) + " means and " +
                             std::to_string(pred.variance.size()) + " variances for " +
                             std::to_string(rows) + " points");
}

// Ceres' view of the problem. An exception must not unwind through Ceres' solver loop, so
// a throwing model becomes a failed evaluation (Ceres then shrinks the step or stops) and
// its message is kept for the caller.
class CalibrationCost final : public ceres::CostFunction {
 public:
  explicit CalibrationCost(const CalibrationProblem& problem) : problem_(problem) {
    set_num_residuals(static_cast<int>(problem.target_count()));
    mutable_parameter_block_sizes()->push_back(static_cast<std::int32_t>(problem.parameter_count()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Index p = problem_.parameter_count();
    const Eigen::Index n = problem_.target_count();
    try {
      const Eigen::VectorXd theta =
          problem_.from_unit(Eigen::Map<const Eigen::VectorXd>(parameters[0], p));
      const bool want_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
      Eigen::MatrixXd j;
      const Eigen::VectorXd r = problem_.residuals(theta, want_jacobian ? &j : nullptr);
      if (!r.allFinite()) return false;
      Eigen::Map<Eigen::VectorXd>(residuals, n) = r;
      if (want_jacobian) {
        if (!j.allFinite()) return false;
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> out(
            jacobians[0], n, p);
        out = j * problem_.range().asDiagonal();
      }
      return true;
    } catch (const std::exception& e) {
      if (error_.empty()) error_ = e.what();
      return false;
    }
  }

  const std::string& error() const { return error_; }

 private:
  const CalibrationProblem& problem_;
  mutable std::string error_;
};

struct LocalSolve {
  Eigen::VectorXd u;
  double chi_squared = 0.0;
  bool usable = false;
  std::string report;
  std::string error;
};

LocalSolve solve_local(const CalibrationProblem& problem, const Eigen::VectorXd& u0,
                       const CalibrationOptions& options) {
  const Eigen::Index p = problem.parameter_count();
  std::vector<double> u(u0.data(), u0.data() + p);
  auto cost = std::make_unique<CalibrationCost>(problem);
  const CalibrationCost* cost_view = cost.get();
  ceres::Problem cp;
  cp.AddResidualBlock(cost.release(), nullptr, u.data());
  for (int j = 0; j < static_cast<int>(p); ++j) {
    cp.SetParameterLowerBound(u.data(), j, 0.0);
    cp.SetParameterUpperBound(u.data(), j, 1.0);
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.max_num_iterations = options.max_solver_iterations;
  // Tight: the fits are tiny, and recovery to 1e-6 needs the zero-residual case to run to
  // the end rather than stop on a relative cost change.
  so.function_tolerance = 1e-14;
  so.gradient_tolerance = 1e-14;
  so.parameter_tolerance = 1e-12;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  so.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &cp, &summary);

  LocalSolve out;
  out.u = Eigen::Map<const Eigen::VectorXd>(u.data(), p).cwiseMax(0.0).cwiseMin(1.0);
  out.report = summary.BriefReport();
  out.error = cost_view->error();
  out.usable = summary.IsSolutionUsable();
  if (out.usable) {
    out.chi_squared = problem.chi_squared(problem.from_unit(out.u));
    out.usable = std::isfinite(out.chi_squared);
  }
  return out;
}

Minimum make_minimum(const CalibrationProblem& problem, const Eigen::VectorXd& u,
                     const CalibrationOptions& options) {
  Minimum m;
  m.theta = problem.from_unit(u);
  const TargetPredictions pred = problem.evaluate(m.theta.transpose());
  m.chi_squared = pred.chi_squared(0);
  for (Eigen::Index i = 0; i < problem.target_count(); ++i) {
    m.residuals.push_back(pred.residual(0, i));
    m.predicted.push_back(pred.mean(0, i));
    m.sigma_total.push_back(pred.sigma_total(0, i));
  }
  m.at_bound = (u.array() <= kAtBoundTolerance).any() || (u.array() >= 1.0 - kAtBoundTolerance).any();
  const GaussNewtonUncertainty g = gauss_newton_uncertainty(problem, m.theta, options);
  m.covariance = g.covariance;
  m.covariance_available = g.covariance_available;
  m.standard_errors = g.standard_errors;
  m.rank_deficient = g.rank_deficient;
  m.singular_values = g.singular_values;
  m.weakest_direction = g.weakest_direction;
  return m;
}

// Union-find over converged points.
struct Clusters {
  std::vector<std::size_t> parent;
  explicit Clusters(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t root(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(std::size_t a, std::size_t b) {
    a = root(a);
    b = root(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

std::vector<Eigen::VectorXd> unit_starts(Eigen::Index p, const CalibrationOptions& options) {
  std::vector<Eigen::VectorXd> starts{Eigen::VectorXd::Constant(p, 0.5)};
  if (options.multistart_points <= 0) return starts;
  const auto count = static_cast<std::size_t>(options.multistart_points);
  std::vector<std::vector<double>> unit;
  if (static_cast<std::size_t>(p) <= surrogate::kSobolMaxDimensions) {
    std::vector<surrogate::ParameterRange> box(static_cast<std::size_t>(p));
    for (std::size_t j = 0; j < box.size(); ++j) box[j] = {"u" + std::to_string(j), 0.0, 1.0, 2};
    // The sequence's first point is the centre, already a start.
    unit = surrogate::sobol_design(box, count, 1);
  } else {
    surrogate::LatinHypercubeOptions lhs;
    lhs.points = count;
    lhs.seed = options.seed;
    unit = surrogate::latin_hypercube_unit(static_cast<std::size_t>(p), lhs);
  }
  for (const auto& row : unit) starts.push_back(Eigen::Map<const Eigen::VectorXd>(row.data(), p));
  return starts;
}

}  // namespace

void validate(const CalibrationOptions& o) {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("calibration options: " + what);
  };
  if (o.multistart_points < 0)
    fail("multistart_points must be >= 0, got " + std::to_string(o.multistart_points));
  if (!(o.confidence > 0.0 && o.confidence < 1.0))
    fail("confidence must lie in (0, 1), got " + number(o.confidence));
  if (o.grid_points_per_axis < 3)
    fail("grid_points_per_axis must be >= 3, got " + std::to_string(o.grid_points_per_axis));
  if (o.grid_points_per_axis_3d < 3)
    fail("grid_points_per_axis_3d must be >= 3, got " + std::to_string(o.grid_points_per_axis_3d));
  if (o.mcmc_samples < 0) fail("mcmc_samples must be >= 0, got " + std::to_string(o.mcmc_samples));
  if (o.mcmc_burn_in < 0) fail("mcmc_burn_in must be >= 0, got " + std::to_string(o.mcmc_burn_in));
  if (o.mcmc_chains < 1) fail("mcmc_chains must be >= 1, got " + std::to_string(o.mcmc_chains));
  if (o.histogram_bins < 1)
    fail("histogram_bins must be >= 1, got " + std::to_string(o.histogram_bins));
  if (!(o.distinct_minimum_tolerance > 0.0))
    fail("distinct_minimum_tolerance must be > 0, got " + number(o.distinct_minimum_tolerance));
  if (!(o.distinct_minimum_barrier >= 0.0))
    fail("distinct_minimum_barrier must be >= 0, got " + number(o.distinct_minimum_barrier));
  if (!(o.rank_condition_threshold > 0.0 && o.rank_condition_threshold < 1.0))
    fail("rank_condition_threshold must lie in (0, 1), got " + number(o.rank_condition_threshold));
  if (o.max_solver_iterations < 1)
    fail("max_solver_iterations must be >= 1, got " + std::to_string(o.max_solver_iterations));
}

CalibrationProblem::CalibrationProblem(std::vector<ParameterBounds> parameters,
                                       std::vector<Target> targets)
    : parameters_(std::move(parameters)), targets_(std::move(targets)) {
  if (parameters_.empty()) throw std::invalid_argument("calibrate: no parameters to calibrate");
  if (targets_.empty()) throw std::invalid_argument("calibrate: no targets (measured quantities)");
  std::set<std::string> seen;
  for (std::size_t j = 0; j < parameters_.size(); ++j) {
    const ParameterBounds& b = parameters_[j];
    if (b.name.empty())
      throw std::invalid_argument("calibrate: parameter " + std::to_string(j) + " has no name");
    if (!seen.insert(b.name).second)
      throw std::invalid_argument("calibrate: parameter " + quoted(b.name) + " is listed twice");
    if (!std::isfinite(b.lower) || !std::isfinite(b.upper) || !(b.lower < b.upper))
      throw std::invalid_argument("calibrate: parameter " + quoted(b.name) + ": lower (" +
                                  number(b.lower) + ") must be below upper (" + number(b.upper) +
                                  "), both finite");
  }
  std::vector<std::string> names;
  for (const auto& b : parameters_) names.push_back(b.name);
  std::vector<std::string> sorted_names = names;
  std::sort(sorted_names.begin(), sorted_names.end());

  for (std::size_t i = 0; i < targets_.size(); ++i) {
    const Target& t = targets_[i];
    const std::string label = target_label(i);
    if (!t.model) throw std::invalid_argument("calibrate: " + label + " has no surrogate model");
    if (!std::isfinite(t.measured))
      throw std::invalid_argument("calibrate: " + label + ": measured value is not finite");
    if (!(t.sigma_measured > 0.0) || !std::isfinite(t.sigma_measured))
      throw std::invalid_argument("calibrate: " + label + ": sigma_measured must be > 0, got " +
                                  number(t.sigma_measured));
    if (!(t.sigma_dem >= 0.0) || !std::isfinite(t.sigma_dem))
      throw std::invalid_argument("calibrate: " + label + ": sigma_dem must be >= 0, got " +
                                  number(t.sigma_dem));
    if (t.model->input_dimension() != parameters_.size())
      throw std::invalid_argument("calibrate: " + label + ": its model has " +
                                  std::to_string(t.model->input_dimension()) + " inputs but " +
                                  std::to_string(parameters_.size()) + " parameters are calibrated");
    // Same names in another order would silently swap mu_r and mu_s; other names (e.g.
    // "x0", "x1" of an unnamed fit) are taken in the parameters' order.
    const std::vector<std::string>& inputs = t.model->input_names();
    if (inputs.size() == names.size() && inputs != names) {
      std::vector<std::string> sorted_inputs = inputs;
      std::sort(sorted_inputs.begin(), sorted_inputs.end());
      if (sorted_inputs == sorted_names)
        throw std::invalid_argument("calibrate: " + label +
                                    ": its model takes the parameters in another order (input " +
                                    quoted(inputs.front()) + " first, parameter " +
                                    quoted(names.front()) + " first)");
    }
  }
}

std::string CalibrationProblem::target_label(std::size_t i) const {
  const Target& t = targets_.at(i);
  return "target " + std::to_string(i) + " (" + t.setup + " " + t.observable + ")";
}

Eigen::VectorXd CalibrationProblem::lower() const {
  Eigen::VectorXd v(parameter_count());
  for (Eigen::Index j = 0; j < v.size(); ++j) v(j) = parameters_[static_cast<std::size_t>(j)].lower;
  return v;
}

Eigen::VectorXd CalibrationProblem::upper() const {
  Eigen::VectorXd v(parameter_count());
  for (Eigen::Index j = 0; j < v.size(); ++j) v(j) = parameters_[static_cast<std::size_t>(j)].upper;
  return v;
}

Eigen::VectorXd CalibrationProblem::range() const { return upper() - lower(); }

Eigen::VectorXd CalibrationProblem::to_unit(const Eigen::VectorXd& theta) const {
  return (theta - lower()).cwiseQuotient(range());
}

Eigen::VectorXd CalibrationProblem::from_unit(const Eigen::VectorXd& u) const {
  return lower() + u.cwiseProduct(range());
}

bool CalibrationProblem::inside_bounds(const Eigen::VectorXd& theta) const {
  if (theta.size() != parameter_count()) return false;
  for (Eigen::Index j = 0; j < theta.size(); ++j) {
    const ParameterBounds& b = parameters_[static_cast<std::size_t>(j)];
    if (!(theta(j) >= b.lower && theta(j) <= b.upper)) return false;
  }
  return true;
}

TargetPredictions CalibrationProblem::evaluate(const Eigen::MatrixXd& points) const {
  if (points.cols() != parameter_count())
    throw std::invalid_argument("calibrate: points have " + std::to_string(points.cols()) +
                                " columns but " + std::to_string(parameter_count()) +
                                " parameters are calibrated");
  const Eigen::Index m = points.rows();
  const Eigen::Index n = target_count();
  TargetPredictions out;
  out.mean.resize(m, n);
  out.sigma_total.resize(m, n);
  out.residual.resize(m, n);
  out.log_variance_sum = Eigen::VectorXd::Zero(m);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Target& t = targets_[static_cast<std::size_t>(i)];
    Eigen::VectorXd variance = Eigen::VectorXd::Constant(
        m, t.sigma_measured * t.sigma_measured + t.sigma_dem * t.sigma_dem);
    if (t.include_surrogate_variance) {
      const surrogate::Prediction pred = t.model->predict(points);
      check_prediction(target_label(static_cast<std::size_t>(i)), pred, m);
      out.mean.col(i) = pred.mean;
      // A surrogate may return a tiny negative variance from rounding.
      variance += pred.variance.cwiseMax(0.0);
    } else {
      const Eigen::VectorXd mean = t.model->predict_mean(points);
      if (mean.size() != m)
        throw std::runtime_error("calibrate: the model of " + target_label(static_cast<std::size_t>(i)) +
                                 " returned " + std::to_string(mean.size()) + " means for " +
                                 std::to_string(m) + " points");
      out.mean.col(i) = mean;
    }
    out.sigma_total.col(i) = variance.cwiseSqrt();
    out.residual.col(i) =
        (Eigen::VectorXd::Constant(m, t.measured) - out.mean.col(i)).cwiseQuotient(out.sigma_total.col(i));
    out.log_variance_sum += variance.array().log().matrix();
  }
  out.chi_squared = out.residual.rowwise().squaredNorm();
  return out;
}

double CalibrationProblem::chi_squared(const Eigen::VectorXd& theta) const {
  return evaluate(theta.transpose()).chi_squared(0);
}

double CalibrationProblem::log_posterior(const Eigen::VectorXd& theta) const {
  if (!inside_bounds(theta)) return -std::numeric_limits<double>::infinity();
  const TargetPredictions pred = evaluate(theta.transpose());
  const double lp = -0.5 * pred.chi_squared(0) - 0.5 * pred.log_variance_sum(0);
  return std::isfinite(lp) ? lp : -std::numeric_limits<double>::infinity();
}

Eigen::VectorXd CalibrationProblem::residuals(const Eigen::VectorXd& theta,
                                              Eigen::MatrixXd* jacobian) const {
  const Eigen::Index p = parameter_count();
  const Eigen::Index n = target_count();
  if (theta.size() != p)
    throw std::invalid_argument("calibrate: theta has " + std::to_string(theta.size()) +
                                " values but " + std::to_string(p) + " parameters are calibrated");
  Eigen::VectorXd r(n);
  if (jacobian) jacobian->resize(n, p);
  const Eigen::MatrixXd point = theta.transpose();
  const Eigen::VectorXd step = kVarianceStep * range();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Target& t = targets_[static_cast<std::size_t>(i)];
    const std::string label = target_label(static_cast<std::size_t>(i));
    double mean = 0.0;
    double model_variance = 0.0;
    Eigen::RowVectorXd d_variance = Eigen::RowVectorXd::Zero(p);
    if (t.include_surrogate_variance) {
      // The centre and its 2p neighbours in one predict() call.
      Eigen::MatrixXd points = jacobian ? point.replicate(2 * p + 1, 1) : point;
      if (jacobian)
        for (Eigen::Index j = 0; j < p; ++j) {
          points(1 + 2 * j, j) += step(j);
          points(2 + 2 * j, j) -= step(j);
        }
      const surrogate::Prediction pred = t.model->predict(points);
      check_prediction(label, pred, points.rows());
      mean = pred.mean(0);
      model_variance = std::max(pred.variance(0), 0.0);
      if (jacobian)
        for (Eigen::Index j = 0; j < p; ++j)
          d_variance(j) = (std::max(pred.variance(1 + 2 * j), 0.0) -
                           std::max(pred.variance(2 + 2 * j), 0.0)) /
                          (2.0 * step(j));
    } else {
      const Eigen::VectorXd m = t.model->predict_mean(point);
      if (m.size() != 1) throw std::runtime_error("calibrate: the model of " + label + " returned no mean");
      mean = m(0);
    }
    const double s2 =
        t.sigma_measured * t.sigma_measured + t.sigma_dem * t.sigma_dem + model_variance;
    const double s = std::sqrt(s2);
    r(i) = (t.measured - mean) / s;
    if (jacobian) {
      const Eigen::MatrixXd g = t.model->gradient(point);
      if (g.rows() != 1 || g.cols() != p)
        throw std::runtime_error("calibrate: the model of " + label + " returned a " +
                                 std::to_string(g.rows()) + " x " + std::to_string(g.cols()) +
                                 " gradient for one point of " + std::to_string(p) + " inputs");
      // r = (y - m) / s, s = sqrt(s2): dr = -dm / s - r ds / s, with ds = d(s2) / (2 s).
      jacobian->row(i) = -g.row(0) / s - r(i) * d_variance / (2.0 * s2);
    }
  }
  return r;
}

std::unique_ptr<ceres::CostFunction> CalibrationProblem::make_cost_function() const {
  return std::make_unique<CalibrationCost>(*this);
}

Minimum minimize_from(const CalibrationProblem& problem, const Eigen::VectorXd& start,
                      const CalibrationOptions& options) {
  validate(options);
  if (!problem.inside_bounds(start))
    throw std::invalid_argument("calibrate: the start point is outside the bounds or has " +
                                std::to_string(start.size()) + " values for " +
                                std::to_string(problem.parameter_count()) + " parameters");
  const LocalSolve s = solve_local(problem, problem.to_unit(start), options);
  if (!s.usable)
    throw std::runtime_error("calibrate: the local solve failed: " +
                             (s.error.empty() ? s.report : s.error));
  Minimum m = make_minimum(problem, s.u, options);
  m.starts = 1;
  m.solver_report = s.report;
  return m;
}

std::vector<Minimum> find_minima(const CalibrationProblem& problem,
                                 const CalibrationOptions& options) {
  validate(options);
  const Eigen::Index p = problem.parameter_count();
  std::vector<LocalSolve> solves;
  std::string first_error;
  for (const Eigen::VectorXd& u0 : unit_starts(p, options)) {
    LocalSolve s = solve_local(problem, u0, options);
    if (s.usable)
      solves.push_back(std::move(s));
    else if (first_error.empty())
      first_error = s.error.empty() ? s.report : s.error;
  }
  if (solves.empty())
    throw std::runtime_error("calibrate: no local solve succeeded: " + first_error);
  std::stable_sort(solves.begin(), solves.end(), [](const LocalSolve& a, const LocalSolve& b) {
    return a.chi_squared < b.chi_squared;
  });

  const std::size_t k = solves.size();
  Clusters clusters(k);
  std::vector<std::pair<std::size_t, std::size_t>> far_pairs;
  for (std::size_t a = 0; a < k; ++a)
    for (std::size_t b = a + 1; b < k; ++b) {
      if ((solves[a].u - solves[b].u).norm() < options.distinct_minimum_tolerance)
        clusters.unite(a, b);
      else
        far_pairs.emplace_back(a, b);
    }
  // Segments go to the models in batches (a GP predicts thousands of points at once far
  // faster than one at a time), skipping pairs an earlier batch already joined.
  for (std::size_t next = 0; next < far_pairs.size();) {
    std::vector<std::pair<std::size_t, std::size_t>> batch;
    for (; next < far_pairs.size() && batch.size() < kPairsPerBatch; ++next)
      if (clusters.root(far_pairs[next].first) != clusters.root(far_pairs[next].second))
        batch.push_back(far_pairs[next]);
    if (batch.empty()) continue;
    Eigen::MatrixXd points(static_cast<Eigen::Index>(batch.size()) * kBarrierPoints, p);
    for (std::size_t q = 0; q < batch.size(); ++q) {
      const Eigen::VectorXd& ua = solves[batch[q].first].u;
      const Eigen::VectorXd& ub = solves[batch[q].second].u;
      for (int s = 0; s < kBarrierPoints; ++s) {
        const double f = (s + 1.0) / (kBarrierPoints + 1.0);
        points.row(static_cast<Eigen::Index>(q) * kBarrierPoints + s) =
            problem.from_unit(ua + f * (ub - ua)).transpose();
      }
    }
    const Eigen::VectorXd chi2 = problem.evaluate(points).chi_squared;
    for (std::size_t q = 0; q < batch.size(); ++q) {
      const auto [a, b] = batch[q];
      const double top = chi2.segment(static_cast<Eigen::Index>(q) * kBarrierPoints, kBarrierPoints).maxCoeff();
      if (top <= std::max(solves[a].chi_squared, solves[b].chi_squared) + options.distinct_minimum_barrier)
        clusters.unite(a, b);
    }
  }

  // Solves are sorted, so each cluster's first member is its best point.
  std::vector<Minimum> minima;
  std::vector<std::size_t> roots;
  for (std::size_t a = 0; a < k; ++a) {
    const std::size_t r = clusters.root(a);
    const auto it = std::find(roots.begin(), roots.end(), r);
    if (it == roots.end()) {
      roots.push_back(r);
      Minimum m = make_minimum(problem, solves[a].u, options);
      m.starts = 1;
      m.solver_report = solves[a].report;
      minima.push_back(std::move(m));
    } else {
      ++minima[static_cast<std::size_t>(it - roots.begin())].starts;
    }
  }
  std::stable_sort(minima.begin(), minima.end(), [](const Minimum& a, const Minimum& b) {
    return a.chi_squared < b.chi_squared;
  });
  return minima;
}

}  // namespace demcal::calibrate
