// The analytic world of the diagnosis tests (test_discrepancy.cpp, test_model_discrepancy.cpp):
// two base parameters (mu_r, mu_s); three sandglass orifices with discharge time and AoR and
// three container thicknesses with AoR, by formulas; candidates cohesion, wall friction and
// moisture whose effects are linear in their parameter; two blind effects no candidate has
// (the sandglass AoR following the orifice, a constant offset of the discharge times). One
// world, so that a change to it moves both suites alike.
#pragma once

#include "calibrate/discrepancy_diagnosis.hpp"
#include "surrogate/surrogate_model.hpp"
#include "tests/support/invalid_argument_message.hpp"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <Eigen/Dense>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace demcal::testing::analytic_world {

using namespace demcal::calibrate;
using demcal::surrogate::LeaveOneOut;
using demcal::surrogate::Prediction;
using demcal::surrogate::SurrogateModel;

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

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

inline std::shared_ptr<const SurrogateModel> model(std::vector<std::string> names,
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

using demcal::testing::invalid_argument_message;

// ---------------------------------------------------------------------------------------
// The analytic world

inline const std::vector<std::string> kBaseNames = {"mu_r", "mu_s"};
inline const Eigen::Vector2d kTruth(0.3, 0.5);
inline std::vector<ParameterBounds> base_bounds() {
  return {{"mu_r", 0.05, 0.8}, {"mu_s", 0.2, 0.9}};
}

enum Effect {
  kNone = -1,
  kCohesion = 0,
  kWallFriction = 1,
  kMoisture = 2,
  kOrificeAor = 3,
  kTimeBias = 4
};
inline constexpr int kCandidates = 3;  // kOrificeAor is no candidate: the blind case

struct Spec {
  std::string setup, observable;
  double orifice_m = kNaN, thickness_d = kNaN;
  bool time() const { return observable == "discharge_time_s"; }
  bool sandglass() const { return !std::isnan(orifice_m); }
};

// The last two are held out of every fit: an orifice smaller than any fitted (the model
// must extrapolate) and a container between two fitted thicknesses.
inline std::vector<Spec> specs() {
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
inline constexpr std::size_t kHeldOutCount = 2;
inline const std::vector<TargetKey> kHeldOut = {{"orifice_8mm", "discharge_time_s"},
                                                {"container_3d", "angle_of_repose_deg"}};

inline std::vector<Target> without_held_out(std::vector<Target> all) {
  all.resize(all.size() - kHeldOutCount);
  return all;
}

inline SetupVariables setup_variables() {
  SetupVariables v;
  for (const Spec& s : specs()) {
    if (s.sandglass())
      v[s.setup]["orifice_diameter_m"] = s.orifice_m;
    else
      v[s.setup]["thickness_d"] = s.thickness_d;
  }
  return v;
}

inline double base_mean(const Spec& s, const Eigen::VectorXd& x) {
  const double mu_r = x(0), mu_s = x(1);
  if (s.time())
    return 5.0 * std::pow(s.orifice_m / 0.014, -2.5) *
           (1.0 + 0.4 * mu_r + 1.2 * mu_s + 0.6 * mu_s * mu_s);
  if (s.sandglass())
    return 20.0 + 30.0 * mu_r + 12.0 * mu_s + 8.0 * mu_r * mu_r + 100.0 * (s.orifice_m - 0.014);
  return 22.0 + 28.0 * mu_r + 14.0 * mu_s + 6.0 * mu_r * mu_s + 4.0 / s.thickness_d;
}

// What switching a module on adds, linear in phi.
inline double effect(const Spec& s, const Eigen::VectorXd& x, int e, double phi) {
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

inline CandidateParameter candidate_parameter(int e) {
  switch (e) {
    case kCohesion:
      return {"surface_energy_j_m2", 0.0, 0.0, 0.2};
    case kWallFriction:
      return {"wall_friction_coefficient", 0.0, 0.0, 1.0};
    default:
      return {"moisture_content", 0.0, 0.0, 0.1};
  }
}
inline const char* candidate_name(int e) {
  return e == kCohesion ? "cohesion" : e == kWallFriction ? "wall_friction" : "moisture";
}

struct Sigmas {
  double measured, dem;
};
inline Sigmas sigmas(const Spec& s) {
  if (s.time()) {
    const double t = base_mean(s, kTruth);
    return {0.01 * t, 0.005 * t};
  }
  return {0.5, 0.3};
}

// y_i = truth + N(0, sigma_total), the noise the likelihood assumes.
inline std::vector<double> record(int e, double phi, unsigned long seed) {
  Normal n(seed);
  std::vector<double> y;
  for (const Spec& s : specs()) {
    const Sigmas sg = sigmas(s);
    y.push_back(base_mean(s, kTruth) + effect(s, kTruth, e, phi) +
                std::hypot(sg.measured, sg.dem) * n());
  }
  return y;
}

inline std::vector<Target> base_targets(const std::vector<double>& y) {
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

inline std::vector<Target> extended_targets(int e, const std::vector<double>& y) {
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

inline CalibrationOptions quick_calibration() {
  CalibrationOptions o = diagnosis_calibration_defaults();
  o.multistart_points = 8;
  o.grid_points_per_axis = 41;
  o.grid_points_per_axis_3d = 21;
  return o;
}

inline DiagnosisOptions quick_options() {
  DiagnosisOptions o;
  o.calibration = quick_calibration();
  o.held_out = kHeldOut;
  return o;
}

// The sensitivities a user would measure: a few DEM runs at the base fit with the module
// off and on (4 replicates each, at half the parameter's range), so their standard error
// is sqrt(2 / 4) sigma_dem / (range / 2), and the estimate carries that noise.
inline CandidateModule candidate(int e, const Eigen::VectorXd& theta_hat,
                                 const std::vector<double>& y, Normal& noise) {
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

inline WorldRun diagnose(int e, double phi, unsigned long seed,
                         const DiagnosisOptions& options = quick_options()) {
  WorldRun run;
  run.y = record(e, phi, seed);
  std::vector<Target> all = base_targets(run.y);
  // The user calibrates first, then runs the DEM at the base fit for the sensitivities.
  const CalibrationResult base =
      demcal::calibrate::calibrate(base_bounds(), without_held_out(all), options.calibration);
  Normal noise(seed + 7919);
  std::vector<CandidateModule> candidates;
  for (int k = 0; k < kCandidates; ++k)
    candidates.push_back(candidate(k, base.minima.front().theta, run.y, noise));
  run.d = diagnose_discrepancy(base_bounds(), all, candidates, setup_variables(), options);
  return run;
}

inline constexpr double kCohesionTruth = 0.05;
inline constexpr double kWallTruth = 0.5;

}  // namespace demcal::testing::analytic_world
