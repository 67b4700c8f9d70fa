// Regression on fitted models: from the checked-in design table of
// studies/sandglass-calibration (doe.csv, 50 DEM runs), the surrogates' fitted
// coefficients and hyperparameters, and the calibration they lead to, equal
// the checked-in references in tests/data/regression/. These guard the fitted
// model against unintended change: a change to the fit, the optimizer's
// settings or the calibration shows up here with the number that moved.
//
// Tolerances: polynomial coefficients are a linear solve (1e-9 relative);
// Gaussian-process hyperparameters come from a bounded multi-start optimizer
// whose last digits depend on floating-point order (1e-4 relative, far below
// any change that matters); calibration results inherit that (1e-3).
// After an intended change, regenerate the references with
//   DEMCAL_UPDATE_REFERENCES=1 ./build/tests/demcal_unit_tests --gtest_filter='RegressionOnFittedModels.*'
// and say why in the commit.

#include "calibrate/calibration.hpp"
#include "config/doe_csv.hpp"
#include "surrogate/surrogate_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace demcal {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = DEMCAL_SOURCE_DIR;

surrogate::ReplicatedData data(const config::DoeCsv& t, const std::string& observable) {
  surrogate::ReplicatedData d;
  d.input_names = t.parameter_names;
  d.lower = {0.05, 0.2};  // studies/sandglass-calibration/study.toml [design]
  d.upper = {0.6, 0.9};
  d.output_name = observable;
  const int k = t.observable_index(observable);
  d.x.resize(static_cast<Eigen::Index>(t.rows.size()), 2);
  d.y.resize(static_cast<Eigen::Index>(t.rows.size()));
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    d.x(static_cast<Eigen::Index>(i), 0) = t.rows[i].parameters[0];
    d.x(static_cast<Eigen::Index>(i), 1) = t.rows[i].parameters[1];
    d.y(static_cast<Eigen::Index>(i)) = t.rows[i].observables[static_cast<std::size_t>(k)];
    d.group.push_back(t.rows[i].point);
  }
  return d;
}

// The study's surrogate ([surrogate] of its study.toml).
surrogate::SurrogateSpec study_spec() {
  surrogate::SurrogateSpec s;
  s.model = "gaussian_process";
  s.kernel = surrogate::CovarianceKernel::matern52;
  s.mean = surrogate::MeanFunction::linear;
  s.nugget = "replicates";
  return s;
}

nlohmann::json current() {
  const auto t = config::read_doe_csv(kSource / "studies/sandglass-calibration/doe.csv");
  nlohmann::json j;
  std::vector<calibrate::Target> targets;
  for (const std::string name : {"angle_of_repose_deg", "discharge_time_s"}) {
    const auto d = data(t, name);
    const auto gp = surrogate::fit_surrogate(d, study_spec());
    const auto& g = dynamic_cast<const surrogate::GaussianProcess&>(*gp.model);
    const auto h = g.hyperparameters();
    j[name]["gp"] = {{"length_scales", h.length_scales},
                     {"signal_variance", h.signal_variance},
                     {"log_marginal_likelihood", g.log_marginal_likelihood()},
                     {"replicate_sd", gp.scatter.sd},
                     {"loo_rmse", gp.validation.rmse}};
    auto ps = study_spec();
    ps.model = "polynomial";
    ps.degree = 2;
    const auto poly = surrogate::fit_surrogate(d, ps);
    const auto& p = dynamic_cast<const surrogate::PolynomialSurface&>(*poly.model);
    const Eigen::VectorXd cv = p.coefficients(), sev = p.standard_errors();
    const std::vector<double> c(cv.data(), cv.data() + cv.size()), se(sev.data(), sev.data() + sev.size());
    j[name]["polynomial_degree_2"] = {{"terms", p.term_names()}, {"coefficients", c}, {"standard_errors", se}};
    calibrate::Target target;
    target.setup = "sandglass";
    target.observable = name;
    target.sigma_dem = gp.scatter.sd;
    target.model = gp.model;
    targets.push_back(target);
  }
  // A calibration against the surrogates' own prediction at (0.25, 0.45):
  // recordings inside the model's range, so the regions are bounded.
  Eigen::MatrixXd at(1, 2);
  at << 0.25, 0.45;
  targets[0].measured = targets[0].model->predict_mean(at)(0);
  targets[0].sigma_measured = 0.5;
  targets[1].measured = targets[1].model->predict_mean(at)(0);
  targets[1].sigma_measured = 0.01;
  calibrate::CalibrationOptions o;
  o.mcmc_samples = 0;  // the regression is on the deterministic part
  o.grid_points_per_axis = 81;
  const std::vector<calibrate::ParameterBounds> b = {{"mu_r", 0.05, 0.6}, {"mu_s", 0.2, 0.9}};
  const auto joint = calibrate::calibrate(b, targets, o);
  const auto alone = calibrate::calibrate(b, {targets[0]}, o);
  j["calibration"] = {{"best", {joint.minima.at(0).theta(0), joint.minima.at(0).theta(1)}},
                      {"area_joint", joint.region.area},
                      {"area_aor_alone", alone.region.area}};
  return j;
}

void expect_close(const nlohmann::json& ref, const nlohmann::json& now, double rel, const std::string& path) {
  if (ref.is_number()) {
    const double a = ref.get<double>(), b = now.get<double>();
    EXPECT_NEAR(b, a, rel * std::max(1.0, std::abs(a))) << path;
  } else if (ref.is_array()) {
    ASSERT_EQ(ref.size(), now.size()) << path;
    for (std::size_t i = 0; i < ref.size(); ++i) expect_close(ref[i], now[i], rel, path + "[" + std::to_string(i) + "]");
  } else if (ref.is_object()) {
    for (const auto& [k, v] : ref.items()) {
      ASSERT_TRUE(now.contains(k)) << path << "." << k;
      const double r = k == "polynomial_degree_2" ? 1e-9 : k == "calibration" ? 1e-3 : rel;
      expect_close(v, now[k], r, path + "." + k);
    }
  } else {
    EXPECT_EQ(ref, now) << path;
  }
}

TEST(RegressionOnFittedModels, SandglassCalibrationSurrogatesAndCalibrationMatchTheReferences) {
  const fs::path ref_file = kSource / "tests/data/regression/sandglass_calibration_fit.json";
  const nlohmann::json now = current();
  if (std::getenv("DEMCAL_UPDATE_REFERENCES")) {
    // Regenerating: write the references; the comparison below is then with
    // themselves, but the science checks after it still have to hold.
    std::ofstream(ref_file) << now.dump(1) << "\n";
  }
  std::ifstream in(ref_file);
  ASSERT_TRUE(in) << ref_file << " is missing; see the comment at the top of this file";
  const auto ref = nlohmann::json::parse(in);
  expect_close(ref, now, 1e-4, "");
  // And what the references say, so a regenerated file cannot quietly lose it:
  // the stated point is recovered, and the discharge time narrows the region
  // AoR alone leaves. In this quick slice model it narrows it by only about
  // 1.6x (0.226 vs 0.144): AoR and time rise together with both frictions
  // here, so their iso-lines cross at a shallow angle (studies/sandglass-recovery/README.md;
  // walls lined with the sand make them cross: studies/sandglass-recovery-lined).
  EXPECT_NEAR(now["calibration"]["best"][0].get<double>(), 0.25, 1e-3);
  EXPECT_NEAR(now["calibration"]["best"][1].get<double>(), 0.45, 1e-3);
  EXPECT_GT(now["calibration"]["area_aor_alone"].get<double>(), 1.3 * now["calibration"]["area_joint"].get<double>());
}

}  // namespace
}  // namespace demcal
