// Model discrepancy as a competitor (issue 19): the generic discrepancy of
// calibrate/model_discrepancy.hpp against the named candidates, on the analytic world of
// test_discrepancy.cpp (copied below: two base parameters, three sandglass orifices with
// discharge time and AoR, three container thicknesses with AoR, candidates cohesion, wall
// friction and moisture), plus one more effect no candidate has: a constant offset of every
// discharge time (1 s; it was first 0.3 s, detected in 3 of 5 seeds only since a higher mu_s
// absorbs most of it -- judged "discrepancy" in all 3, with no target standing out -- so it
// was raised to test the decision rather than the detection).
//
// Criteria, fixed before measuring (5 seeds each; the workflow of diagnose_discrepancy,
// every candidate refitted, then decide_explanation with its default margin, log B >= 3):
//   (a) cohesion or wall friction concealed -> that candidate named in >= 4 of 5 seeds,
//       never another;
//   (b) the AoR following the orifice, or the offset of the discharge times -> verdict
//       "discrepancy" (no physics named) in >= 4 of 5 seeds where a mismatch is detected,
//       and the discrepancy names the observable that carries it;
//   (c) nothing concealed -> "none_needed" in 5 of 5 seeds.
// Unit checks: at zero amplitude the evidence is model_evidence's Laplace evidence; the
// widened intervals contain the base ones; option and input errors.
#include "calibrate/discrepancy_diagnosis.hpp"
#include "calibrate/model_discrepancy.hpp"

#include <gtest/gtest.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace {

using namespace demcal::calibrate;
using demcal::surrogate::LeaveOneOut;
using demcal::surrogate::Prediction;
using demcal::surrogate::SurrogateModel;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A surrogate given by a formula; its gradient by central differences (the formulas are
// smooth, and 1e-6 steps give ~1e-9 relative accuracy, far below the noise).
class AnalyticSurrogate final : public SurrogateModel {
 public:
  using Function = std::function<double(const Eigen::VectorXd&)>;

  AnalyticSurrogate(std::vector<std::string> names, Function mean)
      : names_(std::move(names)), mean_(std::move(mean)) {}

  std::string kind() const override { return "analytic"; }
  std::string description() const override { return "analytic test function"; }
  std::size_t input_dimension() const override { return names_.size(); }
  const std::vector<std::string>& input_names() const override { return names_; }

  Prediction predict(const Eigen::MatrixXd& points) const override {
    check(points);
    Prediction p{Eigen::VectorXd(points.rows()), Eigen::VectorXd::Zero(points.rows())};
    for (Eigen::Index i = 0; i < points.rows(); ++i) p.mean(i) = mean_(points.row(i).transpose());
    return p;
  }
  Eigen::VectorXd predict_mean(const Eigen::MatrixXd& points) const override {
    return predict(points).mean;
  }
  Eigen::MatrixXd gradient(const Eigen::MatrixXd& points) const override {
    check(points);
    Eigen::MatrixXd g(points.rows(), points.cols());
    for (Eigen::Index i = 0; i < points.rows(); ++i)
      for (Eigen::Index j = 0; j < points.cols(); ++j) {
        Eigen::VectorXd a = points.row(i).transpose(), b = a;
        const double h = 1e-6 * std::max(1.0, std::abs(a(j)));
        a(j) += h;
        b(j) -= h;
        g(i, j) = (mean_(a) - mean_(b)) / (2.0 * h);
      }
    return g;
  }
  LeaveOneOut leave_one_out() const override { return {}; }

 private:
  void check(const Eigen::MatrixXd& points) const {
    demcal::surrogate::detail::check_points("analytic", points,
                                            static_cast<Eigen::Index>(names_.size()));
  }
  std::vector<std::string> names_;
  Function mean_;
};

std::shared_ptr<const SurrogateModel> model(std::vector<std::string> names,
                                            AnalyticSurrogate::Function f) {
  return std::make_shared<AnalyticSurrogate>(std::move(names), std::move(f));
}

// Gaussian draws from GSL's MT19937: the same on every platform.
struct Normal {
  explicit Normal(unsigned long seed) : rng(gsl_rng_alloc(gsl_rng_mt19937)) {
    gsl_rng_set(rng, seed);
  }
  ~Normal() { gsl_rng_free(rng); }
  Normal(const Normal&) = delete;
  Normal& operator=(const Normal&) = delete;
  double operator()() { return gsl_ran_gaussian(rng, 1.0); }
  gsl_rng* rng;
};

template <class F>
std::string invalid_argument_message(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// ---------------------------------------------------------------------------------------
// The analytic world

const std::vector<std::string> kBaseNames = {"mu_r", "mu_s"};
const Eigen::Vector2d kTruth(0.3, 0.5);
std::vector<ParameterBounds> base_bounds() { return {{"mu_r", 0.05, 0.8}, {"mu_s", 0.2, 0.9}}; }

enum Effect {
  kNone = -1,
  kCohesion = 0,
  kWallFriction = 1,
  kMoisture = 2,
  kOrificeAor = 3,
  kTimeBias = 4
};
constexpr int kCandidates = 3;  // kOrificeAor is no candidate: the blind case

struct Spec {
  std::string setup, observable;
  double orifice_m = kNaN, thickness_d = kNaN;
  bool time() const { return observable == "discharge_time_s"; }
  bool sandglass() const { return !std::isnan(orifice_m); }
};

// The last two are held out of every fit: an orifice smaller than any fitted (the model
// must extrapolate) and a container between two fitted thicknesses.
std::vector<Spec> specs() {
  std::vector<Spec> s;
  for (const auto& [name, d] : std::vector<std::pair<std::string, double>>{
           {"orifice_10mm", 0.010}, {"orifice_14mm", 0.014}, {"orifice_20mm", 0.020}}) {
    s.push_back({name, "discharge_time_s", d, kNaN});
    s.push_back({name, "angle_of_repose_deg", d, kNaN});
  }
  for (const auto& [name, h] : std::vector<std::pair<std::string, double>>{
           {"container_2d", 2.0}, {"container_4d", 4.0}, {"container_8d", 8.0}})
    s.push_back({name, "angle_of_repose_deg", kNaN, h});
  s.push_back({"orifice_8mm", "discharge_time_s", 0.008, kNaN});
  s.push_back({"container_3d", "angle_of_repose_deg", kNaN, 3.0});
  return s;
}
constexpr std::size_t kHeldOutCount = 2;
const std::vector<TargetKey> kHeldOut = {{"orifice_8mm", "discharge_time_s"},
                                         {"container_3d", "angle_of_repose_deg"}};

std::vector<Target> without_held_out(std::vector<Target> all) {
  all.resize(all.size() - kHeldOutCount);
  return all;
}

SetupVariables setup_variables() {
  SetupVariables v;
  for (const Spec& s : specs()) {
    if (s.sandglass())
      v[s.setup]["orifice_diameter_m"] = s.orifice_m;
    else
      v[s.setup]["thickness_d"] = s.thickness_d;
  }
  return v;
}

double base_mean(const Spec& s, const Eigen::VectorXd& x) {
  const double mu_r = x(0), mu_s = x(1);
  if (s.time())
    return 5.0 * std::pow(s.orifice_m / 0.014, -2.5) *
           (1.0 + 0.4 * mu_r + 1.2 * mu_s + 0.6 * mu_s * mu_s);
  if (s.sandglass())
    return 20.0 + 30.0 * mu_r + 12.0 * mu_s + 8.0 * mu_r * mu_r + 100.0 * (s.orifice_m - 0.014);
  return 22.0 + 28.0 * mu_r + 14.0 * mu_s + 6.0 * mu_r * mu_s + 4.0 / s.thickness_d;
}

// What switching a module on adds, linear in phi.
double effect(const Spec& s, const Eigen::VectorXd& x, int e, double phi) {
  switch (e) {
    case kCohesion:  // bridges slow small orifices most; a little extra AoR everywhere
      return s.time() ? base_mean(s, x) * 3.0 * phi * std::pow(0.010 / s.orifice_m, 2) : 10.0 * phi;
    case kWallFriction:  // walls hold the heap up in thin containers
      return s.sandglass() ? 0.0 : 20.0 * phi / s.thickness_d;
    case kMoisture:  // everything a little more resistant
      return s.time() ? base_mean(s, x) * 2.0 * phi : 30.0 * phi;
    case kOrificeAor:  // the sandglass heap follows the orifice: no candidate does that
      return s.sandglass() && !s.time() ? phi * 400.0 * (s.orifice_m - 0.014) : 0.0;
    case kTimeBias:  // a constant offset of every discharge time (a clock started late)
      return s.time() ? phi : 0.0;
    default:
      return 0.0;
  }
}

CandidateParameter candidate_parameter(int e) {
  switch (e) {
    case kCohesion:
      return {"surface_energy_j_m2", 0.0, 0.0, 0.2};
    case kWallFriction:
      return {"wall_friction_coefficient", 0.0, 0.0, 1.0};
    default:
      return {"moisture_content", 0.0, 0.0, 0.1};
  }
}
const char* candidate_name(int e) {
  return e == kCohesion ? "cohesion" : e == kWallFriction ? "wall_friction" : "moisture";
}

struct Sigmas {
  double measured, dem;
};
Sigmas sigmas(const Spec& s) {
  if (s.time()) {
    const double t = base_mean(s, kTruth);
    return {0.01 * t, 0.005 * t};
  }
  return {0.5, 0.3};
}

// y_i = truth + N(0, sigma_total), the noise the likelihood assumes.
std::vector<double> record(int e, double phi, unsigned long seed) {
  Normal n(seed);
  std::vector<double> y;
  for (const Spec& s : specs()) {
    const Sigmas sg = sigmas(s);
    y.push_back(base_mean(s, kTruth) + effect(s, kTruth, e, phi) +
                std::hypot(sg.measured, sg.dem) * n());
  }
  return y;
}

std::vector<Target> base_targets(const std::vector<double>& y) {
  std::vector<Target> t;
  const std::vector<Spec> all = specs();
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Spec s = all[i];
    const Sigmas sg = sigmas(s);
    t.push_back({s.setup, s.observable, y[i], sg.measured, sg.dem,
                 model(kBaseNames, [s](const Eigen::VectorXd& x) { return base_mean(s, x); }),
                 true});
  }
  return t;
}

std::vector<Target> extended_targets(int e, const std::vector<double>& y) {
  std::vector<Target> t = base_targets(y);
  const std::vector<Spec> all = specs();
  const std::vector<std::string> names = {"mu_r", "mu_s", candidate_parameter(e).name};
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Spec s = all[i];
    t[i].model = model(names, [s, e](const Eigen::VectorXd& x) {
      return base_mean(s, x) + effect(s, x, e, x(2));
    });
  }
  return t;
}

CalibrationOptions quick_calibration() {
  CalibrationOptions o = diagnosis_calibration_defaults();
  o.multistart_points = 8;
  o.grid_points_per_axis = 41;
  o.grid_points_per_axis_3d = 21;
  return o;
}

DiagnosisOptions quick_options() {
  DiagnosisOptions o;
  o.calibration = quick_calibration();
  o.held_out = kHeldOut;
  return o;
}

// The sensitivities a user would measure: a few DEM runs at the base fit with the module
// off and on (4 replicates each, at half the parameter's range), so their standard error
// is sqrt(2 / 4) sigma_dem / (range / 2), and the estimate carries that noise.
CandidateModule candidate(int e, const Eigen::VectorXd& theta_hat, const std::vector<double>& y,
                          Normal& noise) {
  CandidateModule c;
  c.name = candidate_name(e);
  c.parameter = candidate_parameter(e);
  const double step = 0.5 * (c.parameter.upper - c.parameter.lower);
  for (const Spec& s : specs()) {
    const double se = std::sqrt(2.0 / 4.0) * sigmas(s).dem / step;
    c.sensitivity.push_back(effect(s, theta_hat, e, 1.0) + se * noise());
    c.sensitivity_se.push_back(se);
  }
  c.extended_targets = extended_targets(e, y);
  return c;
}

struct WorldRun {
  DiscrepancyDiagnosis d;
  std::vector<double> y;
};

WorldRun diagnose(int e, double phi, unsigned long seed,
                  const DiagnosisOptions& options = quick_options()) {
  WorldRun run;
  run.y = record(e, phi, seed);
  std::vector<Target> all = base_targets(run.y);
  // The user calibrates first, then runs the DEM at the base fit for the sensitivities.
  const CalibrationResult base =
      calibrate(base_bounds(), without_held_out(all), options.calibration);
  Normal noise(seed + 7919);
  std::vector<CandidateModule> candidates;
  for (int k = 0; k < kCandidates; ++k)
    candidates.push_back(candidate(k, base.minima.front().theta, run.y, noise));
  run.d = diagnose_discrepancy(base_bounds(), all, candidates, setup_variables(), options);
  return run;
}

constexpr double kCohesionTruth = 0.05;
constexpr double kWallTruth = 0.5;

// ---------------------------------------------------------------------------------------
// Detection
// ---------------------------------------------------------------------------------------
// The competitor

struct Judged {
  DiscrepancyDiagnosis d;
  DiscrepancyEvidence disc;
  ExplanationDecision decision;
};

Judged judge(int e, double phi, unsigned long seed) {
  DiagnosisOptions o = quick_options();
  o.leading_candidates = kCandidates;  // every candidate refitted: the best is compared
  Judged j;
  const WorldRun run = diagnose(e, phi, seed, o);
  j.d = run.d;
  // What the workflow calls after diagnose_discrepancy (base_targets() ends with the held-out
  // ones).
  const DiscrepancyJudgement judged = judge_against_discrepancy(base_bounds(), base_targets(run.y),
                                                                kHeldOut, j.d, setup_variables());
  EXPECT_TRUE(judged.available) << judged.note;
  j.disc = judged.discrepancy;
  j.decision = judged.decision;
  EXPECT_FALSE(judged.to_json().dump().empty());
  return j;
}

void print(const char* what, int seed, const Judged& j) {
  std::printf(
      "[model discrepancy] %s seed %d: %s %s, best %s, log B over discrepancy %.2f, over base "
      "%.2f; %s\n",
      what, seed, to_string(j.decision.verdict), j.decision.physics.c_str(),
      j.decision.best_candidate.c_str(), j.decision.log_bayes_factor_over_discrepancy,
      j.decision.log_bayes_factor_over_base, j.decision.statement.c_str());
}

TEST(ModelDiscrepancy, ZeroAmplitudeIsTheBaseLaplaceEvidence) {
  const std::vector<double> y = record(kNone, 0.0, 11);
  const auto targets = without_held_out(base_targets(y));
  const CalibrationResult base = calibrate(base_bounds(), targets, quick_calibration());
  const ModelEvidence ev = model_evidence(base, "base");
  const CalibrationProblem problem(base_bounds(), targets);
  const DiscrepancyEvidence disc =
      discrepancy_evidence(problem, base.minima.front().theta, setup_variables());
  EXPECT_NEAR(disc.log_evidence_base, ev.log_evidence_laplace, 1e-4);
  // The widened intervals contain the base model's.
  for (std::size_t k = 0; k < disc.lower.size(); ++k) {
    EXPECT_LE(disc.lower[k], disc.base_lower[k] + 1e-9);
    EXPECT_GE(disc.upper[k], disc.base_upper[k] - 1e-9);
  }
  EXPECT_EQ(disc.evidence.data.size(), ev.data.size());
  EXPECT_NO_THROW(bayes_factor(disc.evidence, ev));
  EXPECT_FALSE(disc.to_json().dump().empty());
}

TEST(ModelDiscrepancy, NamesACandidateThatReproducesTheSignature) {
  for (const auto& [e, phi, first] : std::vector<std::tuple<int, double, int>>{
           {kCohesion, kCohesionTruth, 100}, {kWallFriction, kWallTruth, 200}}) {
    int named_right = 0, named_wrong = 0;
    for (int k = 0; k < 5; ++k) {
      const Judged j = judge(e, phi, static_cast<unsigned long>(first + k));
      print(candidate_name(e), first + k, j);
      if (j.decision.verdict == Explanation::physics)
        (j.decision.physics == candidate_name(e) ? named_right : named_wrong) += 1;
    }
    EXPECT_GE(named_right, 4) << candidate_name(e);
    EXPECT_EQ(named_wrong, 0) << candidate_name(e);
  }
}

TEST(ModelDiscrepancy, ACandidateIsNamedOnlyWhenItBeatsTheRunnerUpByTheMargin) {
  // A mimic: a second candidate with the named one's fit and its log evidence `gap` below.
  // Within the margin the recordings cannot tell the two apart, so neither is named (the
  // blind test's cohesion vs size spread, tests/concealed/README.md run 4); at the margin or
  // beyond, the best is named as before. Found on the first seed that names cohesion.
  Judged j;
  int seed = 100;
  for (; seed < 110; ++seed) {
    j = judge(kCohesion, kCohesionTruth, static_cast<unsigned long>(seed));
    if (j.decision.verdict == Explanation::physics) break;
  }
  ASSERT_EQ(j.decision.verdict, Explanation::physics) << "no seed in 100-109 named cohesion";
  ASSERT_EQ(j.decision.physics, "cohesion");
  const auto best = std::find_if(j.d.fits.begin(), j.d.fits.end(),
                                 [](const CandidateFit& f) { return f.name == "cohesion"; });
  ASSERT_NE(best, j.d.fits.end());
  const double margin = ExplanationOptions{}.required_log_bayes_factor;
  const auto decide_with_mimic = [&](double gap) {
    std::vector<ModelEvidence> evidences;
    for (const auto& f : j.d.fits) evidences.push_back(f.evidence);
    ModelEvidence mimic = best->evidence;
    mimic.model = "mimic";
    mimic.log_evidence -= gap;
    evidences.push_back(mimic);
    return decide_explanation(j.d.detection, j.d.base_evidence, evidences, j.disc);
  };
  for (const double gap : {0.0, 1.0, margin - 0.01}) {
    const ExplanationDecision d = decide_with_mimic(gap);
    EXPECT_EQ(d.verdict, Explanation::discrepancy) << "gap " << gap;
    EXPECT_TRUE(d.physics.empty());
    EXPECT_EQ(d.best_candidate, "cohesion");
    EXPECT_EQ(d.runner_up, "mimic");
    EXPECT_NEAR(d.log_bayes_factor_over_runner_up, gap, 1e-9);
    ASSERT_GE(d.indistinguishable.size(), 2u);
    EXPECT_EQ(d.indistinguishable[0], "cohesion");
    EXPECT_EQ(d.indistinguishable[1], "mimic");
    EXPECT_NE(d.statement.find("cannot tell them apart"), std::string::npos) << d.statement;
    EXPECT_NE(d.statement.find("as by mimic"), std::string::npos) << d.statement;
    EXPECT_NE(d.to_json().dump().find("\"indistinguishable\":[\"cohesion\",\"mimic\""),
              std::string::npos);
  }
  for (const double gap : {margin, margin + 5.0}) {
    const ExplanationDecision d = decide_with_mimic(gap);
    EXPECT_EQ(d.verdict, Explanation::physics) << "gap " << gap;
    EXPECT_EQ(d.physics, "cohesion");
    EXPECT_TRUE(d.indistinguishable.empty());
    EXPECT_NE(d.statement.find("over mimic, the next candidate"), std::string::npos) << d.statement;
  }
  // The candidates-only verdict of diagnose_discrepancy follows the same rule: cohesion
  // beat its next candidate by the margin here, or it would not have been chosen.
  EXPECT_EQ(j.d.outcome, DiagnosisOutcome::explained);
  EXPECT_GE(std::log(j.d.bayes_factor_over_next), margin);
}

TEST(ModelDiscrepancy, DiscrepancyWinsWhenNoCandidateHasThePattern) {
  for (const auto& [e, phi, first, observable] :
       std::vector<std::tuple<int, double, int, std::string>>{
           {kOrificeAor, 1.0, 300, "angle_of_repose_deg"},
           {kTimeBias, 1.0, 400, "discharge_time_s"}}) {
    int detected = 0, discrepancy = 0, observable_named = 0;
    for (int k = 0; k < 5; ++k) {
      const Judged j = judge(e, phi, static_cast<unsigned long>(first + k));
      print(e == kOrificeAor ? "AoR follows the orifice" : "discharge-time offset", first + k, j);
      if (!j.d.detection.mismatch()) continue;
      ++detected;
      if (j.decision.verdict != Explanation::discrepancy) continue;
      ++discrepancy;
      EXPECT_TRUE(j.decision.physics.empty());
      EXPECT_NE(j.decision.statement.find("no candidate explains"), std::string::npos);
      if (j.decision.statement.find(observable) != std::string::npos) ++observable_named;
    }
    EXPECT_GE(detected, 4) << observable;
    EXPECT_GE(discrepancy, detected - 1) << observable;
    EXPECT_GE(observable_named, discrepancy - 1) << observable;
  }
}

TEST(ModelDiscrepancy, NeitherWithoutAMismatch) {
  for (int k = 0; k < 5; ++k) {
    const Judged j = judge(kNone, 0.0, static_cast<unsigned long>(500 + k));
    print("null", 500 + k, j);
    EXPECT_EQ(j.decision.verdict, Explanation::none_needed);
    EXPECT_TRUE(j.decision.physics.empty());
  }
}

TEST(ModelDiscrepancy, OptionsAreChecked) {
  DiscrepancyOptions o;
  o.max_amplitude = o.min_amplitude;
  EXPECT_THROW(validate(o), std::invalid_argument);
  o = {};
  o.amplitude_nodes = 1;
  EXPECT_THROW(validate(o), std::invalid_argument);
  ExplanationOptions x;
  x.required_log_bayes_factor = -1.0;
  EXPECT_THROW(validate(x), std::invalid_argument);
}

}  // namespace
