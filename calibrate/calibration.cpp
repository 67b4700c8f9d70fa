#include "calibrate/calibration.hpp"

#include "calibrate/detail/number_text.hpp"

#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace demcal::calibrate {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// A parameter with at least this share (bound-scaled) of a rank-deficient direction moves
// along it, so the data do not fix it.
constexpr double kWeakShare = 0.1;
// Effective samples below which posterior summaries are flagged as rough.
constexpr double kFewEffectiveSamples = 200.0;

using detail::fmt;
std::string percent(double confidence) { return fmt(100.0 * confidence, 3) + " %"; }

std::string vector_text(const Eigen::VectorXd& v, int digits = 2) {
  std::string s = "(";
  for (Eigen::Index j = 0; j < v.size(); ++j) {
    if (j) s += ", ";
    s += fmt(v(j), digits);
  }
  return s + ")";
}

std::string names_text(const std::vector<ParameterBounds>& parameters) {
  std::string s = "(";
  for (std::size_t j = 0; j < parameters.size(); ++j) {
    if (j) s += ", ";
    s += parameters[j].name;
  }
  return s + ")";
}

std::string point_text(const std::vector<ParameterBounds>& parameters, const Eigen::VectorXd& theta) {
  std::string s = "(";
  for (std::size_t j = 0; j < parameters.size(); ++j) {
    if (j) s += ", ";
    s += parameters[j].name + " = " + fmt(theta(static_cast<Eigen::Index>(j)), 4);
  }
  return s + ")";
}

std::string target_text(const TargetSummary& t) { return t.setup + " " + t.observable; }

// Share of each parameter in a direction given in parameter units, measured in bound-scaled
// units so that a parameter's units do not decide it.
Eigen::VectorXd scaled_share(const Eigen::VectorXd& direction, const Eigen::VectorXd& range) {
  Eigen::VectorXd v = direction.cwiseQuotient(range);
  const double n = v.norm();
  return n > 0.0 ? Eigen::VectorXd(v.cwiseAbs() / n) : Eigen::VectorXd(Eigen::VectorXd::Zero(v.size()));
}

void add_notes(const CalibrationProblem& problem, CalibrationResult& r) {
  const auto& params = r.parameters;
  const auto p = static_cast<Eigen::Index>(params.size());
  const Minimum& best = r.minima.front();
  const double conf = r.options.confidence;
  const double delta = gsl_cdf_chisq_Pinv(conf, static_cast<double>(p));
  std::vector<std::string>& notes = r.notes;

  // Minima.
  int starts = 0;
  for (const Minimum& m : r.minima) starts += m.starts;
  if (r.minima.size() == 1) {
    notes.push_back("One minimum: chi^2 = " + fmt(best.chi_squared) + " at " +
                    point_text(params, best.theta) + " (all " + std::to_string(starts) +
                    " local solves end there).");
  } else {
    std::string s = std::to_string(r.minima.size()) + " distinct minima:";
    int rivals = 0;
    for (std::size_t k = 0; k < r.minima.size(); ++k) {
      const Minimum& m = r.minima[k];
      s += (k ? "; " : " ") + std::string("chi^2 = ") + fmt(m.chi_squared) + " at " +
           point_text(params, m.theta) + " (" + std::to_string(m.starts) + " of " +
           std::to_string(starts) + " starts)";
      if (k > 0 && m.chi_squared - best.chi_squared <= delta) ++rivals;
    }
    notes.push_back(s + ".");
    if (rivals > 0)
      notes.push_back(std::to_string(rivals) + " other minim" + (rivals == 1 ? "um" : "a") +
                      " lie" + (rivals == 1 ? "s" : "") + " within the " + percent(conf) +
                      " likelihood-ratio threshold of the best: the data cannot choose between them.");
  }
  for (Eigen::Index j = 0; j < p; ++j) {
    const ParameterBounds& b = params[static_cast<std::size_t>(j)];
    const double u = (best.theta(j) - b.lower) / (b.upper - b.lower);
    if (u <= 1e-6 || u >= 1.0 - 1e-6)
      notes.push_back("The best minimum lies on the " + std::string(u <= 1e-6 ? "lower" : "upper") +
                      " bound of " + b.name + " (" + fmt(u <= 1e-6 ? b.lower : b.upper, 4) +
                      "): the data would prefer a value beyond it, and its covariance ignores the bound.");
  }

  // Local identifiability.
  if (best.rank_deficient) {
    const double top = best.singular_values(0);
    Eigen::Index rank = 0;
    for (Eigen::Index k = 0; k < best.singular_values.size(); ++k)
      if (top > 0.0 && best.singular_values(k) >= r.options.rank_condition_threshold * top) ++rank;
    std::string why = r.targets.size() < params.size()
                          ? std::to_string(r.targets.size()) + " target" +
                                (r.targets.size() == 1 ? "" : "s") + " cannot determine " +
                                std::to_string(params.size()) + " parameters"
                          : "the targets' sensitivities are (nearly) parallel";
    notes.push_back("The Jacobian at the best minimum is rank deficient (rank " + std::to_string(rank) +
                    " of " + std::to_string(p) + "): " + why +
                    ". chi^2 hardly changes along the direction " +
                    vector_text(best.weakest_direction) + " in " + names_text(params) +
                    ", so the Gauss-Newton covariance is not available there.");
  } else if (best.covariance_available) {
    std::string s = "Gauss-Newton standard errors at the best minimum:";
    for (Eigen::Index j = 0; j < p; ++j)
      s += (j ? ", " : " ") + params[static_cast<std::size_t>(j)].name + " = " + fmt(best.theta(j), 4) +
           " +/- " + fmt(best.standard_errors[static_cast<std::size_t>(j)], 2);
    notes.push_back(s + ".");
  }

  // Identification per parameter.
  const Eigen::VectorXd share =
      best.rank_deficient ? scaled_share(best.weakest_direction, problem.range()) : Eigen::VectorXd::Zero(p);
  for (Eigen::Index j = 0; j < p; ++j) {
    const auto js = static_cast<std::size_t>(j);
    const std::string& name = params[js].name;
    if (r.region.available && r.region.nodes_inside > 0) {
      const ParameterExtent& e = r.region.extent[js];
      const std::string range_text = "[" + fmt(e.lower, 3) + ", " + fmt(e.upper, 3) + "]";
      std::string along;
      if (r.region.principal_axis.allFinite() && p > 1)
        along = " along the direction " + vector_text(r.region.principal_axis) + " in " + names_text(params);
      if (e.touches_lower_bound && e.touches_upper_bound)
        notes.push_back(name + " is not identified: the " + percent(conf) +
                        " region reaches both of its bounds" + along + ".");
      else if (e.touches_lower_bound || e.touches_upper_bound)
        notes.push_back(name + " is bounded by the data on one side only: the " + percent(conf) +
                        " region " + range_text + " reaches its " +
                        (e.touches_lower_bound ? "lower" : "upper") + " bound.");
      else if (share(j) >= kWeakShare)
        notes.push_back(name + " is not identified by these targets: it moves along the poorly " +
                        "determined direction, and its " + percent(conf) + " region " + range_text +
                        " is cut off by the bounds of the other parameters.");
      else
        notes.push_back(name + " is identified: " + percent(conf) + " region " + range_text + ".");
    } else if (!r.identified[js]) {
      notes.push_back(name + " is not identified: its " + percent(conf) +
                      " posterior interval reaches a bound or it moves along the poorly determined direction.");
    }
  }
  if (r.region.available) {
    double box = 1.0;
    for (const ParameterBounds& b : params) box *= b.upper - b.lower;
    const char* measure = p == 1 ? "length" : (p == 2 ? "area" : "volume");
    notes.push_back("The " + percent(conf) + " likelihood-ratio region has " + measure + " " +
                    fmt(r.region.area) + " (" + fmt(100.0 * r.region.area / box, 3) +
                    " % of the box), chi^2 <= " + fmt(r.region.threshold) + ".");
    if (!r.region.resolved)
      notes.push_back("The region spans fewer than 5 grid nodes along some parameter: its " +
                      std::string(measure) + " and extent are coarse; the standard errors are the better measure.");
  } else {
    notes.push_back("No likelihood-ratio grid above 3 parameters: identification is judged from the posterior.");
  }

  // Goodness of fit.
  if (r.fit.degrees_of_freedom < 1) {
    notes.push_back(std::to_string(r.targets.size()) + " target" + (r.targets.size() == 1 ? "" : "s") +
                    " for " + std::to_string(params.size()) + " parameters leave no degrees of freedom: chi^2 = " +
                    fmt(best.chi_squared) + " cannot test the model (it can match any such data).");
  } else if (r.fit.p_value < 1.0 - conf) {
    notes.push_back("Mismatch: chi^2 = " + fmt(r.fit.chi_square) + " for " +
                    std::to_string(r.fit.degrees_of_freedom) + " degrees of freedom (p = " +
                    fmt(r.fit.p_value, 2) + "): no parameter set reproduces the measurements within " +
                    "their uncertainties; the model may be missing physics.");
  } else {
    notes.push_back("No significant mismatch: chi^2 = " + fmt(r.fit.chi_square) + " for " +
                    std::to_string(r.fit.degrees_of_freedom) + " degrees of freedom (p = " +
                    fmt(r.fit.p_value, 2) + ").");
  }
  for (std::size_t i = 0; i < r.targets.size(); ++i) {
    const TargetSummary& t = r.targets[i];
    if (std::abs(best.residuals[i]) > 2.0)
      notes.push_back(target_text(t) + " is off by " + fmt(best.residuals[i], 2) +
                      " sigma at the best minimum (measured " + fmt(t.measured, 4) + ", predicted " +
                      fmt(best.predicted[i], 4) + ").");
    const double noise2 = t.sigma_measured * t.sigma_measured + t.sigma_dem * t.sigma_dem;
    const double total2 = best.sigma_total[i] * best.sigma_total[i];
    if (t.include_surrogate_variance && total2 - noise2 > noise2)
      notes.push_back("The surrogate's own uncertainty for " + target_text(t) + " (sd " +
                      fmt(std::sqrt(total2 - noise2), 2) + ") exceeds the measurement and DEM scatter (sd " +
                      fmt(std::sqrt(noise2), 2) + ") at the best minimum: more DEM runs near it would tighten the region.");
  }

  // Posterior.
  if (r.posterior.available) {
    const PosteriorSummary& post = r.posterior;
    if (post.acceptance_rate < 0.05 || post.acceptance_rate > 0.8)
      notes.push_back("MCMC acceptance rate " + fmt(post.acceptance_rate, 2) +
                      " is far from the usual 0.1-0.5: the posterior summaries may be rough.");
    for (const MarginalPosterior& m : post.marginals) {
      if (m.r_hat > 1.1)
        notes.push_back("The MCMC chains disagree about " + m.name + " (R-hat " + fmt(m.r_hat, 3) +
                        "): they may sit in different minima, which the pooled samples weigh by chain count.");
      if (m.effective_sample_size < kFewEffectiveSamples)
        notes.push_back("Only " + fmt(m.effective_sample_size, 3) + " effective posterior samples of " +
                        m.name + ": increase mcmc_samples for smoother summaries.");
    }
    if (post.credible_region.available && r.region.available)
      notes.push_back("The " + percent(conf) + " highest-posterior-density region has " +
                      std::string(p == 1 ? "length " : (p == 2 ? "area " : "volume ")) +
                      fmt(post.credible_region.area) + " (likelihood-ratio region: " + fmt(r.region.area) + ").");
  }
}

nlohmann::json vector_json(const Eigen::VectorXd& v) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index j = 0; j < v.size(); ++j) a.push_back(v(j));
  return a;
}

nlohmann::json matrix_json(const Eigen::MatrixXd& m) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) a.push_back(vector_json(m.row(i).transpose()));
  return a;
}

using detail::number_json;

nlohmann::json vector_json(const std::vector<double>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (double x : v) a.push_back(number_json(x));
  return a;
}

}  // namespace

CalibrationResult calibrate(const std::vector<ParameterBounds>& parameters,
                            const std::vector<Target>& targets, const CalibrationOptions& options) {
  validate(options);
  const CalibrationProblem problem(parameters, targets);
  const auto p = static_cast<Eigen::Index>(parameters.size());
  CalibrationResult r;
  r.parameters = parameters;
  r.options = options;
  for (const Target& t : targets)
    r.targets.push_back({t.setup, t.observable, t.measured, t.sigma_measured, t.sigma_dem,
                         t.include_surrogate_variance, t.model->kind(), t.model->description()});

  r.minima = find_minima(problem, options);
  const Minimum& best = r.minima.front();
  r.region = likelihood_region(problem, best.chi_squared, options);

  // Chains start only in minima the data cannot rule out against the best one.
  const double delta = gsl_cdf_chisq_Pinv(options.confidence, static_cast<double>(p));
  std::vector<Eigen::VectorXd> starts;
  for (const Minimum& m : r.minima)
    if (m.chi_squared - best.chi_squared <= delta) starts.push_back(m.theta);
  r.posterior = sample_posterior(problem, starts, options, &r.region);

  const int dof = static_cast<int>(targets.size()) - static_cast<int>(p);
  if (dof >= 1) {
    r.fit = goodness_of_fit(best.residuals, static_cast<int>(p));
  } else {
    r.fit.chi_square = best.chi_squared;
    r.fit.degrees_of_freedom = dof;
    r.fit.chi_square_per_dof = kNaN;
    r.fit.p_value = kNaN;
  }

  const Eigen::VectorXd share =
      best.rank_deficient ? scaled_share(best.weakest_direction, problem.range()) : Eigen::VectorXd::Zero(p);
  r.identified.assign(static_cast<std::size_t>(p), false);
  for (Eigen::Index j = 0; j < p; ++j) {
    const auto js = static_cast<std::size_t>(j);
    bool inside;
    if (r.region.available) {
      inside = r.region.extent[js].identified();
    } else if (r.posterior.available) {
      // An interval that comes within (1 - confidence) of the range of a bound is what a
      // posterior flat up to that bound gives.
      const ParameterBounds& b = parameters[js];
      const double margin = (1.0 - options.confidence) * (b.upper - b.lower);
      const MarginalPosterior& m = r.posterior.marginals[js];
      inside = m.lower - b.lower > margin && b.upper - m.upper > margin;
    } else {
      const double z = std::sqrt(delta);
      const double se = best.standard_errors[js];
      inside = best.covariance_available && best.theta(j) - z * se > parameters[js].lower &&
               best.theta(j) + z * se < parameters[js].upper;
    }
    r.identified[js] = inside && share(j) < kWeakShare;
  }
  add_notes(problem, r);
  return r;
}

nlohmann::json CalibrationResult::to_json(bool include_grids, bool include_samples) const {
  using nlohmann::json;
  json j;
  j["parameters"] = json::array();
  for (const ParameterBounds& b : parameters)
    j["parameters"].push_back({{"name", b.name}, {"lower", b.lower}, {"upper", b.upper}});
  j["targets"] = json::array();
  for (const TargetSummary& t : targets)
    j["targets"].push_back({{"setup", t.setup},
                            {"observable", t.observable},
                            {"measured", t.measured},
                            {"sigma_measured", t.sigma_measured},
                            {"sigma_dem", t.sigma_dem},
                            {"include_surrogate_variance", t.include_surrogate_variance},
                            {"model_kind", t.model_kind},
                            {"model_description", t.model_description}});
  j["options"] = {{"multistart_points", options.multistart_points},
                  {"seed", options.seed},
                  {"confidence", options.confidence},
                  {"grid_points_per_axis", options.grid_points_per_axis},
                  {"grid_points_per_axis_3d", options.grid_points_per_axis_3d},
                  {"mcmc_samples", options.mcmc_samples},
                  {"mcmc_burn_in", options.mcmc_burn_in},
                  {"mcmc_chains", options.mcmc_chains},
                  {"histogram_bins", options.histogram_bins},
                  {"distinct_minimum_tolerance", options.distinct_minimum_tolerance},
                  {"distinct_minimum_barrier", options.distinct_minimum_barrier},
                  {"rank_condition_threshold", options.rank_condition_threshold},
                  {"max_solver_iterations", options.max_solver_iterations}};

  j["minima"] = json::array();
  for (const Minimum& m : minima) {
    json mj = {{"theta", vector_json(m.theta)},
               {"chi_squared", m.chi_squared},
               {"residuals", vector_json(m.residuals)},
               {"predicted", vector_json(m.predicted)},
               {"sigma_total", vector_json(m.sigma_total)},
               {"at_bound", m.at_bound},
               {"starts", m.starts},
               {"covariance_available", m.covariance_available},
               {"covariance", m.covariance_available ? matrix_json(m.covariance) : json()},
               {"standard_errors", vector_json(m.standard_errors)},
               {"rank_deficient", m.rank_deficient},
               {"singular_values", vector_json(m.singular_values)},
               {"weakest_direction", vector_json(m.weakest_direction)},
               {"solver_report", m.solver_report}};
    j["minima"].push_back(std::move(mj));
  }
  j["goodness_of_fit"] = {{"chi_square", fit.chi_square},
                          {"degrees_of_freedom", fit.degrees_of_freedom},
                          {"chi_square_per_dof", number_json(fit.chi_square_per_dof)},
                          {"p_value", number_json(fit.p_value)}};

  json rj = {{"available", region.available}, {"confidence", region.confidence}};
  if (region.available) {
    rj["layout"] = "node (i0, i1, i2) is element i0 + n0 * (i1 + n1 * i2): parameter 0 varies fastest";
    rj["axes"] = region.axes;
    rj["chi_squared_min"] = region.chi_squared_min;
    rj["threshold"] = region.threshold;
    rj["grid_minimum"] = vector_json(region.grid_minimum);
    rj["nodes_inside"] = region.nodes_inside;
    rj["area"] = region.area;
    rj["resolved"] = region.resolved;
    rj["principal_axis"] = vector_json(region.principal_axis);
    rj["extent"] = json::array();
    for (const ParameterExtent& e : region.extent)
      rj["extent"].push_back({{"parameter", e.name},
                              {"lower", number_json(e.lower)},
                              {"upper", number_json(e.upper)},
                              {"touches_lower_bound", e.touches_lower_bound},
                              {"touches_upper_bound", e.touches_upper_bound},
                              {"identified", e.identified()}});
    if (include_grids) {
      rj["chi_squared"] = region.chi_squared;
      rj["log_posterior"] = vector_json(region.log_posterior);
      rj["inside"] = region.inside;
      rj["predicted_mean"] = json::array();
      for (std::size_t i = 0; i < region.predicted_mean.size() && i < targets.size(); ++i)
        rj["predicted_mean"].push_back({{"setup", targets[i].setup},
                                        {"observable", targets[i].observable},
                                        {"measured", targets[i].measured},
                                        {"values", region.predicted_mean[i]}});
    }
  }
  j["region"] = std::move(rj);

  json pj = {{"available", posterior.available}};
  if (posterior.available) {
    pj["chains"] = posterior.chains;
    pj["samples_per_chain"] = posterior.samples_per_chain;
    pj["acceptance_rate"] = posterior.acceptance_rate;
    pj["mean"] = vector_json(posterior.mean);
    pj["covariance"] = matrix_json(posterior.covariance);
    pj["marginals"] = json::array();
    for (const MarginalPosterior& m : posterior.marginals)
      pj["marginals"].push_back({{"parameter", m.name},
                                 {"mean", m.mean},
                                 {"sd", m.sd},
                                 {"lower", m.lower},
                                 {"median", m.median},
                                 {"upper", m.upper},
                                 {"effective_sample_size", m.effective_sample_size},
                                 {"r_hat", number_json(m.r_hat)},
                                 {"histogram_edges", m.histogram_edges},
                                 {"histogram_density", m.histogram_density}});
    const CredibleRegion& c = posterior.credible_region;
    json cj = {{"available", c.available}};
    if (c.available) {
      cj["log_posterior_level"] = c.log_posterior_level;
      cj["nodes_inside"] = c.nodes_inside;
      cj["area"] = c.area;
      if (include_grids) cj["inside"] = c.inside;
    }
    pj["credible_region"] = std::move(cj);
    if (include_samples) {
      pj["samples"] = matrix_json(posterior.samples);
      pj["log_posterior"] = vector_json(posterior.log_posterior);
    }
  }
  j["posterior"] = std::move(pj);
  j["identified"] = identified;
  j["notes"] = notes;
  return j;
}

RegionComparison compare_regions(const CalibrationResult& a, const CalibrationResult& b) {
  if (a.parameters.size() != b.parameters.size())
    throw std::invalid_argument("compare regions: " + std::to_string(a.parameters.size()) +
                                " parameters against " + std::to_string(b.parameters.size()));
  for (std::size_t j = 0; j < a.parameters.size(); ++j)
    if (a.parameters[j].name != b.parameters[j].name)
      throw std::invalid_argument("compare regions: parameter " + std::to_string(j) + " is '" +
                                  a.parameters[j].name + "' in one and '" + b.parameters[j].name +
                                  "' in the other");
  if (!a.region.available || !b.region.available)
    throw std::invalid_argument("compare regions: no likelihood-ratio region (more than 3 parameters)");

  RegionComparison c;
  c.area_a = a.region.area;
  c.area_b = b.region.area;
  c.ratio = c.area_b > 0.0 ? c.area_a / c.area_b
                           : (c.area_a > 0.0 ? std::numeric_limits<double>::infinity() : kNaN);
  c.same_grid = a.region.axes == b.region.axes;
  c.overlap_area = c.overlap_fraction_a = c.overlap_fraction_b = kNaN;
  if (c.same_grid) {
    const std::vector<double> w = grid_cell_measures(a.region.axes);
    c.overlap_area = 0.0;
    for (std::size_t k = 0; k < w.size(); ++k)
      if (a.region.inside[k] && b.region.inside[k]) c.overlap_area += w[k];
    c.overlap_fraction_a = c.area_a > 0.0 ? c.overlap_area / c.area_a : kNaN;
    c.overlap_fraction_b = c.area_b > 0.0 ? c.overlap_area / c.area_b : kNaN;
  }
  for (std::size_t j = 0; j < a.parameters.size(); ++j) {
    const double wa = a.region.extent[j].upper - a.region.extent[j].lower;
    const double wb = b.region.extent[j].upper - b.region.extent[j].lower;
    c.extent_ratio.push_back(wb > 0.0 ? wa / wb : kNaN);
  }
  const bool credible = a.posterior.credible_region.available && b.posterior.credible_region.available;
  c.credible_area_a = credible ? a.posterior.credible_region.area : kNaN;
  c.credible_area_b = credible ? b.posterior.credible_region.area : kNaN;
  c.credible_ratio = credible && c.credible_area_b > 0.0 ? c.credible_area_a / c.credible_area_b : kNaN;
  return c;
}

nlohmann::json RegionComparison::to_json() const {
  nlohmann::json j = {{"area_a", area_a},
                      {"area_b", area_b},
                      {"ratio", number_json(ratio)},
                      {"same_grid", same_grid},
                      {"overlap_area", number_json(overlap_area)},
                      {"overlap_fraction_a", number_json(overlap_fraction_a)},
                      {"overlap_fraction_b", number_json(overlap_fraction_b)},
                      {"extent_ratio", vector_json(extent_ratio)},
                      {"credible_area_a", number_json(credible_area_a)},
                      {"credible_area_b", number_json(credible_area_b)},
                      {"credible_ratio", number_json(credible_ratio)}};
  return j;
}

}  // namespace demcal::calibrate
