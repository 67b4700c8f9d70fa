// The inverse problem on analytic "surrogates" whose answers are known: recovery of a
// known (mu_r, mu_s), rank deficiency and the open region of AoR alone, coverage of the
// likelihood-ratio region over noisy recordings, distinct minima, the Gauss-Newton
// covariance and the MCMC posterior against a linear-Gaussian closed form, and input checks.
#include "calibrate/calibration.hpp"
#include "tests/support/invalid_argument_message.hpp"

#include <gtest/gtest.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace {

using namespace demcal::calibrate;
using demcal::surrogate::LeaveOneOut;
using demcal::surrogate::Prediction;
using demcal::surrogate::SurrogateModel;

// A surrogate given by formulas: mean, its gradient, and (optionally) a variance.
class AnalyticSurrogate final : public SurrogateModel {
 public:
  using Function = std::function<double(const Eigen::VectorXd&)>;
  using Gradient = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

  AnalyticSurrogate(std::vector<std::string> names, Function mean, Gradient gradient,
                    Function variance = {})
      : names_(std::move(names)), mean_(std::move(mean)), gradient_(std::move(gradient)),
        variance_(std::move(variance)) {}

  std::string kind() const override { return "analytic"; }
  std::string description() const override { return "analytic test function"; }
  std::size_t input_dimension() const override { return names_.size(); }
  const std::vector<std::string>& input_names() const override { return names_; }

  Prediction predict(const Eigen::MatrixXd& points) const override {
    check(points);
    Prediction p{Eigen::VectorXd(points.rows()), Eigen::VectorXd::Zero(points.rows())};
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      const Eigen::VectorXd x = points.row(i).transpose();
      p.mean(i) = mean_(x);
      if (variance_) p.variance(i) = variance_(x);
    }
    return p;
  }
  Eigen::VectorXd predict_mean(const Eigen::MatrixXd& points) const override {
    return predict(points).mean;
  }
  Eigen::MatrixXd gradient(const Eigen::MatrixXd& points) const override {
    check(points);
    Eigen::MatrixXd g(points.rows(), points.cols());
    for (Eigen::Index i = 0; i < points.rows(); ++i) g.row(i) = gradient_(points.row(i).transpose()).transpose();
    return g;
  }
  LeaveOneOut leave_one_out() const override { return {}; }

 private:
  void check(const Eigen::MatrixXd& points) const {
    demcal::surrogate::detail::check_points("analytic", points, static_cast<Eigen::Index>(names_.size()));
  }
  std::vector<std::string> names_;
  Function mean_;
  Gradient gradient_;
  Function variance_;
};

const std::vector<std::string> kNames = {"mu_r", "mu_s"};

// AoR-like: rises with both frictions, mostly with rolling friction, mildly curved.
double aor(const Eigen::VectorXd& x) {
  return 20.0 + 25.0 * x(0) + 15.0 * x(1) + 10.0 * x(0) * x(0) + 5.0 * x(0) * x(1);
}
Eigen::VectorXd aor_gradient(const Eigen::VectorXd& x) {
  return Eigen::Vector2d(25.0 + 20.0 * x(0) + 5.0 * x(1), 15.0 + 5.0 * x(0));
}
// Discharge-time-like: mostly sliding friction, so its gradient points elsewhere.
double discharge(const Eigen::VectorXd& x) { return 4.0 + 1.5 * x(0) + 6.0 * x(1) + 4.0 * x(1) * x(1); }
Eigen::VectorXd discharge_gradient(const Eigen::VectorXd& x) {
  return Eigen::Vector2d(1.5, 6.0 + 8.0 * x(1));
}

std::shared_ptr<const SurrogateModel> model(AnalyticSurrogate::Function f, AnalyticSurrogate::Gradient g,
                                            AnalyticSurrogate::Function v = {},
                                            std::vector<std::string> names = kNames) {
  return std::make_shared<AnalyticSurrogate>(std::move(names), std::move(f), std::move(g), std::move(v));
}

const Eigen::Vector2d kTruth(0.3, 0.52);

std::vector<ParameterBounds> paper_bounds() { return {{"mu_r", 0.05, 0.8}, {"mu_s", 0.2, 0.9}}; }

Target aor_target(double measured) {
  return {"sandglass", "angle_of_repose_deg", measured, 0.5, 0.3, model(aor, aor_gradient), true};
}
Target discharge_target(double measured) {
  return {"sandglass", "discharge_time_s", measured, 0.15, 0.1, model(discharge, discharge_gradient), true};
}

CalibrationOptions quick_options() {
  CalibrationOptions o;
  o.mcmc_samples = 4000;
  o.mcmc_burn_in = 1000;
  return o;
}

using demcal::testing::invalid_argument_message;

// Appends rather than writing "y" + std::to_string(i): GCC 12 raises a false -Wrestrict
// on operator+(const char*, std::string&&).
std::string indexed(const char* prefix, int i) {
  std::string s = prefix;
  s += std::to_string(i);
  return s;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

bool any_note_contains(const CalibrationResult& r, const std::string& part) {
  for (const auto& n : r.notes)
    if (contains(n, part)) return true;
  return false;
}

// Gaussian draws from GSL's MT19937: the same on every platform.
struct Normal {
  explicit Normal(unsigned long seed) : rng(gsl_rng_alloc(gsl_rng_mt19937)) { gsl_rng_set(rng, seed); }
  ~Normal() { gsl_rng_free(rng); }
  Normal(const Normal&) = delete;
  Normal& operator=(const Normal&) = delete;
  double operator()() { return gsl_ran_gaussian(rng, 1.0); }
  gsl_rng* rng;
};

// ---------------------------------------------------------------------------------------
// Recovery and identifiability

TEST(Calibration, RecoversKnownFrictionFromAorAndDischargeTime) {
  const auto result = calibrate(paper_bounds(), {aor_target(aor(kTruth)), discharge_target(discharge(kTruth))},
                                quick_options());
  ASSERT_FALSE(result.minima.empty());
  const Minimum& best = result.minima.front();
  EXPECT_NEAR(best.theta(0), kTruth(0), 1e-6);
  EXPECT_NEAR(best.theta(1), kTruth(1), 1e-6);
  EXPECT_LT(best.chi_squared, 1e-12);
  EXPECT_EQ(result.minima.size(), 1u) << "a closed problem has one minimum";
  EXPECT_FALSE(best.rank_deficient);
  EXPECT_TRUE(best.covariance_available);
  EXPECT_FALSE(best.at_bound);
  EXPECT_TRUE(result.identified[0]);
  EXPECT_TRUE(result.identified[1]);
  EXPECT_TRUE(result.region.resolved);
  EXPECT_TRUE(result.region.extent[0].identified());
  EXPECT_TRUE(result.region.extent[1].identified());
  EXPECT_LE(result.region.extent[0].lower, kTruth(0));
  EXPECT_GE(result.region.extent[0].upper, kTruth(0));
  // Two targets, two parameters: nothing left to test the model with.
  EXPECT_EQ(result.fit.degrees_of_freedom, 0);
  EXPECT_TRUE(std::isnan(result.fit.p_value));
  EXPECT_TRUE(any_note_contains(result, "no degrees of freedom"));
  EXPECT_FALSE(best.solver_report.empty());
}

TEST(Calibration, AorAloneIsRankDeficientAlongItsIsoLine) {
  const auto alone = calibrate(paper_bounds(), {aor_target(aor(kTruth))}, quick_options());
  const Minimum& best = alone.minima.front();
  EXPECT_LT(best.chi_squared, 1e-12);
  EXPECT_NEAR(aor(best.theta), aor(kTruth), 1e-6) << "the minimum lies on the measured iso-line";
  // A 1 x 2 Jacobian: always rank deficient, however well conditioned its one row is.
  EXPECT_TRUE(best.rank_deficient);
  EXPECT_FALSE(best.covariance_available);
  EXPECT_TRUE(std::isnan(best.covariance(0, 0)));
  EXPECT_TRUE(std::isnan(best.standard_errors[1]));
  ASSERT_EQ(best.singular_values.size(), 2);
  EXPECT_GT(best.singular_values(0), 0.0);
  EXPECT_EQ(best.singular_values(1), 0.0);
  const Eigen::VectorXd g = aor_gradient(best.theta).normalized();
  EXPECT_NEAR(best.weakest_direction.norm(), 1.0, 1e-12);
  EXPECT_LT(std::abs(best.weakest_direction.dot(g)), 1e-6) << "the weak direction is the iso-line tangent";
  // A valley of equally good points is one minimum, not one per start.
  EXPECT_EQ(alone.minima.size(), 1u);
  EXPECT_GT(best.starts, 1);

  // The region runs along the iso-line and across the box.
  const Eigen::Vector2d grad = aor_gradient(kTruth);
  const Eigen::Vector2d tangent = Eigen::Vector2d(-grad(1), grad(0)).normalized();
  EXPECT_GT(std::abs(alone.region.principal_axis.dot(tangent)), 0.99);
  EXPECT_TRUE(alone.region.extent[1].touches_lower_bound);
  EXPECT_TRUE(alone.region.extent[1].touches_upper_bound);
  EXPECT_FALSE(alone.identified[0]) << "mu_r moves along the weak direction";
  EXPECT_FALSE(alone.identified[1]);
  EXPECT_TRUE(any_note_contains(alone, "rank deficient"));
  EXPECT_TRUE(any_note_contains(alone, "mu_s is not identified"));

  // The discharge time closes the region.
  const auto both = calibrate(paper_bounds(), {aor_target(aor(kTruth)), discharge_target(discharge(kTruth))},
                              quick_options());
  const RegionComparison c = compare_regions(alone, both);
  EXPECT_GE(c.ratio, 3.0) << "area alone " << c.area_a << ", with discharge time " << c.area_b;
  EXPECT_TRUE(c.same_grid);
  // The closed region lies inside the open one.
  EXPECT_GT(c.overlap_fraction_b, 0.95);
  EXPECT_GT(c.extent_ratio[1], 3.0);
  EXPECT_GT(c.credible_ratio, 3.0);
}

TEST(Calibration, RegionGridHoldsPredictionsInTheDocumentedLayout) {
  CalibrationOptions o = quick_options();
  o.grid_points_per_axis = 31;
  o.mcmc_samples = 0;
  const auto r = calibrate(paper_bounds(), {aor_target(aor(kTruth)), discharge_target(discharge(kTruth))}, o);
  ASSERT_TRUE(r.region.available);
  ASSERT_EQ(r.region.axes.size(), 2u);
  ASSERT_EQ(r.region.chi_squared.size(), 31u * 31u);
  ASSERT_EQ(r.region.predicted_mean.size(), 2u);
  EXPECT_DOUBLE_EQ(r.region.axes[0].front(), 0.05);
  EXPECT_DOUBLE_EQ(r.region.axes[1].back(), 0.9);
  // Parameter 0 varies fastest.
  const std::size_t i0 = 7, i1 = 19, k = i0 + 31 * i1;
  const Eigen::Vector2d x(r.region.axes[0][i0], r.region.axes[1][i1]);
  EXPECT_NEAR(r.region.predicted_mean[0][k], aor(x), 1e-12);
  EXPECT_NEAR(r.region.predicted_mean[1][k], discharge(x), 1e-12);
  const double r0 = (aor(kTruth) - aor(x)) / std::sqrt(0.5 * 0.5 + 0.3 * 0.3);
  const double r1 = (discharge(kTruth) - discharge(x)) / std::sqrt(0.15 * 0.15 + 0.1 * 0.1);
  EXPECT_NEAR(r.region.chi_squared[k], r0 * r0 + r1 * r1, 1e-9);
  EXPECT_NEAR(r.region.threshold, r.region.chi_squared_min + gsl_cdf_chisq_Pinv(0.95, 2), 1e-12);
  // The cell measures add up to the box.
  double box = 0.0;
  for (double w : grid_cell_measures(r.region.axes)) box += w;
  EXPECT_NEAR(box, 0.75 * 0.7, 1e-12);
  EXPECT_FALSE(r.posterior.available);

  const nlohmann::json j = r.to_json();
  EXPECT_EQ(j["region"]["chi_squared"].size(), 31u * 31u);
  EXPECT_EQ(j["region"]["predicted_mean"][1]["observable"], "discharge_time_s");
  EXPECT_TRUE(j["goodness_of_fit"]["p_value"].is_null());
  EXPECT_EQ(j["minima"].size(), r.minima.size());
  EXPECT_FALSE(r.to_json(false)["region"].contains("chi_squared"));
}

// ---------------------------------------------------------------------------------------
// Coverage: the 95 % region holds the truth in about 95 % of noisy recordings.

TEST(Calibration, LikelihoodRatioRegionCoversTheTruth) {
  // Three targets for two parameters, so that chi^2_min is not 0 and the statement tested
  // is Wilks': chi^2(truth) - chi^2_min ~ chi^2_2. A constant surrogate variance, which the
  // stated sigma_total includes.
  const auto aor_model = model(aor, aor_gradient, [](const Eigen::VectorXd&) { return 0.2 * 0.2; });
  const auto time_model = model(discharge, discharge_gradient, [](const Eigen::VectorXd&) { return 0.05 * 0.05; });
  const auto pile = [](const Eigen::VectorXd& x) { return 18.0 + 20.0 * x(0) + 20.0 * x(1); };
  const auto pile_model = model(pile, [](const Eigen::VectorXd&) { return Eigen::VectorXd(Eigen::Vector2d(20.0, 20.0)); });
  const double s_aor = std::sqrt(0.5 * 0.5 + 0.3 * 0.3 + 0.2 * 0.2);
  const double s_time = std::sqrt(0.15 * 0.15 + 0.1 * 0.1 + 0.05 * 0.05);
  const double s_pile = 0.8;
  const double delta = gsl_cdf_chisq_Pinv(0.95, 2);
  CalibrationOptions o;
  o.multistart_points = 2;
  o.grid_points_per_axis = 61;
  Normal normal(2024);
  const int recordings = 1000;
  int covered = 0, grid_checked = 0;
  double chi2_min_sum = 0.0;
  for (int rec = 0; rec < recordings; ++rec) {
    const double m_aor = aor(kTruth) + s_aor * normal();
    const double m_time = discharge(kTruth) + s_time * normal();
    const double m_pile = pile(kTruth) + s_pile * normal();
    const CalibrationProblem problem(paper_bounds(),
                                     {{"sandglass", "angle_of_repose_deg", m_aor, 0.5, 0.3, aor_model, true},
                                      {"sandglass", "discharge_time_s", m_time, 0.15, 0.1, time_model, true},
                                      {"pile", "angle_of_repose_deg", m_pile, s_pile, 0.0, pile_model, true}});
    const auto minima = find_minima(problem, o);
    chi2_min_sum += minima.front().chi_squared;
    const double chi2_truth = problem.chi_squared(kTruth);
    const bool inside = chi2_truth - minima.front().chi_squared <= delta;
    covered += inside ? 1 : 0;
    if (rec < 5) {
      // The same statement on the grid, away from the region's edge (where the nearest
      // node may fall on the other side).
      const LikelihoodRegion region = likelihood_region(problem, minima.front().chi_squared, o);
      EXPECT_NEAR(region.threshold, minima.front().chi_squared + delta, 1e-9)
          << "the optimizer found a point at least as good as every grid node";
      EXPECT_EQ(region_contains(problem, region, kTruth), inside);
      if (std::abs(chi2_truth - region.threshold) > 1.0) {
        const auto nearest = [&](int j) {
          const auto& a = region.axes[static_cast<std::size_t>(j)];
          return static_cast<std::size_t>(std::lround((kTruth(j) - a.front()) / (a[1] - a[0])));
        };
        EXPECT_EQ(region.inside[nearest(0) + 61 * nearest(1)], inside) << "recording " << rec;
        ++grid_checked;
      }
    }
  }
  // Binomial sd at 1000 recordings: 0.007; the bounds are 3.5 sd.
  const double coverage = static_cast<double>(covered) / recordings;
  EXPECT_GE(coverage, 0.925);
  EXPECT_LE(coverage, 0.975);
  EXPECT_GE(grid_checked, 3);
  // chi^2_min ~ chi^2 with 3 - 2 = 1 degree of freedom: mean 1, sd of the mean 0.045.
  EXPECT_NEAR(chi2_min_sum / recordings, 1.0, 0.15);
}

// ---------------------------------------------------------------------------------------
// Multi-start

TEST(CalibrationProblem, MultiStartFindsTwoSeparatedMinima) {
  // A double well in mu_r (zero at 0.3 and 0.7), mu_s fixed by a second target, and a
  // weak third target that slightly prefers mu_r = 0.3.
  const auto well = model(
      [](const Eigen::VectorXd& x) { return 100.0 * std::pow(x(0) - 0.3, 2) * std::pow(x(0) - 0.7, 2); },
      [](const Eigen::VectorXd& x) {
        const double a = x(0) - 0.3, b = x(0) - 0.7;
        return Eigen::Vector2d(200.0 * a * b * (a + b), 0.0);
      });
  const auto linear_s = model([](const Eigen::VectorXd& x) { return 5.0 + 10.0 * x(1); },
                              [](const Eigen::VectorXd&) { return Eigen::Vector2d(0.0, 10.0); });
  const auto linear_r = model([](const Eigen::VectorXd& x) { return x(0); },
                              [](const Eigen::VectorXd&) { return Eigen::Vector2d(1.0, 0.0); });
  const CalibrationProblem problem({{"mu_r", 0.0, 1.0}, {"mu_s", 0.0, 1.0}},
                                   {{"pile", "well", 0.0, 0.01, 0.0, well, true},
                                    {"sandglass", "time", 11.0, 0.05, 0.0, linear_s, true},
                                    {"pile", "hint", 0.3, 1.0, 0.0, linear_r, true}});
  const auto minima = find_minima(problem, CalibrationOptions{});
  ASSERT_EQ(minima.size(), 2u);
  EXPECT_NEAR(minima[0].theta(0), 0.3, 1e-4);
  EXPECT_NEAR(minima[1].theta(0), 0.7, 0.01);  // the hint pulls it off the flat zero
  EXPECT_NEAR(minima[0].theta(1), 0.6, 1e-6);
  EXPECT_NEAR(minima[1].theta(1), 0.6, 1e-6);
  EXPECT_LT(minima[0].chi_squared, 1e-8);
  // The hint's residual (0.7 - 0.3) / 1 at the second minimum.
  EXPECT_NEAR(minima[1].chi_squared, 0.16, 0.01);
  EXPECT_EQ(minima[0].starts + minima[1].starts, 17);
  EXPECT_GT(minima[1].starts, 0);

  // The report names both.
  CalibrationOptions o = quick_options();
  o.mcmc_samples = 0;
  const auto r = calibrate(problem.parameters(), problem.targets(), o);
  EXPECT_EQ(r.minima.size(), 2u);
  EXPECT_TRUE(any_note_contains(r, "2 distinct minima"));
  EXPECT_TRUE(any_note_contains(r, "cannot choose between them"));
}

TEST(CalibrationProblem, MinimumOnABoundIsFlagged) {
  // Measured AoR above anything the box can reach: the best point is the upper corner.
  const CalibrationProblem problem(paper_bounds(), {aor_target(100.0)});
  const auto minima = find_minima(problem, CalibrationOptions{});
  EXPECT_TRUE(minima.front().at_bound);
  EXPECT_NEAR(minima.front().theta(0), 0.8, 1e-9);
  EXPECT_NEAR(minima.front().theta(1), 0.9, 1e-9);
}

TEST(CalibrationProblem, JacobianIncludesTheVarianceTerm) {
  // A surrogate whose variance grows with mu_s: d r / d theta has a variance part.
  const auto m = model(aor, aor_gradient, [](const Eigen::VectorXd& x) { return 0.5 + 2.0 * x(1) * x(1) + x(0); });
  const CalibrationProblem problem(paper_bounds(), {{"pile", "angle_of_repose_deg", 30.0, 0.5, 0.2, m, true}});
  const Eigen::Vector2d theta(0.4, 0.6);
  Eigen::MatrixXd j;
  problem.residuals(theta, &j);
  for (int k = 0; k < 2; ++k) {
    const double h = 1e-6;
    Eigen::Vector2d a = theta, b = theta;
    a(k) += h;
    b(k) -= h;
    const double numeric = (problem.residuals(a)(0) - problem.residuals(b)(0)) / (2 * h);
    EXPECT_NEAR(j(0, k), numeric, 1e-6 * std::abs(numeric) + 1e-8) << "parameter " << k;
  }
  // log posterior = -chi^2/2 - log(sigma_total^2)/2 inside the box, -inf outside.
  const double s2 = 0.25 + 0.04 + 0.5 + 2.0 * 0.36 + 0.4;
  const double r = (30.0 - aor(theta)) / std::sqrt(s2);
  EXPECT_NEAR(problem.log_posterior(theta), -0.5 * r * r - 0.5 * std::log(s2), 1e-12);
  EXPECT_TRUE(std::isinf(problem.log_posterior(Eigen::Vector2d(0.9, 0.5))));
}

// ---------------------------------------------------------------------------------------
// Linear-Gaussian: Gauss-Newton covariance, region and posterior have closed forms.

struct LinearCase {
  Eigen::Matrix2d a;  // rows: gradients of the two targets
  Eigen::Vector2d sigma;
  Eigen::Vector2d truth{0.3, 0.5};
  Eigen::Matrix2d covariance() const {
    const Eigen::Matrix2d j = sigma.cwiseInverse().asDiagonal() * a;
    return (j.transpose() * j).inverse();
  }
  std::vector<Target> targets() const {
    std::vector<Target> t;
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector2d g = a.row(i).transpose();
      const double c = 10.0 * (i + 1);
      auto f = model([g, c](const Eigen::VectorXd& x) { return c + g.dot(x); },
                     [g](const Eigen::VectorXd&) { return Eigen::VectorXd(g); });
      t.push_back({"setup", indexed("y", i), c + g.dot(truth), sigma(i), 0.0, f, true});
    }
    return t;
  }
  static LinearCase standard() {
    LinearCase c;
    c.a << 30.0, 10.0, 2.0, 8.0;
    c.sigma << 0.5, 0.2;
    return c;
  }
};

std::vector<ParameterBounds> linear_bounds() { return {{"mu_r", 0.0, 0.6}, {"mu_s", 0.2, 0.8}}; }

TEST(ConfidenceRegion, GaussNewtonCovarianceMatchesLinearTheory) {
  const LinearCase lc = LinearCase::standard();
  const CalibrationProblem problem(linear_bounds(), lc.targets());
  const auto g = gauss_newton_uncertainty(problem, lc.truth, CalibrationOptions{});
  ASSERT_TRUE(g.covariance_available);
  EXPECT_FALSE(g.rank_deficient);
  const Eigen::Matrix2d expected = lc.covariance();
  EXPECT_LT((g.covariance - expected).norm(), 1e-9 * expected.norm());
  EXPECT_NEAR(g.standard_errors[0], std::sqrt(expected(0, 0)), 1e-9);
  // Singular values of the bound-scaled Jacobian.
  const Eigen::Matrix2d ju = lc.sigma.cwiseInverse().asDiagonal() * lc.a * Eigen::Vector2d(0.6, 0.6).asDiagonal();
  const Eigen::JacobiSVD<Eigen::Matrix2d> svd(ju);
  EXPECT_NEAR(g.singular_values(0), svd.singularValues()(0), 1e-6);
  EXPECT_NEAR(g.singular_values(1), svd.singularValues()(1), 1e-6);
}

TEST(ConfidenceRegion, ParallelSensitivitiesAreRankDeficient) {
  // The second target sees only the same combination of parameters as the first.
  LinearCase lc = LinearCase::standard();
  lc.a.row(1) = 0.25 * lc.a.row(0);
  const CalibrationProblem problem(linear_bounds(), lc.targets());
  const auto g = gauss_newton_uncertainty(problem, lc.truth, CalibrationOptions{});
  EXPECT_TRUE(g.rank_deficient);
  EXPECT_FALSE(g.covariance_available);
  EXPECT_LT(std::abs(g.weakest_direction.dot(lc.a.row(0).transpose().normalized())), 1e-6);
  // Independent sensitivities: full rank.
  lc.a.row(1) = Eigen::RowVector2d(2.0, 8.0);
  const CalibrationProblem ok(linear_bounds(), lc.targets());
  EXPECT_FALSE(gauss_newton_uncertainty(ok, lc.truth, CalibrationOptions{}).rank_deficient);
}

TEST(ConfidenceRegion, AreaMatchesTheAnalyticEllipse) {
  const LinearCase lc = LinearCase::standard();
  const CalibrationProblem problem(linear_bounds(), lc.targets());
  const LikelihoodRegion region = likelihood_region(problem, 0.0, CalibrationOptions{});
  const double q = gsl_cdf_chisq_Pinv(0.95, 2);
  const double ellipse = std::numbers::pi * q * std::sqrt(lc.covariance().determinant());
  EXPECT_NEAR(region.area / ellipse, 1.0, 0.03);
  EXPECT_TRUE(region.resolved);
  // Extent: the ellipse's projection, +/- sqrt(q C_jj).
  for (int j = 0; j < 2; ++j) {
    const double half = std::sqrt(q * lc.covariance()(j, j));
    const double h = 0.6 / 120.0;
    EXPECT_NEAR(region.extent[static_cast<std::size_t>(j)].lower, lc.truth(j) - half, h);
    EXPECT_NEAR(region.extent[static_cast<std::size_t>(j)].upper, lc.truth(j) + half, h);
  }
}

TEST(ConfidenceRegion, OneAndThreeParameters) {
  // One parameter: the region is an interval, +/- sqrt(chi2_1) standard errors.
  const auto line = model([](const Eigen::VectorXd& x) { return 2.0 + 10.0 * x(0); },
                          [](const Eigen::VectorXd&) { return Eigen::VectorXd::Constant(1, 10.0); }, {},
                          {"mu_r"});
  CalibrationOptions o = quick_options();
  const auto r1 = calibrate({{"mu_r", 0.0, 1.0}}, {{"pile", "y", 5.0, 0.1, 0.0, line, true}}, o);
  EXPECT_NEAR(r1.minima.front().theta(0), 0.3, 1e-9);
  EXPECT_NEAR(r1.region.area, 2.0 * std::sqrt(gsl_cdf_chisq_Pinv(0.95, 1)) * 0.01, 2.0 / 120.0);
  EXPECT_NEAR(r1.posterior.marginals[0].sd, 0.01, 0.001);

  // Three parameters: the grid is a volume; compare with the analytic ellipsoid.
  const std::vector<std::string> names3 = {"a", "b", "c"};
  const Eigen::Matrix3d a = (Eigen::Matrix3d() << 10, 2, 1, 1, 8, 3, 2, 1, 12).finished();
  const double sigma = 0.2;
  std::vector<Target> targets;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d g = a.row(i).transpose();
    targets.push_back({"s", indexed("y", i), g.dot(Eigen::Vector3d(0.5, 0.5, 0.5)), sigma, 0.0,
                       model([g](const Eigen::VectorXd& x) { return g.dot(x); },
                             [g](const Eigen::VectorXd&) { return Eigen::VectorXd(g); }, {}, names3),
                       true});
  }
  o.mcmc_samples = 0;
  const auto r3 = calibrate({{"a", 0.3, 0.7}, {"b", 0.3, 0.7}, {"c", 0.3, 0.7}}, targets, o);
  ASSERT_TRUE(r3.region.available);
  const Eigen::Matrix3d c = ((a / sigma).transpose() * (a / sigma)).inverse();
  const double q = gsl_cdf_chisq_Pinv(0.95, 3);
  const double ellipsoid = 4.0 / 3.0 * std::numbers::pi * std::pow(q, 1.5) * std::sqrt(c.determinant());
  EXPECT_NEAR(r3.region.area / ellipsoid, 1.0, 0.1);
  EXPECT_TRUE(r3.identified[0] && r3.identified[1] && r3.identified[2]);

  // Four parameters: no grid; identification from the posterior.
  const std::vector<std::string> names4 = {"a", "b", "c", "d"};
  std::vector<Target> t4;
  for (int i = 0; i < 4; ++i)
    t4.push_back({"s", indexed("y", i), 0.5, 0.05, 0.0,
                  model([i](const Eigen::VectorXd& x) { return x(i); },
                        [i](const Eigen::VectorXd&) { Eigen::VectorXd g = Eigen::VectorXd::Zero(4); g(i) = 1; return g; },
                        {}, names4),
                  true});
  t4.pop_back();  // d has no target: it stays free
  o.mcmc_samples = 4000;
  const auto r4 = calibrate({{"a", 0, 1}, {"b", 0, 1}, {"c", 0, 1}, {"d", 0, 1}}, t4, o);
  EXPECT_FALSE(r4.region.available);
  EXPECT_TRUE(r4.identified[0]);
  EXPECT_FALSE(r4.identified[3]);
  EXPECT_TRUE(r4.minima.front().rank_deficient);
}

TEST(PosteriorSampling, MatchesTheLinearGaussianPosterior) {
  const LinearCase lc = LinearCase::standard();
  CalibrationOptions o;  // the defaults: 20000 samples in 2 chains
  const auto r = calibrate(linear_bounds(), lc.targets(), o);
  ASSERT_TRUE(r.posterior.available);
  const Eigen::Matrix2d c = lc.covariance();
  for (int j = 0; j < 2; ++j) {
    const double sd = std::sqrt(c(j, j));
    const MarginalPosterior& m = r.posterior.marginals[static_cast<std::size_t>(j)];
    EXPECT_NEAR(m.mean, lc.truth(j), 0.1 * sd) << m.name;
    EXPECT_NEAR(m.sd / sd, 1.0, 0.05) << m.name;
    EXPECT_NEAR(m.median, lc.truth(j), 0.1 * sd);
    EXPECT_NEAR(m.upper - m.lower, 2.0 * 1.959964 * sd, 0.1 * sd);
    EXPECT_GT(m.effective_sample_size, 1000.0);
    EXPECT_LT(m.r_hat, 1.05);
    double integral = 0.0;
    for (std::size_t b = 0; b < m.histogram_density.size(); ++b)
      integral += m.histogram_density[b] * (m.histogram_edges[b + 1] - m.histogram_edges[b]);
    EXPECT_NEAR(integral, 1.0, 1e-9);
  }
  const double rho = c(0, 1) / std::sqrt(c(0, 0) * c(1, 1));
  const double rho_mc = r.posterior.covariance(0, 1) /
                        std::sqrt(r.posterior.covariance(0, 0) * r.posterior.covariance(1, 1));
  EXPECT_NEAR(rho_mc, rho, 0.05);
  EXPECT_GT(r.posterior.acceptance_rate, 0.15);
  EXPECT_LT(r.posterior.acceptance_rate, 0.6);
  // With a Gaussian posterior the HPD region is the likelihood-ratio ellipse.
  ASSERT_TRUE(r.posterior.credible_region.available);
  EXPECT_NEAR(r.posterior.credible_region.area / r.region.area, 1.0, 0.1);
  EXPECT_EQ(r.posterior.samples.rows(), 20000);
}

TEST(PosteriorSampling, DeterministicForASeed) {
  const LinearCase lc = LinearCase::standard();
  CalibrationOptions o = quick_options();
  o.grid_points_per_axis = 21;
  const auto a = calibrate(linear_bounds(), lc.targets(), o);
  const auto b = calibrate(linear_bounds(), lc.targets(), o);
  EXPECT_EQ(a.posterior.samples, b.posterior.samples);
  o.seed = 2;
  const auto c = calibrate(linear_bounds(), lc.targets(), o);
  EXPECT_NE(a.posterior.samples, c.posterior.samples);
}

TEST(PosteriorSampling, VarianceTermPullsTowardsConfidentSurrogate) {
  // A flat mean (the data say nothing about mu_r) with a surrogate variance that grows
  // with mu_r: the likelihood's log-variance term makes low mu_r more probable, with
  // density proportional to exp(-(y - m)^2 / 2 s^2) / s.
  const double sm = 0.1;
  const auto flat = model([](const Eigen::VectorXd&) { return 1.0; },
                          [](const Eigen::VectorXd&) { return Eigen::VectorXd::Zero(1); },
                          [sm](const Eigen::VectorXd& x) { return sm * sm * (std::exp(4.0 * x(0)) - 1.0); }, {"mu_r"});
  CalibrationOptions o = quick_options();
  o.mcmc_samples = 20000;
  const auto r = calibrate({{"mu_r", 0.0, 1.0}}, {{"pile", "y", 1.0, sm, 0.0, flat, true}}, o);
  // Exact posterior mean of density exp(-2x) on [0, 1]: 1/2 - e^-2 / (1 - e^-2).
  const double expected = 0.5 - std::exp(-2.0) / (1.0 - std::exp(-2.0));
  EXPECT_NEAR(r.posterior.marginals[0].mean, expected, 0.02);
}

// ---------------------------------------------------------------------------------------
// Bad input

TEST(CalibrationProblem, RejectsBadInputNamingTheItem) {
  const auto good = [] { return std::vector<Target>{aor_target(30.0), discharge_target(8.0)}; };
  auto msg = invalid_argument_message([&] {
    auto t = good();
    t[1].sigma_measured = 0.0;
    (void)CalibrationProblem(paper_bounds(), t);
  });
  EXPECT_TRUE(contains(msg, "target 1 (sandglass discharge_time_s)")) << msg;
  EXPECT_TRUE(contains(msg, "sigma_measured")) << msg;
  msg = invalid_argument_message([&] {
    auto t = good();
    t[0].sigma_measured = -1.0;
    (void)CalibrationProblem(paper_bounds(), t);
  });
  EXPECT_TRUE(contains(msg, "target 0 (sandglass angle_of_repose_deg)")) << msg;
  msg = invalid_argument_message([&] {
    auto t = good();
    t[0].sigma_dem = -0.1;
    (void)CalibrationProblem(paper_bounds(), t);
  });
  EXPECT_TRUE(contains(msg, "sigma_dem")) << msg;
  msg = invalid_argument_message([&] { (void)CalibrationProblem(paper_bounds(), {}); });
  EXPECT_TRUE(contains(msg, "no targets")) << msg;
  msg = invalid_argument_message([&] { (void)CalibrationProblem({}, good()); });
  EXPECT_TRUE(contains(msg, "no parameters")) << msg;
  msg = invalid_argument_message([&] { (void)CalibrationProblem({{"mu_r", 0.5, 0.5}, {"mu_s", 0.2, 0.9}}, good()); });
  EXPECT_TRUE(contains(msg, "'mu_r'")) << msg;
  msg = invalid_argument_message([&] { (void)CalibrationProblem({{"mu_r", 0.1, 0.5}, {"mu_s", 0.9, 0.2}}, good()); });
  EXPECT_TRUE(contains(msg, "'mu_s'")) << msg;
  msg = invalid_argument_message([&] { (void)CalibrationProblem({{"mu_r", 0.1, 0.5}, {"mu_r", 0.2, 0.9}}, good()); });
  EXPECT_TRUE(contains(msg, "listed twice")) << msg;
  msg = invalid_argument_message([&] {
    auto t = good();
    t[1].model = model([](const Eigen::VectorXd& x) { return x(0); },
                       [](const Eigen::VectorXd&) { return Eigen::VectorXd::Ones(1); }, {}, {"mu_r"});
    (void)CalibrationProblem(paper_bounds(), t);
  });
  EXPECT_TRUE(contains(msg, "target 1")) << msg;
  EXPECT_TRUE(contains(msg, "1 inputs but 2 parameters")) << msg;
  msg = invalid_argument_message([&] {
    auto t = good();
    t[0].model = model(aor, aor_gradient, {}, {"mu_s", "mu_r"});
    (void)CalibrationProblem(paper_bounds(), t);
  });
  EXPECT_TRUE(contains(msg, "another order")) << msg;
  msg = invalid_argument_message([&] {
    auto t = good();
    t[0].model = nullptr;
    (void)CalibrationProblem(paper_bounds(), t);
  });
  EXPECT_TRUE(contains(msg, "target 0")) << msg;
  msg = invalid_argument_message([&] {
    CalibrationOptions o;
    o.confidence = 1.0;
    (void)calibrate(paper_bounds(), good(), o);
  });
  EXPECT_TRUE(contains(msg, "confidence")) << msg;
  // Unnamed model inputs are taken in the parameters' order.
  auto t = good();
  t[0].model = model(aor, aor_gradient, {}, {"x0", "x1"});
  EXPECT_NO_THROW((void)CalibrationProblem(paper_bounds(), t));
  // Different parameter names cannot be compared.
  CalibrationOptions o = quick_options();
  o.mcmc_samples = 0;
  o.grid_points_per_axis = 11;
  const auto ra = calibrate(paper_bounds(), good(), o);
  auto other = paper_bounds();
  other[1].name = "mu_w";
  auto tw = good();
  for (auto& x : tw) x.model = model(aor, aor_gradient, {}, {"mu_r", "mu_w"});
  const auto rb = calibrate(other, tw, o);
  msg = invalid_argument_message([&] { (void)compare_regions(ra, rb); });
  EXPECT_TRUE(contains(msg, "'mu_s'")) << msg;
}

// ---------------------------------------------------------------------------------------
// Performance with surrogates of a Gaussian process's cost.

// Radial-basis interpolant with a GP-like predictive variance: one n-vector of kernel
// values and one triangular solve per point, as a GP on n training runs.
class KernelSurrogate final : public SurrogateModel {
 public:
  KernelSurrogate(int n, std::function<double(const Eigen::VectorXd&)> f) : names_(kNames) {
    Normal u(7);
    centres_.resize(n, 2);
    Eigen::VectorXd y(n);
    for (int i = 0; i < n; ++i) {
      centres_.row(i) << 0.05 + 0.75 * gsl_rng_uniform(u.rng), 0.2 + 0.7 * gsl_rng_uniform(u.rng);
      y(i) = f(centres_.row(i).transpose());
    }
    Eigen::MatrixXd k = kernel(centres_);
    k.diagonal().array() += 1e-6;
    llt_.compute(k);
    alpha_ = llt_.solve(y);
  }
  std::string kind() const override { return "kernel"; }
  std::string description() const override { return "test RBF interpolant"; }
  std::size_t input_dimension() const override { return 2; }
  const std::vector<std::string>& input_names() const override { return names_; }
  Prediction predict(const Eigen::MatrixXd& x) const override {
    const Eigen::MatrixXd kx = kernel(x);  // points x centres
    Prediction p;
    p.mean = kx * alpha_;
    const Eigen::MatrixXd v = llt_.matrixL().solve(kx.transpose());
    p.variance = (1e-2 * (1.0 - v.colwise().squaredNorm().array())).matrix().transpose().cwiseMax(0.0);
    return p;
  }
  Eigen::VectorXd predict_mean(const Eigen::MatrixXd& x) const override { return kernel(x) * alpha_; }
  Eigen::MatrixXd gradient(const Eigen::MatrixXd& x) const override {
    Eigen::MatrixXd g(x.rows(), 2);
    const Eigen::MatrixXd kx = kernel(x);
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      for (int j = 0; j < 2; ++j) {
        const Eigen::VectorXd d = (centres_.col(j).array() - x(i, j)).matrix() / (kLength * kLength);
        g(i, j) = kx.row(i).dot(d.cwiseProduct(alpha_));
      }
    return g;
  }
  LeaveOneOut leave_one_out() const override { return {}; }

 private:
  static constexpr double kLength = 0.25;
  Eigen::MatrixXd kernel(const Eigen::MatrixXd& x) const {
    Eigen::MatrixXd k(x.rows(), centres_.rows());
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      k.row(i) = (-(centres_.rowwise() - x.row(i)).rowwise().squaredNorm() / (2 * kLength * kLength))
                     .array()
                     .exp()
                     .transpose();
    return k;
  }
  std::vector<std::string> names_;
  Eigen::MatrixXd centres_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::VectorXd alpha_;
};

TEST(Calibration, FastWithGaussianProcessSizedSurrogates) {
  const auto gp_aor = std::make_shared<KernelSurrogate>(60, aor);
  const auto gp_time = std::make_shared<KernelSurrogate>(60, discharge);
  CalibrationOptions o;  // defaults: 121^2 grid, 20000 samples
#if defined(__SANITIZE_ADDRESS__) || !defined(NDEBUG)
  o.mcmc_samples = 4000;  // instrumented Eigen is an order of magnitude slower
  o.grid_points_per_axis = 61;
#endif
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = calibrate(paper_bounds(),
                           {{"sandglass", "angle_of_repose_deg", aor(kTruth), 0.5, 0.3, gp_aor, true},
                            {"sandglass", "discharge_time_s", discharge(kTruth), 0.15, 0.1, gp_time, true}},
                           o);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  RecordProperty("calibrate_seconds", std::to_string(seconds));
  std::printf("calibrate() with two 60-point kernel surrogates: %.2f s\n", seconds);
  EXPECT_NEAR(r.minima.front().theta(0), kTruth(0), 0.02);
  EXPECT_NEAR(r.minima.front().theta(1), kTruth(1), 0.02);
  EXPECT_TRUE(r.posterior.available);
  EXPECT_LT(seconds, 20.0);  // generous: the cores are shared; about 1 s when idle
}

}  // namespace
