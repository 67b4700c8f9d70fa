#include "calibrate/adaptive_design.hpp"

#include "calibrate/detail/number_text.hpp"
#include "calibrate/region_components.hpp"
#include "calibrate/weighted_variance_acquisition.hpp"
#include "surrogate/latin_hypercube_design.hpp"

#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace demcal::calibrate {
namespace {

using detail::fmt;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// A run's theta matches the design's choice within this fraction of each range: a run store
// that printed theta with 10 or more significant digits still resumes. The fits use the
// design's own theta, so a resumed design is bit-identical to an uninterrupted one.
constexpr double kThetaMatch = 1e-9;

bool same_value(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

bool same_results(const std::vector<RunResult>& a, const std::vector<RunResult>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t r = 0; r < a.size(); ++r) {
    if (a[r].request.batch != b[r].request.batch || a[r].request.slot != b[r].request.slot ||
        a[r].observables.size() != b[r].observables.size())
      return false;
    for (std::size_t i = 0; i < a[r].observables.size(); ++i)
      if (!same_value(a[r].observables[i], b[r].observables[i])) return false;
  }
  return true;
}

std::string point_text(const std::vector<ParameterBounds>& parameters,
                       const Eigen::VectorXd& theta) {
  std::string s;
  for (std::size_t j = 0; j < parameters.size(); ++j)
    s += (j ? ", " : "") + parameters[j].name + " = " + fmt(theta(static_cast<Eigen::Index>(j)), 3);
  return s;
}

// AdaptiveDesignOptions::space_filling_batch: greedy maximin over the nodes carrying 95 % of
// the weights (they come by decreasing weight). Ties go to the heavier node. Value: NaN (no
// acquisition was maximized; the stopping rule values the batch by batch_variance_drop).
std::vector<AcquisitionChoice> fill_high_posterior_set(const CalibrationProblem& problem,
                                                       const PosteriorWeights& weights,
                                                       const Eigen::MatrixXd& design_points,
                                                       int count, double min_separation) {
  constexpr double kHighPosteriorMass = 0.95;
  std::vector<Eigen::VectorXd> set;
  double mass = 0.0;
  for (Eigen::Index g = 0; g < weights.points.rows() && mass < kHighPosteriorMass; ++g) {
    set.push_back(weights.points.row(g).transpose());
    mass += weights.weights(g);
  }
  std::vector<Eigen::VectorXd> taken;
  for (Eigen::Index r = 0; r < design_points.rows(); ++r)
    taken.push_back(problem.to_unit(design_points.row(r).transpose()));
  std::vector<AcquisitionChoice> chosen;
  for (int slot = 0; slot < count; ++slot) {
    double best_distance = -1.0;
    std::size_t best = set.size();
    for (std::size_t c = 0; c < set.size(); ++c) {
      const Eigen::VectorXd u = problem.to_unit(set[c]);
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& t : taken) nearest = std::min(nearest, (u - t).norm());
      if (nearest > best_distance) best_distance = nearest, best = c;
    }
    // As choose_batch: runs do not pile into one spot.
    if (best == set.size() || best_distance < min_separation) break;
    chosen.push_back({set[best], kNaN});
    taken.push_back(problem.to_unit(set[best]));
  }
  return chosen;
}

}  // namespace

struct AdaptiveDesign::Stage {
  std::vector<RunResult> inputs;  // runs of batches 0..batch, design order, design's theta
  RunsCalibration calibration;
  AdaptiveBatchRecord record;
  int stable_streak = 0;     // consecutive stable batches ending here
  int too_large_streak = 0;  // consecutive batches whose chi^2 failed the range test
  AdaptiveDesignStatus status = AdaptiveDesignStatus::running;
  std::string statement;
  std::vector<RunRequest> next;  // the next batch, when running
  // This batch's posterior weights as the acquisition tempers them (before any averaging):
  // the next batch averages with them when options.acquisition_weight_batches == 2.
  PosteriorWeights acquisition_weights;
};

AdaptiveDesign::AdaptiveDesign(AdaptiveDesignProblem problem, AdaptiveDesignOptions options)
    : problem_(std::move(problem)), options_(std::move(options)) {
  std::string error;
  if (!options_.Validate(&error)) throw std::invalid_argument(error);
  // The design shrinks the likelihood-ratio region, which the calibration grids for 1 to 3
  // parameters only.
  if (problem_.parameters.empty() || problem_.parameters.size() > 3)
    throw std::invalid_argument(
        "adaptive design: needs 1 to 3 parameters (the 95 % region is "
        "computed on a grid), got " +
        std::to_string(problem_.parameters.size()));
  for (const auto& b : problem_.parameters)
    if (!std::isfinite(b.lower) || !std::isfinite(b.upper) || !(b.upper > b.lower))
      throw std::invalid_argument("adaptive design: parameter '" + b.name +
                                  "' needs finite bounds with lower < upper");
  // A linear-mean GP needs p + 1 points for its mean and one more to have any residual.
  if (options_.initial_points < static_cast<int>(problem_.parameters.size()) + 2)
    throw std::invalid_argument("adaptive design: initial_points must be >= parameters + 2 = " +
                                std::to_string(problem_.parameters.size() + 2) + ", got " +
                                std::to_string(options_.initial_points));
  if (problem_.recordings.empty()) throw std::invalid_argument("adaptive design: no recordings");
  for (std::size_t i = 0; i < problem_.recordings.size(); ++i) {
    const auto& r = problem_.recordings[i];
    if (!std::isfinite(r.value) || !(r.sigma > 0.0) || !std::isfinite(r.sigma))
      throw std::invalid_argument("adaptive design: recording " + std::to_string(i + 1) + " (" +
                                  r.setup + " " + r.observable +
                                  ") needs a finite value and a finite sigma > 0");
  }
}

const RunsCalibration* AdaptiveDesign::latest_calibration() const {
  return latest_ ? &latest_->calibration : nullptr;
}

std::vector<RunRequest> AdaptiveDesign::start_batch() const {
  std::vector<surrogate::ParameterRange> ranges;
  for (const auto& b : problem_.parameters) ranges.push_back({b.name, b.lower, b.upper, 2});
  surrogate::LatinHypercubeOptions lo;
  lo.points = static_cast<std::size_t>(options_.initial_points);
  lo.seed = options_.seed;
  const auto unit = surrogate::latin_hypercube_unit(ranges.size(), lo);
  const auto points = surrogate::scale_to_ranges(unit, ranges);
  std::vector<RunRequest> batch;
  for (std::size_t k = 0; k < points.size(); ++k)
    batch.push_back({0, k, points[k], 0, run_seed(options_.seed, 0, k),
                     "space-filling start (maximin Latin hypercube)", kNaN});
  // Replicates at the points nearest the centre: the scatter is measured away from the
  // bounds, where a DEM's behaviour is most typical of the box.
  std::vector<std::pair<double, std::size_t>> by_distance;
  for (std::size_t k = 0; k < unit.size(); ++k) {
    double d2 = 0.0;
    for (double u : unit[k]) d2 += (u - 0.5) * (u - 0.5);
    by_distance.emplace_back(d2, k);
  }
  std::stable_sort(by_distance.begin(), by_distance.end());
  for (int r = 0; r < options_.initial_replicated_points; ++r) {
    const std::size_t k = by_distance[static_cast<std::size_t>(r)].second;
    const std::size_t slot = batch.size();
    batch.push_back({0, slot, points[k], 1, run_seed(options_.seed, 0, slot),
                     "replicate in the start (measures the scatter)", kNaN});
  }
  return batch;
}

AdaptiveDesign::Stage AdaptiveDesign::analyse(std::size_t batch,
                                              const std::vector<RunResult>& runs_so_far,
                                              const std::vector<RunRequest>& this_batch) const {
  const Stage* previous = batch > 0 ? stages_[batch - 1].get() : nullptr;
  Stage st;
  st.inputs = runs_so_far;
  st.calibration = calibrate_runs(problem_.parameters, problem_.recordings, runs_so_far,
                                  options_.surrogate, options_.calibration);
  const CalibrationResult& cal = st.calibration.result;
  if (cal.minima.empty())
    throw std::runtime_error("adaptive design: the calibration found no minimum");
  const Minimum& best = cal.minima.front();
  const CalibrationProblem problem(problem_.parameters, st.calibration.targets);
  const PosteriorWeights weights = posterior_weights(problem, options_);

  AdaptiveBatchRecord& rec = st.record;
  rec.index = batch;
  rec.runs = this_batch;
  rec.complete = true;
  rec.runs_total = runs_so_far.size();
  rec.region_area = cal.region.area;
  rec.region_resolved = cal.region.resolved;
  rec.best_point.assign(best.theta.data(), best.theta.data() + best.theta.size());
  rec.best_chi_squared = best.chi_squared;
  rec.surrogate_variance_ratio = weighted_surrogate_variance(problem, weights);
  rec.scatter_degrees_of_freedom = std::numeric_limits<int>::max();
  for (const auto& f : st.calibration.surrogates)
    rec.scatter_degrees_of_freedom =
        std::min(rec.scatter_degrees_of_freedom, f.scatter.degrees_of_freedom);
  rec.posterior_mean.assign(problem_.parameters.size(), 0.0);
  for (Eigen::Index g = 0; g < weights.points.rows(); ++g)
    for (std::size_t j = 0; j < problem_.parameters.size(); ++j)
      rec.posterior_mean[j] +=
          weights.weights(g) * weights.points(g, static_cast<Eigen::Index>(j));
  // The next batch, planned in full before the stopping test: its acquisition values are
  // what another batch is expected to gain. Cut to the budget below (the kriging believer is
  // greedy, so a cut batch is the prefix of the full one).
  const std::size_t next = batch + 1;
  const int count = options_.batch_size;
  // Distinct design points in order of first appearance, and runs at each.
  std::vector<std::vector<double>> points;
  std::map<std::vector<double>, int> runs_at;
  for (const auto& r : runs_so_far)
    if (runs_at[r.request.theta]++ == 0) points.push_back(r.request.theta);
  if (rec.scatter_degrees_of_freedom < options_.scatter_degrees_of_freedom) {
    // Each replicate adds one degree of freedom; they go to the design points nearest the
    // calibrated point, where they also firm up the surrogates most usefully.
    const int wanted =
        std::min({options_.replicates_per_batch, count,
                  options_.scatter_degrees_of_freedom - rec.scatter_degrees_of_freedom});
    const Eigen::VectorXd u_best = problem.to_unit(best.theta);
    std::vector<std::pair<double, std::size_t>> by_distance;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const Eigen::VectorXd u = problem.to_unit(Eigen::Map<const Eigen::VectorXd>(
          points[k].data(), static_cast<Eigen::Index>(points[k].size())));
      by_distance.emplace_back((u - u_best).norm(), k);
    }
    std::stable_sort(by_distance.begin(), by_distance.end());
    for (int r = 0; r < wanted && r < static_cast<int>(by_distance.size()); ++r) {
      const auto& theta = points[by_distance[static_cast<std::size_t>(r)].second];
      const std::size_t slot = st.next.size();
      st.next.push_back({next, slot, theta, runs_at[theta], run_seed(options_.seed, next, slot),
                         "replicate near the calibrated point (the scatter has " +
                             std::to_string(rec.scatter_degrees_of_freedom) + " < " +
                             std::to_string(options_.scatter_degrees_of_freedom) +
                             " degrees of freedom)",
                         kNaN});
    }
  }
  Eigen::MatrixXd design(static_cast<Eigen::Index>(points.size()),
                         static_cast<Eigen::Index>(problem_.parameters.size()));
  for (std::size_t k = 0; k < points.size(); ++k)
    for (std::size_t j = 0; j < points[k].size(); ++j)
      design(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(j)) = points[k][j];
  // A part of the 95 % region that holds no design point exists only through the
  // surrogates' variance between runs (region_components.hpp): the calibration report asks
  // the user to run there. With confirm_region_parts the design does it itself: one run at
  // each such part's most probable node confirms the part (the run agrees with the
  // recordings) or removes it, and the region is not stable while such a part is left.
  struct ConfirmingRun {
    Eigen::VectorXd theta;  // the part's most probable node
    std::string where;      // the part's extent, for the run's reason
  };
  std::vector<ConfirmingRun> confirming;
  if (options_.confirm_region_parts && cal.region.available) {
    const RegionComponents parts =
        region_components(cal.region.axes, cal.region.inside, best.theta, design);
    for (std::size_t k = 0; k < parts.parts.size(); ++k) {
      const RegionComponent& part = parts.parts[k];
      if (!part.between_design_points) continue;
      ++rec.unconfirmed_parts;
      std::size_t node = parts.label.size();
      for (std::size_t g = 0; g < parts.label.size(); ++g)
        if (parts.label[g] == static_cast<int>(k) &&
            (node == parts.label.size() ||
             cal.region.log_posterior[g] > cal.region.log_posterior[node]))
          node = g;
      if (node == parts.label.size()) continue;
      // The region's layout: the first axis runs fastest.
      Eigen::VectorXd theta(static_cast<Eigen::Index>(cal.region.axes.size()));
      std::size_t rest = node;
      for (std::size_t j = 0; j < cal.region.axes.size(); ++j) {
        theta(static_cast<Eigen::Index>(j)) = cal.region.axes[j][rest % cal.region.axes[j].size()];
        rest /= cal.region.axes[j].size();
      }
      std::string where;
      for (std::size_t j = 0; j < problem_.parameters.size(); ++j)
        where += (j ? ", " : "") + problem_.parameters[j].name + " " + fmt(part.lower[j], 3) + "-" +
                 fmt(part.upper[j], 3);
      confirming.push_back({theta, where});
    }
  }
  for (const ConfirmingRun& c : confirming) {
    if (static_cast<int>(st.next.size()) >= count) break;
    const std::size_t slot = st.next.size();
    st.next.push_back(
        {next, slot, std::vector<double>(c.theta.data(), c.theta.data() + c.theta.size()), 0,
         run_seed(options_.seed, next, slot),
         "confirms or removes a part of the 95 % region that holds no design point (" + c.where +
             "), at its most probable node",
         kNaN});
    design.conservativeResize(design.rows() + 1, Eigen::NoChange);
    design.row(design.rows() - 1) = c.theta.transpose();
  }
  const std::size_t fixed_runs = st.next.size();
  std::vector<double> noise;
  for (const auto& f : st.calibration.surrogates)
    noise.push_back(std::isfinite(f.scatter.sd) ? f.scatter.sd * f.scatter.sd : 0.0);
  // The acquisition's weights: the posterior, or (the swing-damping options) tempered and/or
  // averaged with the previous batch's.
  const bool tempered = options_.acquisition_tempering != 1.0;
  st.acquisition_weights =
      tempered ? posterior_weights(problem, options_, options_.acquisition_tempering) : weights;
  const bool averaged = options_.acquisition_weight_batches == 2 && previous != nullptr;
  const PosteriorWeights acquisition =
      averaged ? average_weights(st.acquisition_weights, previous->acquisition_weights)
               : st.acquisition_weights;
  const int wanted_new = count - static_cast<int>(st.next.size());
  const auto choices = options_.space_filling_batch
                           ? fill_high_posterior_set(problem, acquisition, design, wanted_new,
                                                     options_.min_separation)
                           : choose_batch(problem, acquisition, noise, design, wanted_new, options_);
  for (std::size_t c = 0; c < choices.size(); ++c) {
    const std::size_t slot = st.next.size();
    st.next.push_back({next, slot,
                       std::vector<double>(choices[c].theta.data(),
                                           choices[c].theta.data() + choices[c].theta.size()),
                       0, run_seed(options_.seed, next, slot),
                       options_.space_filling_batch
                           ? "space-filling in the 95 % high-posterior set (farthest from the "
                             "runs, choice " + std::to_string(c + 1) + " of the batch)"
                           : "largest posterior-weighted variance reduction (kriging believer, "
                             "choice " + std::to_string(c + 1) + " of the batch)",
                       choices[c].value});
  }
  // Expected gain: the chosen runs' acquisition values sum to the expected drop of
  // sum_i (posterior-weighted V_i) / s_i^2; per target on average, over the total 1 + r,
  // that is the expected relative drop d of the variance the region is computed with, and
  // the region's volume (p parameters) scales as variance^(p/2).
  double believed_drop = 0.0;
  // The batch's new points: the confirming runs (a replicate adds no new point) and the choices.
  std::vector<Eigen::VectorXd> new_points;
  for (std::size_t r = 0; r < fixed_runs; ++r)
    if (st.next[r].replicate == 0)
      new_points.push_back(Eigen::Map<const Eigen::VectorXd>(
          st.next[r].theta.data(), static_cast<Eigen::Index>(st.next[r].theta.size())));
  if (tempered || averaged || options_.space_filling_batch || !new_points.empty()) {
    // Chosen under other weights, or partly by the confirming rule: valued as a whole under
    // this batch's posterior, as the rule means.
    for (const auto& c : choices) new_points.push_back(c.theta);
    Eigen::MatrixXd chosen(static_cast<Eigen::Index>(new_points.size()),
                           static_cast<Eigen::Index>(problem_.parameters.size()));
    for (std::size_t c = 0; c < new_points.size(); ++c)
      chosen.row(static_cast<Eigen::Index>(c)) = new_points[c].transpose();
    believed_drop = batch_variance_drop(problem, weights, noise, chosen);
  } else {
    for (const auto& c : choices) believed_drop += c.value;
  }
  const double d = std::clamp(believed_drop / static_cast<double>(problem_.recordings.size()) /
                                  (1.0 + rec.surrogate_variance_ratio),
                              0.0, 1.0);
  rec.expected_area_gain =
      1.0 - std::pow(1.0 - d, 0.5 * static_cast<double>(problem_.parameters.size()));
  rec.area_change = kNaN;
  rec.point_move = kNaN;
  if (previous) {
    const auto& prev = previous->record;
    rec.area_change = prev.region_area > 0.0
                          ? std::abs(rec.region_area - prev.region_area) / prev.region_area
                          : std::numeric_limits<double>::infinity();
    // The move as a fraction of the region's extent: "stable" means the point moves less
    // than the data leave it free to move. A region narrower than a grid cell counts as one
    // cell wide. The point is the posterior mean, not minima[0]: along an iso-line of one
    // observable two near-equal minima trade places from batch to batch (the argmin jumps
    // across the region) while the posterior they sit in does not move.
    double move = 0.0;
    for (std::size_t j = 0; j < problem_.parameters.size(); ++j) {
      const auto& b = problem_.parameters[j];
      const int nodes = problem_.parameters.size() == 3
                            ? options_.calibration.grid_points_per_axis_3d
                            : options_.calibration.grid_points_per_axis;
      const double cell = (b.upper - b.lower) / (nodes - 1);
      const auto& e = cal.region.extent.at(j);
      const double width =
          std::isfinite(e.upper - e.lower) ? std::max(e.upper - e.lower, cell) : cell;
      move = std::max(move, std::abs(rec.posterior_mean[j] - prev.posterior_mean[j]) / width);
    }
    rec.point_move = move;
    // The region is computed with each target's total variance, noise x (1 + r) on average
    // (calibration_problem.hpp): the surrogates' share is already in its size. The rule asks
    // either that the share is small (r <= surrogate_variance_tolerance) or that another
    // batch is not expected to shrink the region by more than the area may change
    // (expected_area_gain <= area_tolerance). A fixed fraction of the noise alone cannot be
    // met when the recordings are means of many tests: their noise is the scatter /
    // sqrt(repeats), the surrogate's floor near the region the scatter / sqrt(runs nearby)
    // (on the lined recovery study even the 100-run grid has r = 1.2 to 1.5).
    const bool surrogate_done = rec.surrogate_variance_ratio <= options_.surrogate_variance_tolerance ||
                                rec.expected_area_gain <= options_.area_tolerance;
    // The region's size rests on sigma_dem, the replicate scatter: not stable before the
    // scatter has the degrees of freedom the options ask for.
    const bool scatter_measured =
        rec.scatter_degrees_of_freedom >= options_.scatter_degrees_of_freedom;
    rec.stable = rec.area_change <= options_.area_tolerance &&
                 rec.point_move <= options_.point_tolerance && surrogate_done && scatter_measured &&
                 rec.region_resolved && rec.unconfirmed_parts == 0;
  }
  // chi^2 at the truth is chi^2(targets) when the model can reproduce the recordings, and
  // the best chi^2 is no larger: a best chi^2 above the 1 - alpha quantile happens with
  // probability <= alpha for recordings inside the model's range.
  const auto n_targets = static_cast<double>(problem_.recordings.size());
  const double chi2_limit = gsl_cdf_chisq_Qinv(options_.out_of_range_alpha, n_targets);
  rec.chi_squared_too_large = best.chi_squared > chi2_limit;
  st.stable_streak = rec.stable ? (previous ? previous->stable_streak : 0) + 1 : 0;
  st.too_large_streak =
      rec.chi_squared_too_large ? (previous ? previous->too_large_streak : 0) + 1 : 0;

  const std::string after =
      "after batch " + std::to_string(batch) + " (" + std::to_string(rec.runs_total) + " runs)";
  if (st.too_large_streak >= options_.out_of_range_batches) {
    st.status = AdaptiveDesignStatus::out_of_range;
    st.next.clear();
    // Where the best point sits says which way the recordings leave the model's range.
    std::string where;
    for (std::size_t j = 0; j < problem_.parameters.size(); ++j) {
      const auto& b = problem_.parameters[j];
      const double u = (best.theta(static_cast<Eigen::Index>(j)) - b.lower) / (b.upper - b.lower);
      if (u < 1e-3 || u > 1.0 - 1e-3)
        where += (where.empty() ? "" : ", ") + b.name + " at its " + (u < 0.5 ? "lower" : "upper") +
                 " bound";
    }
    st.statement =
        "the recordings are out of the model's range: " + after + ", the best point (" +
        point_text(problem_.parameters, best.theta) + (where.empty() ? "" : "; " + where) +
        ") has chi^2 = " + fmt(best.chi_squared, 3) + " > " + fmt(chi2_limit, 3) + ", the " +
        fmt(1.0 - options_.out_of_range_alpha, 4) + " quantile of chi^2(" +
        std::to_string(problem_.recordings.size()) + ") that the truth would pass, in " +
        std::to_string(st.too_large_streak) + " consecutive batches; no more runs are spent";
    return st;
  }
  if (st.stable_streak >= options_.stable_batches) {
    st.status = AdaptiveDesignStatus::converged;
    st.next.clear();
    st.statement = "converged " + after + ": over " + std::to_string(st.stable_streak) +
                   " consecutive batches the 95 % region's area changed by <= " +
                   fmt(100.0 * options_.area_tolerance, 3) +
                   " %, the posterior mean moved by <= " + fmt(100.0 * options_.point_tolerance, 3) +
                   " % of the region's extent (best point " +
                   point_text(problem_.parameters, best.theta) +
                   "), and the surrogates' variance is " +
                   fmt(rec.surrogate_variance_ratio, 2) +
                   " of the noise variance (another batch is expected to shrink the area by " +
                   fmt(100.0 * rec.expected_area_gain, 2) + " %); region area " +
                   fmt(rec.region_area, 4);
    return st;
  }
  const int runs_left = options_.max_runs - static_cast<int>(rec.runs_total);
  if (runs_left <= 0 || static_cast<int>(batch) >= options_.max_batches) {
    st.status = AdaptiveDesignStatus::budget_exhausted;
    st.next.clear();
    st.statement = "the budget (" +
                   (runs_left <= 0 ? "max_runs = " + std::to_string(options_.max_runs)
                                   : "max_batches = " + std::to_string(options_.max_batches)) +
                   ") is spent " + after + " before the region was stable; last area change " +
                   fmt(rec.area_change, 2) + ", region area " + fmt(rec.region_area, 4);
    return st;
  }

  st.next.resize(std::min(st.next.size(), static_cast<std::size_t>(runs_left)));
  if (st.next.empty()) {
    st.status = AdaptiveDesignStatus::no_candidates;
    st.statement = "no candidate point is min_separation = " + fmt(options_.min_separation, 3) +
                   " (bound-scaled) away from the runs " + after +
                   "; the region cannot be refined further at this separation";
    return st;
  }
  st.statement = after + ": region area " + fmt(rec.region_area, 4) + ", next batch " +
                 std::to_string(next) + " with " + std::to_string(st.next.size()) + " runs";
  return st;
}

const AdaptiveDesign::Stage& AdaptiveDesign::stage(std::size_t batch,
                                                   const std::vector<RunResult>& runs_so_far,
                                                   const std::vector<RunRequest>& this_batch) {
  if (stages_.size() > batch && same_results(stages_[batch]->inputs, runs_so_far))
    return *stages_[batch];
  stages_.resize(batch);  // later stages were computed from other runs
  stages_.push_back(std::make_shared<const Stage>(analyse(batch, runs_so_far, this_batch)));
  return *stages_.back();
}

std::vector<RunRequest> AdaptiveDesign::next_runs(const std::vector<RunResult>& done_any_order) {
  const std::vector<RunResult> done = runs_in_design_order(done_any_order);
  history_ = AdaptiveDesignHistory{};
  latest_.reset();
  auto label = [](const RunRequest& r) {
    return "run (batch " + std::to_string(r.batch) + ", slot " + std::to_string(r.slot) + ")";
  };
  for (std::size_t r = 1; r < done.size(); ++r)
    if (done[r].request.batch == done[r - 1].request.batch &&
        done[r].request.slot == done[r - 1].request.slot)
      throw std::invalid_argument("adaptive design: " + label(done[r].request) + " is given twice");

  std::vector<RunRequest> plan = start_batch();
  std::vector<RunResult> so_far;
  std::size_t pos = 0;
  for (std::size_t k = 0;; ++k) {
    std::vector<bool> have(plan.size(), false);
    for (; pos < done.size() && done[pos].request.batch == k; ++pos) {
      const RunRequest& got = done[pos].request;
      bool match = got.slot < plan.size() && got.replicate == plan[got.slot].replicate &&
                   got.seed == plan[got.slot].seed &&
                   got.theta.size() == plan[got.slot].theta.size();
      for (std::size_t j = 0; match && j < got.theta.size(); ++j) {
        const auto& b = problem_.parameters.at(j);
        match =
            std::abs(got.theta[j] - plan[got.slot].theta[j]) <= kThetaMatch * (b.upper - b.lower);
      }
      if (!match)
        throw std::invalid_argument("adaptive design: " + label(got) +
                                    " is not the run the design chose there; were the options, "
                                    "the seed, the bounds or the recordings changed?");
      RunResult run = done[pos];
      run.request = plan[got.slot];  // the design's own theta, reason and acquisition
      so_far.push_back(std::move(run));
      have[got.slot] = true;
    }
    const auto missing = std::count(have.begin(), have.end(), false);
    if (missing > 0) {
      if (pos < done.size())
        throw std::invalid_argument("adaptive design: " + label(done[pos].request) +
                                    " belongs to a batch after batch " + std::to_string(k) +
                                    ", which is not complete");
      AdaptiveBatchRecord rec;
      rec.index = k;
      rec.runs = plan;
      history_.batches.push_back(rec);
      history_.status = AdaptiveDesignStatus::running;
      history_.runs_done = so_far.size();
      history_.statement = "batch " + std::to_string(k) + ": " +
                           std::to_string(plan.size() - static_cast<std::size_t>(missing)) +
                           " of " + std::to_string(plan.size()) + " runs done";
      std::vector<RunRequest> out;
      for (std::size_t s = 0; s < plan.size(); ++s)
        if (!have[s]) out.push_back(plan[s]);
      return out;
    }
    const Stage& st = stage(k, so_far, plan);
    latest_ = stages_[k];
    history_.batches.push_back(st.record);
    history_.runs_done = so_far.size();
    history_.status = st.status;
    history_.statement = st.statement;
    if (st.status != AdaptiveDesignStatus::running) {
      if (pos < done.size())
        throw std::invalid_argument("adaptive design: " + label(done[pos].request) +
                                    " comes after the design ended (" + to_string(st.status) + ")");
      return {};
    }
    plan = st.next;
  }
}

AdaptiveDesignResult run_adaptive_design(const AdaptiveDesignProblem& problem,
                                         const AdaptiveDesignOptions& options,
                                         const RunEvaluator& evaluate,
                                         std::vector<RunResult> done) {
  AdaptiveDesign design(problem, options);
  for (auto next = design.next_runs(done); !next.empty(); next = design.next_runs(done)) {
    const auto values = evaluate(next);
    if (values.size() != next.size())
      throw std::runtime_error("adaptive design: the evaluator returned " +
                               std::to_string(values.size()) + " results for " +
                               std::to_string(next.size()) + " runs");
    for (std::size_t r = 0; r < next.size(); ++r) done.push_back({next[r], values[r]});
  }
  AdaptiveDesignResult out;
  out.history = design.history();
  out.runs = runs_in_design_order(std::move(done));
  for (auto& r : out.runs) {
    // Reasons and acquisition values as the design chose them (a resumed run may carry none).
    const auto& b = out.history.batches.at(r.request.batch);
    r.request = b.runs.at(r.request.slot);
  }
  if (const RunsCalibration* c = design.latest_calibration()) out.calibration = *c;
  return out;
}

}  // namespace demcal::calibrate
