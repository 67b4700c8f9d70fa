#include "calibrate/mismatch_location.hpp"

#include "calibrate/detail/number_text.hpp"

#include "calibrate/mismatch_detection.hpp"

#include <gsl/gsl_cdf.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <stdexcept>

namespace demcal::calibrate {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using detail::fmt;
using detail::number_json;

nlohmann::json vector_json(const Eigen::VectorXd& v) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index j = 0; j < v.size(); ++j) a.push_back(number_json(v(j)));
  return a;
}

nlohmann::json matrix_json(const Eigen::MatrixXd& m) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) a.push_back(vector_json(m.row(i).transpose()));
  return a;
}

// "a", "a and b", "a, b and c".
std::string join_names(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (k) s += k + 1 == names.size() ? " and " : ", ";
    s += names[k];
  }
  return s;
}

std::string percent_text(double share) { return fmt(100.0 * share, 2) + " %"; }

// Setups and observables in the order they first appear.
std::vector<std::string> first_appearance(const std::vector<TargetResidual>& residuals, bool observable) {
  std::vector<std::string> out;
  for (const TargetResidual& t : residuals) {
    const std::string& key = observable ? t.observable : t.setup;
    if (std::find(out.begin(), out.end(), key) == out.end()) out.push_back(key);
  }
  return out;
}

std::string location_statement(MismatchLocation& loc, const LocationOptions& options) {
  if (!(loc.chi_square > 0.0)) return "Nothing to locate: every target is matched exactly.";
  if (loc.by_observable.empty() || !loc.by_observable.front().significant) {
    const ResidualGroup& top = loc.by_observable.front();
    return "No observable stands out: the mismatch is spread over the targets (the largest share, " +
           top.name + ", holds " + percent_text(top.share) + " of chi^2, " + p_value_text(top.p_value) + ").";
  }
  // Leading observables that are off on their own, until they hold named_share of chi^2.
  double held = 0.0;
  for (const ResidualGroup& g : loc.by_observable) {
    if (!g.significant || held >= options.named_share * loc.chi_square) break;
    loc.named_observables.push_back(g.name);
    held += g.chi_square;
  }
  const std::set<std::string> named_obs(loc.named_observables.begin(), loc.named_observables.end());
  std::vector<std::string> setups;
  std::map<std::string, double> cell;
  for (const TargetResidual& t : loc.residuals) {
    if (!named_obs.count(t.observable)) continue;
    if (!cell.count(t.setup)) setups.push_back(t.setup);
    cell[t.setup] += t.residual * t.residual;
  }
  std::stable_sort(setups.begin(), setups.end(),
                   [&](const std::string& a, const std::string& b) { return cell[a] > cell[b]; });
  double in_setups = 0.0;
  for (const std::string& s : setups) {
    if (in_setups >= options.named_share * held) break;
    loc.named_setups.push_back(s);
    in_setups += cell[s];
  }
  loc.named_share = in_setups / loc.chi_square;

  std::string where;
  if (loc.named_setups.size() == setups.size() && setups.size() > 1)
    where = " at all " + std::to_string(setups.size()) + " setups";
  else
    where = std::string(loc.named_setups.size() == 1 ? " at the setup " : " at the setups ") +
            join_names(loc.named_setups);
  std::string s = "The mismatch is in " + join_names(loc.named_observables) + where + " (" +
                  percent_text(loc.named_share) + " of chi^2)";

  // The strongest trend, preferring one in a named observable.
  const ResidualTrend* trend = nullptr;
  for (const ResidualTrend& t : loc.trends)
    if (t.significant && named_obs.count(t.observable)) {
      trend = &t;
      break;
    }
  if (!trend)
    for (const ResidualTrend& t : loc.trends)
      if (t.significant) {
        trend = &t;
        break;
      }
  if (trend) {
    const bool only = loc.named_observables.size() == 1 && loc.named_observables.front() == trend->observable;
    s += std::string("; the residuals") + (only ? "" : " of " + trend->observable) + " follow " +
         trend->variable + " (t = " + fmt(trend->t, 2) + ")";
  }
  s += ".";

  const SubsetDisagreement* worst = nullptr;
  int disagreeing = 0;
  for (const SubsetDisagreement& d : loc.disagreements)
    if (d.significant) {
      ++disagreeing;
      if (!worst || d.p_value < worst->p_value) worst = &d;
    }
  if (worst)
    s += " Calibrated on each setup alone, the parameters of " + worst->setup_a + " and " + worst->setup_b +
         " disagree (" + p_value_text(worst->p_value) + ")" +
         (disagreeing > 1 ? ", and " + std::to_string(disagreeing - 1) + " other pair" +
                                (disagreeing == 2 ? "" : "s") + " too"
                          : std::string()) +
         ".";
  return s;
}

}  // namespace

void validate(const LocationOptions& o) {
  if (!(o.alpha > 0.0 && o.alpha < 1.0))
    throw std::invalid_argument("locate_mismatch: alpha must lie in (0, 1), got " + fmt(o.alpha, 6));
  if (o.min_distinct_values < 3)
    throw std::invalid_argument("locate_mismatch: min_distinct_values must be >= 3, got " +
                                std::to_string(o.min_distinct_values));
  if (!(o.named_share > 0.0 && o.named_share <= 1.0))
    throw std::invalid_argument("locate_mismatch: named_share must lie in (0, 1], got " + fmt(o.named_share, 6));
  validate(o.calibration);
}

std::vector<TargetResidual> target_residuals(const CalibrationResult& base) {
  if (base.minima.empty()) throw std::invalid_argument("locate_mismatch: the calibration result has no minimum");
  const Minimum& best = base.minima.front();
  std::vector<TargetResidual> out;
  for (std::size_t i = 0; i < base.targets.size(); ++i)
    out.push_back({base.targets[i].setup, base.targets[i].observable, base.targets[i].measured,
                   best.predicted[i], best.sigma_total[i], best.residuals[i]});
  return out;
}

std::vector<ResidualGroup> residual_groups(const std::vector<TargetResidual>& residuals, bool by_observable,
                                           double alpha) {
  double total = 0.0;
  for (const TargetResidual& t : residuals) total += t.residual * t.residual;
  std::vector<ResidualGroup> groups;
  for (const std::string& name : first_appearance(residuals, by_observable)) {
    ResidualGroup g;
    g.name = name;
    for (const TargetResidual& t : residuals)
      if ((by_observable ? t.observable : t.setup) == name) {
        ++g.count;
        g.chi_square += t.residual * t.residual;
      }
    g.share = total > 0.0 ? g.chi_square / total : kNaN;
    g.p_value = gsl_cdf_chisq_Q(g.chi_square, g.count);
    g.significant = g.p_value < alpha;
    groups.push_back(g);
  }
  std::stable_sort(groups.begin(), groups.end(),
                   [](const ResidualGroup& a, const ResidualGroup& b) { return a.chi_square > b.chi_square; });
  return groups;
}

std::vector<ResidualTrend> residual_trends(const std::vector<TargetResidual>& residuals,
                                           const SetupVariables& setup_variables,
                                           const LocationOptions& options) {
  std::vector<std::string> variables;
  for (const auto& [setup, vars] : setup_variables)
    for (const auto& [name, value] : vars) {
      if (!std::isfinite(value))
        throw std::invalid_argument("locate_mismatch: setup variable '" + name + "' of setup '" + setup +
                                    "' is not finite");
      if (std::find(variables.begin(), variables.end(), name) == variables.end()) variables.push_back(name);
    }
  std::vector<ResidualTrend> trends;
  for (const std::string& variable : variables)
    for (const std::string& observable : first_appearance(residuals, true)) {
      std::vector<double> x, r;
      for (const TargetResidual& t : residuals) {
        if (t.observable != observable) continue;
        const auto s = setup_variables.find(t.setup);
        if (s == setup_variables.end()) continue;
        const auto v = s->second.find(variable);
        if (v == s->second.end()) continue;
        x.push_back(v->second);
        r.push_back(t.residual);
      }
      const std::set<double> distinct(x.begin(), x.end());
      if (static_cast<int>(distinct.size()) < options.min_distinct_values) continue;

      ResidualTrend tr;
      tr.variable = variable;
      tr.observable = observable;
      tr.points = static_cast<int>(x.size());
      tr.distinct_values = static_cast<int>(distinct.size());
      // Centred on the mean of x so that the normal equations stay well conditioned for
      // variables like orifice_diameter_m ~ 1e-2.
      double xbar = 0.0, rbar = 0.0;
      for (std::size_t k = 0; k < x.size(); ++k) {
        xbar += x[k];
        rbar += r[k];
      }
      xbar /= static_cast<double>(x.size());
      rbar /= static_cast<double>(x.size());
      double sxx = 0.0, sxr = 0.0;
      for (std::size_t k = 0; k < x.size(); ++k) {
        sxx += (x[k] - xbar) * (x[k] - xbar);
        sxr += (x[k] - xbar) * r[k];
      }
      tr.slope = sxr / sxx;
      tr.intercept = rbar - tr.slope * xbar;
      for (std::size_t k = 0; k < x.size(); ++k) {
        const double d = r[k] - rbar - tr.slope * (x[k] - xbar);
        tr.line_chi_square += d * d;
      }
      tr.line_degrees_of_freedom = tr.points - 2;
      tr.line_p_value =
          tr.line_degrees_of_freedom > 0 ? gsl_cdf_chisq_Q(tr.line_chi_square, tr.line_degrees_of_freedom) : 1.0;
      tr.slope_standard_error = 1.0 / std::sqrt(sxx);
      tr.t = tr.slope / tr.slope_standard_error;
      tr.p_value = 2.0 * gsl_cdf_ugaussian_Q(std::abs(tr.t));
      tr.significant = tr.p_value < options.alpha;
      tr.change_over_range = tr.slope * (*distinct.rbegin() - *distinct.begin());
      trends.push_back(tr);
    }
  std::stable_sort(trends.begin(), trends.end(),
                   [](const ResidualTrend& a, const ResidualTrend& b) { return std::abs(a.t) > std::abs(b.t); });
  return trends;
}

std::vector<SubsetFit> subset_fits(const std::vector<ParameterBounds>& parameters,
                                   const std::vector<Target>& targets, const CalibrationOptions& options) {
  std::vector<std::string> setups;
  for (const Target& t : targets)
    if (std::find(setups.begin(), setups.end(), t.setup) == setups.end()) setups.push_back(t.setup);
  const auto p = static_cast<int>(parameters.size());
  std::vector<SubsetFit> fits;
  for (const std::string& setup : setups) {
    SubsetFit f;
    f.setup = setup;
    std::vector<Target> subset;
    for (const Target& t : targets)
      if (t.setup == setup) subset.push_back(t);
    f.targets = static_cast<int>(subset.size());
    if (f.targets < p) {
      f.note = std::to_string(f.targets) + " target" + (f.targets == 1 ? "" : "s") + " for " + std::to_string(p) +
               " parameters: not calibrated alone";
      fits.push_back(f);
      continue;
    }
    const CalibrationProblem problem(parameters, subset);
    const Minimum best = find_minima(problem, options).front();
    f.fitted = true;
    f.theta = best.theta;
    f.chi_squared = best.chi_squared;
    f.covariance_available = best.covariance_available;
    f.covariance = best.covariance;
    if (!f.covariance_available)
      f.note = "its targets do not determine every parameter (rank-deficient Jacobian): no covariance";
    fits.push_back(f);
  }
  return fits;
}

std::vector<SubsetDisagreement> subset_disagreements(const std::vector<SubsetFit>& fits, double alpha) {
  std::vector<SubsetDisagreement> out;
  for (std::size_t a = 0; a < fits.size(); ++a)
    for (std::size_t b = a + 1; b < fits.size(); ++b) {
      const SubsetFit& fa = fits[a];
      const SubsetFit& fb = fits[b];
      if (!fa.fitted || !fb.fitted || !fa.covariance_available || !fb.covariance_available) continue;
      const Eigen::LLT<Eigen::MatrixXd> llt(fa.covariance + fb.covariance);
      if (llt.info() != Eigen::Success) continue;
      SubsetDisagreement d;
      d.setup_a = fa.setup;
      d.setup_b = fb.setup;
      d.difference = fa.theta - fb.theta;
      d.statistic = d.difference.dot(llt.solve(d.difference));
      d.degrees_of_freedom = static_cast<int>(d.difference.size());
      d.p_value = gsl_cdf_chisq_Q(d.statistic, d.degrees_of_freedom);
      d.significant = d.p_value < alpha;
      out.push_back(d);
    }
  return out;
}

MismatchLocation locate_mismatch(const std::vector<ParameterBounds>& parameters,
                                 const std::vector<Target>& targets, const CalibrationResult& base,
                                 const SetupVariables& setup_variables, const LocationOptions& options) {
  validate(options);
  if (base.minima.empty()) throw std::invalid_argument("locate_mismatch: the calibration result has no minimum");
  if (targets.size() != base.targets.size())
    throw std::invalid_argument("locate_mismatch: " + std::to_string(targets.size()) +
                                " targets given but the calibration result has " +
                                std::to_string(base.targets.size()));
  for (std::size_t i = 0; i < targets.size(); ++i)
    if (targets[i].setup != base.targets[i].setup || targets[i].observable != base.targets[i].observable)
      throw std::invalid_argument("locate_mismatch: target " + std::to_string(i) + " (" + targets[i].setup + " " +
                                  targets[i].observable + ") is not the calibration result's target " +
                                  std::to_string(i) + " (" + base.targets[i].setup + " " +
                                  base.targets[i].observable + ")");

  MismatchLocation loc;
  loc.residuals = target_residuals(base);
  for (const TargetResidual& t : loc.residuals) loc.chi_square += t.residual * t.residual;
  loc.by_observable = residual_groups(loc.residuals, true, options.alpha);
  loc.by_setup = residual_groups(loc.residuals, false, options.alpha);
  loc.trends = residual_trends(loc.residuals, setup_variables, options);
  if (options.subset_calibrations) {
    loc.subsets = subset_fits(parameters, targets, options.calibration);
    loc.disagreements = subset_disagreements(loc.subsets, options.alpha);
  }
  loc.statement = location_statement(loc, options);
  return loc;
}

nlohmann::json MismatchLocation::to_json() const {
  using nlohmann::json;
  json j;
  j["residuals"] = json::array();
  for (const TargetResidual& t : residuals)
    j["residuals"].push_back({{"setup", t.setup},
                              {"observable", t.observable},
                              {"measured", number_json(t.measured)},
                              {"predicted", number_json(t.predicted)},
                              {"sigma_total", number_json(t.sigma_total)},
                              {"residual", number_json(t.residual)}});
  j["chi_square"] = number_json(chi_square);
  const auto groups_json = [](const std::vector<ResidualGroup>& groups) {
    json a = json::array();
    for (const ResidualGroup& g : groups)
      a.push_back({{"name", g.name},
                   {"count", g.count},
                   {"chi_square", number_json(g.chi_square)},
                   {"share", number_json(g.share)},
                   {"p_value_approximate", number_json(g.p_value)},
                   {"significant", g.significant}});
    return a;
  };
  j["by_observable"] = groups_json(by_observable);
  j["by_setup"] = groups_json(by_setup);
  j["trends"] = json::array();
  for (const ResidualTrend& t : trends)
    j["trends"].push_back({{"variable", t.variable},
                           {"observable", t.observable},
                           {"points", t.points},
                           {"distinct_values", t.distinct_values},
                           {"intercept", number_json(t.intercept)},
                           {"slope", number_json(t.slope)},
                           {"slope_standard_error", number_json(t.slope_standard_error)},
                           {"t", number_json(t.t)},
                           {"p_value_approximate", number_json(t.p_value)},
                           {"significant", t.significant},
                           {"line_chi_square", number_json(t.line_chi_square)},
                           {"line_degrees_of_freedom", t.line_degrees_of_freedom},
                           {"line_p_value", number_json(t.line_p_value)},
                           {"change_over_range", number_json(t.change_over_range)}});
  j["subsets"] = json::array();
  for (const SubsetFit& f : subsets)
    j["subsets"].push_back({{"setup", f.setup},
                            {"targets", f.targets},
                            {"fitted", f.fitted},
                            {"theta", f.fitted ? vector_json(f.theta) : json()},
                            {"chi_squared", f.fitted ? number_json(f.chi_squared) : json()},
                            {"covariance_available", f.covariance_available},
                            {"covariance", f.covariance_available ? matrix_json(f.covariance) : json()},
                            {"note", f.note}});
  j["disagreements"] = json::array();
  for (const SubsetDisagreement& d : disagreements)
    j["disagreements"].push_back({{"setup_a", d.setup_a},
                                  {"setup_b", d.setup_b},
                                  {"difference", vector_json(d.difference)},
                                  {"statistic", number_json(d.statistic)},
                                  {"degrees_of_freedom", d.degrees_of_freedom},
                                  {"p_value", number_json(d.p_value)},
                                  {"significant", d.significant}});
  j["named_observables"] = named_observables;
  j["named_setups"] = named_setups;
  j["named_share"] = number_json(named_share);
  j["statement"] = statement;
  return j;
}

}  // namespace demcal::calibrate
