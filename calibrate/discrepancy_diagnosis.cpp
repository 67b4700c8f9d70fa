#include "calibrate/discrepancy_diagnosis.hpp"

#include "calibrate/detail/number_text.hpp"

#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace demcal::calibrate {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kAtBoundTolerance = 1e-6;  // bound-scaled, as Minimum::at_bound

using detail::fmt;
using detail::number_json;

nlohmann::json vector_json(const Eigen::VectorXd& v) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index j = 0; j < v.size(); ++j) a.push_back(number_json(v(j)));
  return a;
}

std::string key_text(const std::string& setup, const std::string& observable) {
  return setup + " " + observable;
}

std::string factor_text(double log_b) {
  if (std::isnan(log_b)) return "n/a";
  if (log_b > std::log(1e6)) return "> 1e6";
  return fmt(std::exp(log_b), 2);
}

std::string interval_text(double lo, double hi) {
  if (std::isnan(lo) || std::isnan(hi)) return "interval not available";
  return fmt(lo, 2) + (lo < 0.0 || hi < 0.0 ? " to " : "-") + fmt(hi, 2);
}

// The first-order extension of a base target into phi, for candidates without a design:
// mean(theta) + s (phi - phi0), variance(theta) + (phi - phi0)^2 se^2, so that the
// sensitivity's own uncertainty grows with the distance from where it was measured.
class LinearizedExtension final : public surrogate::SurrogateModel {
 public:
  LinearizedExtension(std::shared_ptr<const surrogate::SurrogateModel> base,
                      std::vector<std::string> names, double sensitivity, double sensitivity_se,
                      double off_value)
      : base_(std::move(base)),
        names_(std::move(names)),
        s_(sensitivity),
        se_(sensitivity_se),
        phi0_(off_value) {}

  std::string kind() const override { return "linearized_extension"; }
  std::string description() const override {
    return "first-order extension in " + names_.back() + " of: " + base_->description();
  }
  std::size_t input_dimension() const override { return names_.size(); }
  const std::vector<std::string>& input_names() const override { return names_; }

  surrogate::Prediction predict(const Eigen::MatrixXd& points) const override {
    check(points);
    surrogate::Prediction p = base_->predict(points.leftCols(base_inputs()));
    const Eigen::VectorXd step = points.col(base_inputs()).array() - phi0_;
    p.mean += s_ * step;
    p.variance += (se_ * se_) * step.cwiseAbs2();
    return p;
  }
  Eigen::VectorXd predict_mean(const Eigen::MatrixXd& points) const override {
    check(points);
    return base_->predict_mean(points.leftCols(base_inputs())) +
           s_ * (points.col(base_inputs()).array() - phi0_).matrix();
  }
  Eigen::MatrixXd gradient(const Eigen::MatrixXd& points) const override {
    check(points);
    Eigen::MatrixXd g(points.rows(), points.cols());
    g.leftCols(base_inputs()) = base_->gradient(points.leftCols(base_inputs()));
    g.col(base_inputs()).setConstant(s_);
    return g;
  }
  // Nothing was fitted, so there is nothing to leave out.
  surrogate::LeaveOneOut leave_one_out() const override { return {}; }

 private:
  Eigen::Index base_inputs() const { return static_cast<Eigen::Index>(names_.size()) - 1; }
  void check(const Eigen::MatrixXd& points) const {
    surrogate::detail::check_points("linearized extension", points,
                                    static_cast<Eigen::Index>(names_.size()));
  }
  std::shared_ptr<const surrogate::SurrogateModel> base_;
  std::vector<std::string> names_;
  double s_, se_, phi0_;
};

struct Inputs {
  std::vector<std::size_t> fitted, held;  // indices into the targets
  std::vector<std::string> parameter_names;
};

Inputs check_inputs(const std::vector<ParameterBounds>& parameters,
                    const std::vector<Target>& targets,
                    const std::vector<CandidateModule>& candidates,
                    const SetupVariables& setup_variables, const DiagnosisOptions& options) {
  validate(options);
  const CalibrationProblem all(parameters, targets);  // checks parameters and targets
  const std::string who = "diagnose_discrepancy: ";
  Inputs in;
  for (const ParameterBounds& b : parameters) in.parameter_names.push_back(b.name);

  std::map<std::pair<std::string, std::string>, std::size_t> index;
  std::set<std::string> setups;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    if (!index.emplace(std::make_pair(targets[i].setup, targets[i].observable), i).second)
      throw std::invalid_argument(who + "target '" +
                                  key_text(targets[i].setup, targets[i].observable) +
                                  "' is listed twice");
    setups.insert(targets[i].setup);
  }
  std::vector<bool> held(targets.size(), false);
  for (const TargetKey& k : options.held_out) {
    const auto it = index.find({k.setup, k.observable});
    if (it == index.end())
      throw std::invalid_argument(who + "held-out target '" + key_text(k.setup, k.observable) +
                                  "' is not among the targets");
    if (held[it->second])
      throw std::invalid_argument(who + "held-out target '" + key_text(k.setup, k.observable) +
                                  "' is listed twice");
    held[it->second] = true;
  }
  for (std::size_t i = 0; i < targets.size(); ++i) (held[i] ? in.held : in.fitted).push_back(i);
  if (in.fitted.empty())
    throw std::invalid_argument(who + "every target is held out: nothing to fit");

  for (const auto& [setup, vars] : setup_variables) {
    if (!setups.count(setup))
      throw std::invalid_argument(who + "setup variables are given for setup '" + setup +
                                  "', which no target has");
    for (const auto& [name, value] : vars)
      if (!std::isfinite(value))
        throw std::invalid_argument(who + "setup variable '" + name + "' of setup '" + setup +
                                    "' is not finite");
  }

  std::set<std::string> names;
  for (const CandidateModule& c : candidates) {
    validate(CandidateSignature{c.name, c.parameter, c.sensitivity, c.sensitivity_se},
             targets.size());
    const std::string cw = who + "candidate '" + c.name + "'";
    if (!names.insert(c.name).second) throw std::invalid_argument(cw + " is listed twice");
    if (std::find(in.parameter_names.begin(), in.parameter_names.end(), c.parameter.name) !=
        in.parameter_names.end())
      throw std::invalid_argument(cw + ": its parameter '" + c.parameter.name +
                                  "' is a base parameter");
    std::vector<bool> seen(targets.size(), false);
    for (std::size_t e = 0; e < c.extended_targets.size(); ++e) {
      const Target& t = c.extended_targets[e];
      const std::string label = "extended target '" + key_text(t.setup, t.observable) + "'";
      const auto it = index.find({t.setup, t.observable});
      if (it == index.end())
        throw std::invalid_argument(cw + ": " + label + " is not among the targets");
      if (seen[it->second]) throw std::invalid_argument(cw + ": " + label + " is listed twice");
      seen[it->second] = true;
      if (!t.model) throw std::invalid_argument(cw + ": " + label + " has no surrogate model");
      if (t.model->input_dimension() != parameters.size() + 1)
        throw std::invalid_argument(cw + ": " + label + ": its model has " +
                                    std::to_string(t.model->input_dimension()) + " inputs, not " +
                                    std::to_string(parameters.size() + 1) +
                                    " (the base parameters, then " + c.parameter.name + ")");
      const Target& base = targets[it->second];
      if (t.measured != base.measured || t.sigma_measured != base.sigma_measured)
        throw std::invalid_argument(cw + ": " + label + " has measured " + fmt(t.measured, 6) +
                                    " +/- " + fmt(t.sigma_measured, 6) + " but the target has " +
                                    fmt(base.measured, 6) + " +/- " + fmt(base.sigma_measured, 6));
    }
  }
  return in;
}

// Every target extended into the candidate's parameter: its design where given, else to
// first order. Returns the number of fitted targets that were linearized through `linearized`.
std::vector<Target> extend_targets(const std::vector<ParameterBounds>& parameters,
                                   const std::vector<Target>& targets, const CandidateModule& c,
                                   const std::vector<std::size_t>& fitted, int* linearized) {
  std::vector<std::string> names;
  for (const ParameterBounds& b : parameters) names.push_back(b.name);
  names.push_back(c.parameter.name);
  std::vector<Target> out;
  std::vector<bool> linear(targets.size(), false);
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const Target& base = targets[i];
    const auto it = std::find_if(
        c.extended_targets.begin(), c.extended_targets.end(),
        [&](const Target& t) { return t.setup == base.setup && t.observable == base.observable; });
    if (it != c.extended_targets.end()) {
      out.push_back(*it);
      continue;
    }
    Target t = base;
    const double se = c.sensitivity_se.empty() ? 0.0 : c.sensitivity_se[i];
    t.model = std::make_shared<LinearizedExtension>(base.model, names, c.sensitivity[i], se,
                                                    c.parameter.off_value);
    out.push_back(std::move(t));
    linear[i] = true;
  }
  *linearized = 0;
  for (std::size_t i : fitted)
    if (linear[i]) ++*linearized;
  return out;
}

std::vector<Target> pick(const std::vector<Target>& targets,
                         const std::vector<std::size_t>& indices) {
  std::vector<Target> out;
  for (std::size_t i : indices) out.push_back(targets[i]);
  return out;
}

// The candidate's parameter is the last axis of the grid; chi^2 minimized over the other
// axes at each of its nodes, and the interval where that profile stays below the threshold,
// with the crossings interpolated linearly between nodes.
std::pair<double, double> grid_profile_interval(const CalibrationResult& r, double confidence) {
  const LikelihoodRegion& reg = r.region;
  if (!reg.available || reg.axes.empty()) return {kNaN, kNaN};
  const std::vector<double>& axis = reg.axes.back();
  std::size_t stride = 1;
  for (std::size_t a = 0; a + 1 < reg.axes.size(); ++a) stride *= reg.axes[a].size();
  std::vector<double> profile(axis.size(), std::numeric_limits<double>::infinity());
  for (std::size_t k = 0; k < reg.chi_squared.size(); ++k)
    profile[k / stride] = std::min(profile[k / stride], reg.chi_squared[k]);
  const double least =
      std::min(*std::min_element(profile.begin(), profile.end()), r.minima.front().chi_squared);
  const double threshold = least + gsl_cdf_chisq_Pinv(confidence, 1.0);
  std::size_t first = axis.size(), last = 0;
  for (std::size_t i = 0; i < axis.size(); ++i)
    if (profile[i] <= threshold) {
      first = std::min(first, i);
      last = i;
    }
  if (first == axis.size()) return {kNaN, kNaN};
  const auto cross = [&](std::size_t in, std::size_t out) {
    const double f = (threshold - profile[in]) / (profile[out] - profile[in]);
    return axis[in] + std::clamp(f, 0.0, 1.0) * (axis[out] - axis[in]);
  };
  const double lo = first > 0 ? cross(first, first - 1) : axis[first];
  const double hi = last + 1 < axis.size() ? cross(last, last + 1) : axis[last];
  return {lo, hi};
}

CandidateFit fit_candidate(const std::vector<ParameterBounds>& parameters,
                           const std::vector<Target>& targets, const Inputs& in,
                           const CandidateModule& c, const DiscrepancyDiagnosis& d,
                           const DiagnosisOptions& options) {
  CandidateFit f;
  f.name = c.name;
  f.parameter = c.parameter;
  std::vector<ParameterBounds> extended = parameters;
  extended.push_back({c.parameter.name, c.parameter.lower, c.parameter.upper});
  const std::vector<Target> all =
      extend_targets(parameters, targets, c, in.fitted, &f.linearized_targets);
  f.calibration = calibrate(extended, pick(all, in.fitted), options.calibration);
  f.evidence = model_evidence(f.calibration, c.name);
  if (f.evidence.method != EvidenceMethod::none && d.base_evidence.method != EvidenceMethod::none)
    f.over_base = bayes_factor(f.evidence, d.base_evidence);
  else
    f.over_base = {c.name, "base", kNaN, kNaN, kNaN, "n/a", "no evidence to compare"};

  const Minimum& best = f.calibration.minima.front();
  const auto p = static_cast<Eigen::Index>(parameters.size());
  f.theta = best.theta.head(p);
  f.theta_shift = f.theta - d.base.minima.front().theta;
  f.phi = best.theta(p);
  f.chi_square_per_dof = f.calibration.fit.chi_square_per_dof;

  const double range = c.parameter.upper - c.parameter.lower;
  const double u = (f.phi - c.parameter.lower) / range;
  const bool at_bound = u <= kAtBoundTolerance || u >= 1.0 - kAtBoundTolerance;
  const double confidence = options.calibration.confidence;
  const double se = best.standard_errors[static_cast<std::size_t>(p)];
  if (best.covariance_available && !at_bound && std::isfinite(se)) {
    const double z = std::sqrt(gsl_cdf_chisq_Pinv(confidence, 1.0));
    f.phi_lower = std::max(c.parameter.lower, f.phi - z * se);
    f.phi_upper = std::min(c.parameter.upper, f.phi + z * se);
    f.interval_method = "covariance";
  } else {
    std::tie(f.phi_lower, f.phi_upper) = grid_profile_interval(f.calibration, confidence);
    f.interval_method = std::isnan(f.phi_lower) ? "none" : "grid profile";
  }
  return f;
}

TargetComparison comparison(const Target& t, bool held_out) {
  TargetComparison c;
  c.setup = t.setup;
  c.observable = t.observable;
  c.held_out = held_out;
  c.measured = t.measured;
  c.sigma_measured = t.sigma_measured;
  c.predicted_after = c.sigma_total_after = c.residual_after = kNaN;
  return c;
}

// Predictions of `targets` at one point of `parameters`, as (mean, sigma_total, residual).
TargetPredictions predict_at(const std::vector<ParameterBounds>& parameters,
                             const std::vector<Target>& targets, const Eigen::VectorXd& point) {
  return CalibrationProblem(parameters, targets).evaluate(point.transpose());
}

std::string summary_text(const DiscrepancyDiagnosis& d, const DiagnosisOptions& options) {
  std::string s =
      options.deciding_detection ? options.deciding_detection->statement : d.detection.statement;
  if (d.outcome == DiagnosisOutcome::reproduced || d.outcome == DiagnosisOutcome::untestable)
    return s;
  if (d.location_available) s += " " + d.location.statement;
  if (d.outcome == DiagnosisOutcome::explained) {
    const CandidateFit& f = d.fits[static_cast<std::size_t>(d.chosen)];
    s += " Best explained by " + f.name + ": " + f.parameter.name + " = " + fmt(f.phi, 2) + " (" +
         interval_text(f.phi_lower, f.phi_upper) + "); Bayes factor " +
         factor_text(std::log(d.bayes_factor_over_next)) + " over " +
         (d.next_candidate.empty() ? std::string("the base model")
                                   : d.next_candidate + ", the next candidate") +
         ". With it: chi2/dof = " + fmt(d.chi_square_per_dof_after, 2) + ".";
    return s;
  }
  if (d.fits.empty()) return s + " No candidate was recalibrated: the mismatch is unexplained.";
  const CandidateFit& best = d.fits.front();
  if (!d.next_candidate.empty() && d.bayes_factor_over_base > 0.0 &&
      std::log(d.bayes_factor_over_base) >= options.required_log_bayes_factor)
    return s + " No candidate explains it alone: the best, " + best.name +
           ", has a Bayes factor of " + factor_text(std::log(d.bayes_factor_over_next)) + " over " +
           d.next_candidate + ", the next candidate (" +
           factor_text(options.required_log_bayes_factor) +
           " required), so the recordings cannot tell them apart. The mismatch is unexplained.";
  return s + " No candidate explains it: the best, " + best.name + ", has a Bayes factor of " +
         factor_text(std::log(d.bayes_factor_over_base)) + " over the base model (" +
         factor_text(options.required_log_bayes_factor) +
         " required). The mismatch is unexplained.";
}

}  // namespace

CalibrationOptions diagnosis_calibration_defaults() {
  CalibrationOptions o;
  o.mcmc_samples = 0;
  return o;
}

const char* to_string(DiagnosisOutcome outcome) {
  switch (outcome) {
    case DiagnosisOutcome::reproduced:
      return "reproduced";
    case DiagnosisOutcome::untestable:
      return "untestable";
    case DiagnosisOutcome::explained:
      return "explained";
    case DiagnosisOutcome::unexplained:
      return "unexplained";
  }
  return "untestable";
}

void validate(const DiagnosisOptions& o) {
  const std::string who = "diagnose_discrepancy: ";
  if (!(o.alpha > 0.0 && o.alpha < 1.0))
    throw std::invalid_argument(who + "alpha must lie in (0, 1), got " + fmt(o.alpha, 6));
  if (o.leading_candidates < 0)
    throw std::invalid_argument(who + "leading_candidates must be >= 0, got " +
                                std::to_string(o.leading_candidates));
  if (!(o.required_log_bayes_factor >= 0.0) || !std::isfinite(o.required_log_bayes_factor))
    throw std::invalid_argument(who + "required_log_bayes_factor must be finite and >= 0, got " +
                                fmt(o.required_log_bayes_factor, 6));
  validate(o.calibration);
  LocationOptions location = o.location;
  location.alpha = o.alpha;
  location.calibration = o.calibration;
  validate(location);
  ScoreOptions score = o.score;
  score.alpha = o.alpha;
  validate(score);
}

DiscrepancyDiagnosis diagnose_discrepancy(const std::vector<ParameterBounds>& parameters,
                                          const std::vector<Target>& targets,
                                          const std::vector<CandidateModule>& candidates,
                                          const SetupVariables& setup_variables,
                                          const DiagnosisOptions& options) {
  const Inputs in = check_inputs(parameters, targets, candidates, setup_variables, options);
  const std::vector<Target> fitted = pick(targets, in.fitted);
  const std::vector<Target> held = pick(targets, in.held);

  DiscrepancyDiagnosis d;
  d.base = calibrate(parameters, fitted, options.calibration);
  d.detection = detect_mismatch(d.base, DetectionOptions{options.alpha});
  d.base_evidence = model_evidence(d.base, "base");
  d.chi_square_per_dof_before = d.detection.chi_square_per_dof;
  d.chi_square_per_dof_after = kNaN;
  d.bayes_factor_over_base = d.bayes_factor_over_next = kNaN;
  const Eigen::VectorXd theta0 = d.base.minima.front().theta;

  ScoreOptions score_options = options.score;
  score_options.alpha = options.alpha;
  std::vector<CandidateSignature> signatures;
  for (const CandidateModule& c : candidates) {
    CandidateSignature s{c.name, c.parameter, {}, {}};
    for (std::size_t i : in.fitted) {
      s.sensitivity.push_back(c.sensitivity[i]);
      if (!c.sensitivity_se.empty()) s.sensitivity_se.push_back(c.sensitivity_se[i]);
    }
    signatures.push_back(std::move(s));
  }
  d.scores =
      rank_candidates(CalibrationProblem(parameters, fitted), theta0, signatures, score_options);

  const Minimum& base_best = d.base.minima.front();
  for (std::size_t k = 0; k < fitted.size(); ++k) {
    TargetComparison c = comparison(fitted[k], false);
    c.predicted_before = base_best.predicted[k];
    c.sigma_total_before = base_best.sigma_total[k];
    c.residual_before = base_best.residuals[k];
    d.fitted_targets.push_back(c);
  }
  if (!held.empty()) {
    const TargetPredictions before = predict_at(parameters, held, theta0);
    for (std::size_t k = 0; k < held.size(); ++k) {
      const auto col = static_cast<Eigen::Index>(k);
      TargetComparison c = comparison(held[k], true);
      c.predicted_before = before.mean(0, col);
      c.sigma_total_before = before.sigma_total(0, col);
      c.residual_before = before.residual(0, col);
      d.held_out_targets.push_back(c);
    }
  }

  const MismatchDetection& deciding =
      options.deciding_detection ? *options.deciding_detection : d.detection;
  if (!deciding.mismatch()) {
    d.outcome = deciding.verdict == MismatchVerdict::untestable ? DiagnosisOutcome::untestable
                                                                : DiagnosisOutcome::reproduced;
    d.scores_needed = false;
    if (!d.scores.empty())
      d.notes.push_back(
          "The candidates were scored for information only: without a mismatch no physics is "
          "added.");
    d.summary = summary_text(d, options);
    return d;
  }
  d.scores_needed = true;

  LocationOptions location_options = options.location;
  location_options.alpha = options.alpha;
  location_options.calibration = options.calibration;
  d.location = locate_mismatch(parameters, fitted, d.base, setup_variables, location_options);
  d.location_available = true;

  int recalibrated = 0;
  for (const CandidateScore& sc : d.scores) {
    // The score test ranks; it does not veto. A candidate it could not settle (confounded,
    // or mimicked within the probes' noise) is refitted when the budget allows, after the
    // assessed ones; one the probes did not see at all is not.
    if (sc.status != ScoreStatus::assessed) d.notes.push_back(sc.statement);
    if (sc.signature_within_noise) continue;
    if (recalibrated >= options.leading_candidates) {
      d.notes.push_back(sc.name + " was not recalibrated: ranked " + std::to_string(sc.rank) +
                        " by the score test (leading_candidates = " +
                        std::to_string(options.leading_candidates) + ").");
      continue;
    }
    const auto it = std::find_if(candidates.begin(), candidates.end(),
                                 [&](const CandidateModule& c) { return c.name == sc.name; });
    d.fits.push_back(fit_candidate(parameters, targets, in, *it, d, options));
    ++recalibrated;
    const CandidateFit& f = d.fits.back();
    if (f.linearized_targets > 0)
      d.notes.push_back(
          f.name + ": " + std::to_string(f.linearized_targets) + " of " +
          std::to_string(fitted.size()) +
          " fitted targets were extended to first order from the sensitivities (no extended design"
          " for them); trust the fit only near " +
          f.parameter.name + " = " + fmt(f.parameter.off_value) + ".");
  }
  std::stable_sort(d.fits.begin(), d.fits.end(), [](const CandidateFit& a, const CandidateFit& b) {
    const double x = a.evidence.log_evidence, y = b.evidence.log_evidence;
    if (std::isnan(y)) return !std::isnan(x);
    return !std::isnan(x) && x > y;
  });

  d.outcome = DiagnosisOutcome::unexplained;
  if (!d.fits.empty() && !std::isnan(d.fits.front().evidence.log_evidence)) {
    const CandidateFit& best = d.fits.front();
    d.bayes_factor_over_base = best.over_base.bayes_factor;
    if (d.fits.size() > 1 && !std::isnan(d.fits[1].evidence.log_evidence)) {
      d.next_candidate = d.fits[1].name;
      d.bayes_factor_over_next =
          std::exp(best.evidence.log_evidence - d.fits[1].evidence.log_evidence);
    } else {
      d.bayes_factor_over_next = d.bayes_factor_over_base;
    }
    // Named only when it beats the base model and the next candidate by the margin: two
    // candidates the recordings fit about equally well are not told apart by them.
    if (best.over_base.log_bayes_factor >= options.required_log_bayes_factor &&
        std::log(d.bayes_factor_over_next) >= options.required_log_bayes_factor) {
      d.outcome = DiagnosisOutcome::explained;
      d.chosen = 0;
    }
  }

  if (d.chosen >= 0) {
    const CandidateFit& f = d.fits.front();
    const CandidateModule& c =
        *std::find_if(candidates.begin(), candidates.end(),
                      [&](const CandidateModule& m) { return m.name == f.name; });
    d.chi_square_per_dof_after = f.chi_square_per_dof;
    const Minimum& after = f.calibration.minima.front();
    for (std::size_t k = 0; k < fitted.size(); ++k) {
      d.fitted_targets[k].predicted_after = after.predicted[k];
      d.fitted_targets[k].sigma_total_after = after.sigma_total[k];
      d.fitted_targets[k].residual_after = after.residuals[k];
    }
    if (!held.empty()) {
      std::vector<ParameterBounds> extended = parameters;
      extended.push_back({c.parameter.name, c.parameter.lower, c.parameter.upper});
      int unused = 0;
      const std::vector<Target> all = extend_targets(parameters, targets, c, in.fitted, &unused);
      const TargetPredictions pred = predict_at(extended, pick(all, in.held), after.theta);
      for (std::size_t k = 0; k < held.size(); ++k) {
        const auto col = static_cast<Eigen::Index>(k);
        d.held_out_targets[k].predicted_after = pred.mean(0, col);
        d.held_out_targets[k].sigma_total_after = pred.sigma_total(0, col);
        d.held_out_targets[k].residual_after = pred.residual(0, col);
      }
    }
  }
  for (const TargetComparison& t : d.held_out_targets)
    d.notes.push_back("Held out " + key_text(t.setup, t.observable) + ": measured " +
                      fmt(t.measured, 4) + ", predicted " + fmt(t.predicted_before, 4) +
                      " (r = " + fmt(t.residual_before, 2) + ") by the base model" +
                      (d.chosen >= 0 ? " and " + fmt(t.predicted_after, 4) +
                                           " (r = " + fmt(t.residual_after, 2) + ") with " +
                                           d.fits.front().name
                                     : std::string()) +
                      ".");
  d.summary = summary_text(d, options);
  return d;
}

nlohmann::json DiscrepancyDiagnosis::to_json(bool include_grids) const {
  using nlohmann::json;
  json j;
  j["outcome"] = to_string(outcome);
  j["summary"] = summary;
  j["detection"] = detection.to_json();
  j["base"] = base.to_json(include_grids, false);
  j["base_evidence"] = base_evidence.to_json();
  j["location_available"] = location_available;
  j["location"] = location_available ? location.to_json() : json();
  j["scores_needed"] = scores_needed;
  j["scores"] = json::array();
  for (const CandidateScore& s : scores) j["scores"].push_back(s.to_json());
  j["fits"] = json::array();
  for (const CandidateFit& f : fits)
    j["fits"].push_back({{"name", f.name},
                         {"parameter",
                          {{"name", f.parameter.name},
                           {"off_value", f.parameter.off_value},
                           {"lower", f.parameter.lower},
                           {"upper", f.parameter.upper}}},
                         {"linearized_targets", f.linearized_targets},
                         {"phi", number_json(f.phi)},
                         {"phi_lower", number_json(f.phi_lower)},
                         {"phi_upper", number_json(f.phi_upper)},
                         {"interval_method", f.interval_method},
                         {"theta", vector_json(f.theta)},
                         {"theta_shift", vector_json(f.theta_shift)},
                         {"chi_square_per_dof", number_json(f.chi_square_per_dof)},
                         {"evidence", f.evidence.to_json()},
                         {"over_base", f.over_base.to_json()},
                         {"calibration", f.calibration.to_json(include_grids, false)}});
  j["chosen"] = chosen >= 0 ? json(fits[static_cast<std::size_t>(chosen)].name) : json();
  j["bayes_factor_over_base"] = number_json(bayes_factor_over_base);
  j["bayes_factor_over_next"] = number_json(bayes_factor_over_next);
  j["next_candidate"] = next_candidate.empty() ? json() : json(next_candidate);
  j["chi_square_per_dof_before"] = number_json(chi_square_per_dof_before);
  j["chi_square_per_dof_after"] = number_json(chi_square_per_dof_after);
  const auto targets_json = [](const std::vector<TargetComparison>& list) {
    json a = json::array();
    for (const TargetComparison& t : list)
      a.push_back({{"setup", t.setup},
                   {"observable", t.observable},
                   {"held_out", t.held_out},
                   {"measured", number_json(t.measured)},
                   {"sigma_measured", number_json(t.sigma_measured)},
                   {"predicted_before", number_json(t.predicted_before)},
                   {"sigma_total_before", number_json(t.sigma_total_before)},
                   {"residual_before", number_json(t.residual_before)},
                   {"predicted_after", number_json(t.predicted_after)},
                   {"sigma_total_after", number_json(t.sigma_total_after)},
                   {"residual_after", number_json(t.residual_after)}});
    return a;
  };
  j["fitted_targets"] = targets_json(fitted_targets);
  j["held_out_targets"] = targets_json(held_out_targets);
  j["notes"] = notes;
  return j;
}

}  // namespace demcal::calibrate
