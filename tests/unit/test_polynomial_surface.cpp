// Polynomial response surface: exact recovery, standard errors against the normal
// equations, closed-form leave-one-out against refitting, degree selection, validation
// metrics, JSON round trip and input checks.
#include "surrogate/cross_validation.hpp"
#include "surrogate/full_factorial_design.hpp"
#include "surrogate/polynomial_surface.hpp"
#include "surrogate/surrogate_io.hpp"
#include "tests/support/invalid_argument_message.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>

namespace {

using namespace demcal::surrogate;

// Uniform points in a box from a fixed generator (raw engine output: the same everywhere).
Eigen::MatrixXd random_points(int n, const std::vector<double>& lo, const std::vector<double>& hi,
                              std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Eigen::MatrixXd x(n, static_cast<Eigen::Index>(lo.size()));
  for (int i = 0; i < n; ++i)
    for (std::size_t j = 0; j < lo.size(); ++j)
      x(i, static_cast<Eigen::Index>(j)) =
          lo[j] + (hi[j] - lo[j]) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return x;
}

Eigen::VectorXd gaussian_noise(int n, double sd, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, sd);
  Eigen::VectorXd e(n);
  for (int i = 0; i < n; ++i) e(i) = normal(rng);
  return e;
}

using demcal::testing::invalid_argument_message;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// 1 - 2 mu_r + 3 mu_s + 4 mu_r² - 5 mu_r mu_s + 0.5 mu_s² + 6 mu_r³ - 2 mu_r² mu_s + 1.5 mu_r mu_s² - mu_s³
// in the order of total_degree_terms(3, 2).
const std::vector<double> kCubic = {1.0, -2.0, 3.0, 4.0, -5.0, 0.5, 6.0, -2.0, 1.5, -1.0};

double cubic(double a, double b) {
  const double t[] = {1, a, b, a * a, a * b, b * b, a * a * a, a * a * b, a * b * b, b * b * b};
  double v = 0.0;
  for (std::size_t k = 0; k < kCubic.size(); ++k) v += kCubic[k] * t[k];
  return v;
}

TEST(PolynomialSurface, TermsComeByDegreeWithReadableNames) {
  const auto terms = PolynomialSurface::total_degree_terms(2, 2);
  const std::vector<std::vector<int>> expected = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};
  EXPECT_EQ(terms, expected);
  EXPECT_EQ(PolynomialSurface::total_degree_terms(4, 3).size(), 35u);  // C(4 + 3, 3)
  EXPECT_EQ(PolynomialSurface::total_degree_terms(3, 1).size(), 4u);

  const Eigen::MatrixXd x = to_matrix(full_factorial_design({{"a", 0, 1, 4}, {"b", 0, 1, 4}}));
  Eigen::VectorXd y = x.col(0) + x.col(1);
  PolynomialOptions opt;
  opt.degree = 3;
  opt.input_names = {"mu_r", "mu_s"};
  const auto s = PolynomialSurface::fit(x, y, opt);
  const std::vector<std::string> names = {"1",      "mu_r",        "mu_s",        "mu_r^2",
                                          "mu_r*mu_s", "mu_s^2",   "mu_r^3",      "mu_r^2*mu_s",
                                          "mu_r*mu_s^2", "mu_s^3"};
  EXPECT_EQ(s.term_names(), names);
  EXPECT_EQ(s.description(), "polynomial surface, total degree 3, 10 terms");
  PolynomialOptions quadratic;
  quadratic.degree = 2;
  const auto unnamed = PolynomialSurface::fit(x, y, quadratic);
  EXPECT_EQ(unnamed.term_names()[4], "x0*x1");
}

TEST(PolynomialSurface, RecoversAKnownCubicExactlyFromNoiselessData) {
  // 5 x 5 levels determine a cubic in two inputs; the bounds are the physical ones, so the
  // check also covers the expansion from scaled back to physical coefficients.
  const Eigen::MatrixXd x =
      to_matrix(full_factorial_design({{"mu_r", 0.05, 0.6, 5}, {"mu_s", 0.2, 0.9, 5}}));
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = cubic(x(i, 0), x(i, 1));
  PolynomialOptions opt;
  opt.degree = 3;
  const auto s = PolynomialSurface::fit(x, y, opt);
  const Eigen::VectorXd c = s.unscaled_coefficients();
  ASSERT_EQ(c.size(), 10);
  for (Eigen::Index k = 0; k < c.size(); ++k)
    EXPECT_NEAR(c(k), kCubic[static_cast<std::size_t>(k)], 1e-10) << s.term_names()[static_cast<std::size_t>(k)];
  EXPECT_NEAR(s.r_squared(), 1.0, 1e-14);
  EXPECT_LT(s.residual_sigma(), 1e-12);

  // On [-1, 1] bounds the scaled coefficients are the physical ones.
  const Eigen::MatrixXd u = to_matrix(full_factorial_design({{"a", -1, 1, 5}, {"b", -1, 1, 5}}));
  Eigen::VectorXd yu(u.rows());
  for (Eigen::Index i = 0; i < u.rows(); ++i) yu(i) = cubic(u(i, 0), u(i, 1));
  const auto su = PolynomialSurface::fit(u, yu, opt);
  for (Eigen::Index k = 0; k < 10; ++k)
    EXPECT_NEAR(su.coefficients()(k), kCubic[static_cast<std::size_t>(k)], 1e-10);

  // Mean and analytic gradient at points off the design.
  const Eigen::MatrixXd pts = random_points(7, {0.05, 0.2}, {0.6, 0.9}, 3);
  const Eigen::VectorXd mean = s.predict_mean(pts);
  const Eigen::MatrixXd grad = s.gradient(pts);
  for (Eigen::Index i = 0; i < pts.rows(); ++i) {
    const double a = pts(i, 0), b = pts(i, 1);
    EXPECT_NEAR(mean(i), cubic(a, b), 1e-11);
    const double da = -2 + 8 * a - 5 * b + 18 * a * a - 4 * a * b + 1.5 * b * b;
    const double db = 3 - 5 * a + b - 2 * a * a + 3 * a * b - 3 * b * b;
    EXPECT_NEAR(grad(i, 0), da, 1e-9);
    EXPECT_NEAR(grad(i, 1), db, 1e-9);
  }
}

TEST(PolynomialSurface, StandardErrorsMatchTheNormalEquations) {
  // Quadratic in one input, 8 noisy points: the textbook computation on the raw design
  // [1, x, x²] is independent of the QR on the scaled design.
  const Eigen::VectorXd xv = (Eigen::VectorXd(8) << 0.1, 0.5, 0.9, 1.6, 2.2, 2.5, 3.1, 3.9).finished();
  const Eigen::VectorXd noise = gaussian_noise(8, 0.3, 11);
  Eigen::VectorXd y(8);
  Eigen::MatrixXd X(8, 3);
  for (int i = 0; i < 8; ++i) {
    y(i) = 2.0 - 1.0 * xv(i) + 0.7 * xv(i) * xv(i) + noise(i);
    X.row(i) << 1.0, xv(i), xv(i) * xv(i);
  }
  const Eigen::MatrixXd xtx_inv = (X.transpose() * X).inverse();
  const Eigen::VectorXd beta = xtx_inv * X.transpose() * y;
  const Eigen::VectorXd e = y - X * beta;
  const double s2 = e.squaredNorm() / 5.0;
  const Eigen::VectorXd se = (s2 * xtx_inv).diagonal().cwiseSqrt();
  const double sst = (y.array() - y.mean()).square().sum();

  PolynomialOptions opt;
  opt.degree = 2;
  opt.lower = {0.0};
  opt.upper = {4.0};
  const auto s = PolynomialSurface::fit(Eigen::MatrixXd(xv), y, opt);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(s.unscaled_coefficients()(k), beta(k), 1e-10 * std::abs(beta(k)) + 1e-12);
    EXPECT_NEAR(s.unscaled_standard_errors()(k), se(k), 1e-9 * se(k));
  }
  EXPECT_EQ(s.residual_degrees_of_freedom(), 5);
  EXPECT_NEAR(s.residual_sigma(), std::sqrt(s2), 1e-12);
  EXPECT_NEAR(s.r_squared(), 1.0 - e.squaredNorm() / sst, 1e-12);
  EXPECT_NEAR(s.adjusted_r_squared(), 1.0 - (e.squaredNorm() / 5.0) / (sst / 7.0), 1e-12);

  // Scaled standard errors: the same on the scaled design u = x / 2 - 1.
  Eigen::MatrixXd U(8, 3);
  for (int i = 0; i < 8; ++i) U.row(i) << 1.0, xv(i) / 2 - 1, std::pow(xv(i) / 2 - 1, 2);
  const Eigen::VectorXd se_u = (s2 * (U.transpose() * U).inverse()).diagonal().cwiseSqrt();
  EXPECT_TRUE(s.standard_errors().isApprox(se_u, 1e-9));

  // Prediction standard errors at a new point.
  const double x0 = 1.3;
  const Eigen::Vector3d h(1.0, x0, x0 * x0);
  const double se_mean = std::sqrt(s2 * h.dot(xtx_inv * h));
  const Eigen::MatrixXd p0 = Eigen::MatrixXd::Constant(1, 1, x0);
  EXPECT_NEAR(s.mean_standard_error(p0)(0), se_mean, 1e-10);
  EXPECT_NEAR(s.observation_standard_error(p0)(0), std::sqrt(se_mean * se_mean + s2), 1e-10);
  EXPECT_NEAR(s.predict(p0).variance(0), se_mean * se_mean, 1e-10);
}

TEST(PolynomialSurface, ClosedFormLeaveOneOutEqualsRefittingWithoutEachPoint) {
  const int n = 15;
  const Eigen::MatrixXd x = random_points(n, {0.0, 10.0}, {1.0, 30.0}, 5);
  Eigen::VectorXd y = gaussian_noise(n, 0.2, 6);
  for (int i = 0; i < n; ++i) y(i) += std::sin(3 * x(i, 0)) + 0.05 * x(i, 1) * x(i, 0);
  PolynomialOptions opt;
  opt.degree = 2;
  opt.lower = {0.0, 10.0};  // fixed, so that each refit scales identically
  opt.upper = {1.0, 30.0};
  const auto s = PolynomialSurface::fit(x, y, opt);
  const LeaveOneOut loo = s.leave_one_out();
  double press = 0.0;
  for (int i = 0; i < n; ++i) {
    std::vector<int> keep;
    for (int k = 0; k < n; ++k)
      if (k != i) keep.push_back(k);
    const auto refit = PolynomialSurface::fit(x(keep, Eigen::all), y(keep), opt);
    const Eigen::MatrixXd xi = x.row(i);
    EXPECT_NEAR(loo.mean(i), refit.predict_mean(xi)(0), 1e-10) << "point " << i;
    const double obs_var = std::pow(refit.observation_standard_error(xi)(0), 2);
    EXPECT_NEAR(loo.variance(i), obs_var, 1e-10 * obs_var) << "point " << i;
    press += std::pow(y(i) - refit.predict_mean(xi)(0), 2);
  }
  const ValidationMetrics m = validation_metrics(loo);
  EXPECT_NEAR(m.press, press, 1e-10 * press);
  EXPECT_NEAR(m.rmse, std::sqrt(press / n), 1e-12);
  EXPECT_NEAR(m.q_squared, 1.0 - press / (y.array() - y.mean()).square().sum(), 1e-12);
  EXPECT_NEAR(m.standardized_residuals(3), (y(3) - loo.mean(3)) / std::sqrt(loo.variance(3)), 1e-12);
}

TEST(PolynomialSurface, DegreeSelectionFindsTheDegreeOfANoisyCubic) {
  const int n = 60;
  const Eigen::MatrixXd x = random_points(n, {0.05, 0.2}, {0.6, 0.9}, 21);
  for (std::uint64_t noise_seed : {1u, 2u, 3u}) {
    Eigen::VectorXd y = gaussian_noise(n, 0.01, noise_seed);
    for (int i = 0; i < n; ++i) y(i) += cubic(x(i, 0), x(i, 1));
    const auto loo = select_polynomial_degree(x, y);
    EXPECT_EQ(loo.degree, 3) << "noise seed " << noise_seed;
    ASSERT_EQ(loo.degrees, (std::vector<int>{1, 2, 3, 4}));
    EXPECT_GT(loo.cv_rmse[1], 2 * loo.cv_rmse[2]);  // the quadratic misses the cubic terms
    EXPECT_EQ(loo.surface.degree(), 3);

    DegreeSelectionOptions kfold;
    kfold.method = CrossValidationMethod::k_fold;
    kfold.folds = 5;
    kfold.seed = 7;
    const auto kf = select_polynomial_degree(x, y, {}, kfold);
    EXPECT_EQ(kf.degree, 3) << "noise seed " << noise_seed;
    // Fold assignment is fixed by the seed: the same call gives the same errors.
    EXPECT_EQ(select_polynomial_degree(x, y, {}, kfold).cv_rmse, kf.cv_rmse);

    kfold.one_standard_error_rule = true;
    EXPECT_EQ(select_polynomial_degree(x, y, {}, kfold).degree, 3);
  }
  // Degrees with more terms than points - 1 are skipped: 12 points allow up to degree 3
  // (10 terms) but not 4 (15 terms).
  const Eigen::MatrixXd few = random_points(12, {0, 0}, {1, 1}, 4);
  const auto sel = select_polynomial_degree(few, few.col(0) + few.col(1));
  EXPECT_EQ(sel.degrees, (std::vector<int>{1, 2, 3}));
}

TEST(PolynomialSurface, KFoldAssignmentIsBalancedAndSeeded) {
  const auto a = k_fold_assignment(23, 5, 42);
  std::vector<int> sizes(5, 0);
  for (int f : a) ++sizes.at(static_cast<std::size_t>(f));
  for (int s : sizes) EXPECT_TRUE(s == 4 || s == 5);
  EXPECT_EQ(k_fold_assignment(23, 5, 42), a);
  EXPECT_NE(k_fold_assignment(23, 5, 43), a);
  EXPECT_THROW(k_fold_assignment(3, 5, 1), std::invalid_argument);
}

TEST(PolynomialSurface, ScatterCheckFlagsASurrogateWorseThanRerunningTheDem) {
  // Single runs with scatter 1: a LOO RMSE of 1.3 is mostly that noise, 2.0 is not.
  const auto ok = check_against_scatter(1.3, 1.0, "aor_deg");
  EXPECT_TRUE(ok.within_scatter) << ok.message;
  EXPECT_NEAR(ok.surrogate_error, std::sqrt(1.3 * 1.3 - 1.0), 1e-12);
  const auto bad = check_against_scatter(2.0, 1.0, "aor_deg");
  EXPECT_FALSE(bad.within_scatter);
  EXPECT_TRUE(contains(bad.message, "aor_deg")) << bad.message;
  EXPECT_TRUE(contains(bad.message, "worse than rerunning")) << bad.message;
  // Means of 4 runs carry little noise: the same RMSE of 1.3 is now mostly surrogate error.
  EXPECT_FALSE(check_against_scatter(1.3, 1.0, "aor_deg", 4).within_scatter);
  EXPECT_TRUE(contains(invalid_argument_message([] { check_against_scatter(1.0, -1.0); }),
                       "run_to_run_sd"));
}

TEST(PolynomialSurface, ScatterCheckAllowsForAScatterEstimatedFromFewDegreesOfFreedom) {
  // Surrogate error sqrt(2² - 1) = 1.73 against a scatter of 1 that could be 1.92 (6 dof,
  // chi²_0.05(6) = 1.6354) or 1.13 (100 dof, chi²_0.05(100) = 77.929) at 95 % confidence.
  const auto few = check_against_scatter(2.0, 1.0, "aor_deg", 1, 6);
  EXPECT_NEAR(few.scatter_bound, std::sqrt(6.0 / 1.63538), 1e-4);
  EXPECT_TRUE(few.within_scatter) << few.message;
  EXPECT_TRUE(contains(few.message, "from 6 degrees of freedom")) << few.message;
  const auto many = check_against_scatter(2.0, 1.0, "aor_deg", 1, 100);
  EXPECT_NEAR(many.scatter_bound, std::sqrt(100.0 / 77.9295), 1e-4);
  EXPECT_FALSE(many.within_scatter) << many.message;
  EXPECT_TRUE(contains(many.message, "worse than rerunning")) << many.message;
  // No degrees of freedom given: the scatter is taken as exact, as before.
  EXPECT_EQ(check_against_scatter(2.0, 1.0, "aor_deg").scatter_bound, 1.0);
  EXPECT_TRUE(
      contains(invalid_argument_message([] { check_against_scatter(1.0, 1.0, "x", 1, -1); }),
               "scatter_degrees_of_freedom"));
}

TEST(PolynomialSurface, ExplicitTermSetsAndTheirLimits) {
  const Eigen::MatrixXd x = random_points(20, {0, 0}, {2, 2}, 8);
  const Eigen::VectorXd y = (1.0 + 2.0 * x.col(0).array() * x.col(1).array()).matrix();
  PolynomialOptions opt;
  opt.terms = {{0, 0}, {1, 1}};
  opt.input_names = {"mu_r", "mu_s"};
  opt.lower = {-2, -2};  // symmetric: x0*x1 needs no lower terms in physical units
  opt.upper = {2, 2};
  const auto s = PolynomialSurface::fit(x, y, opt);
  EXPECT_EQ(s.term_names(), (std::vector<std::string>{"1", "mu_r*mu_s"}));
  EXPECT_NEAR(s.unscaled_coefficients()(0), 1.0, 1e-12);
  EXPECT_NEAR(s.unscaled_coefficients()(1), 2.0, 1e-12);
  EXPECT_TRUE(contains(s.description(), "2 explicit terms"));
  // Off-centre bounds: x0*x1 expands into x0 and x1, which the set lacks.
  opt.lower = {0, 0};
  EXPECT_THROW((void)PolynomialSurface::fit(x, y, opt).unscaled_coefficients(), std::logic_error);
}

TEST(PolynomialSurface, RejectsBadInputNamingTheProblem) {
  const Eigen::MatrixXd x = random_points(12, {0, 0}, {1, 1}, 9);
  const Eigen::VectorXd y = x.col(0);
  PolynomialOptions opt;
  EXPECT_TRUE(contains(invalid_argument_message([&] { PolynomialSurface::fit(x, y.head(11), opt); }),
                       "x has 12 rows but y has 11"));
  opt.degree = 0;
  EXPECT_TRUE(contains(invalid_argument_message([&] { PolynomialSurface::fit(x, y, opt); }), "degree"));
  opt.degree = 5;
  EXPECT_TRUE(contains(invalid_argument_message([&] { PolynomialSurface::fit(x, y, opt); }),
                       "degree must be in 1..4, got 5"));
  opt.degree = 4;  // 15 terms
  EXPECT_TRUE(contains(invalid_argument_message([&] { PolynomialSurface::fit(x, y, opt); }),
                       "15 terms need at least 16 points"));
  opt.degree = 2;
  Eigen::MatrixXd xn = x;
  xn(2, 1) = std::nan("");
  opt.input_names = {"mu_r", "mu_s"};
  EXPECT_TRUE(contains(invalid_argument_message([&] { PolynomialSurface::fit(xn, y, opt); }),
                       "x(2, 1) of input 'mu_s' is not finite"));
  Eigen::VectorXd yn = y;
  yn(3) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(contains(invalid_argument_message([&] { PolynomialSurface::fit(x, yn, opt); }),
                       "y[3] is not finite"));
  opt.lower = {0.0, 1.0};
  opt.upper = {1.0, 0.5};
  EXPECT_TRUE(contains(invalid_argument_message([&] { PolynomialSurface::fit(x, y, opt); }),
                       "upper must exceed lower for input 'mu_s'"));
  opt.lower.clear();
  opt.upper.clear();
  opt.terms = {{0, 0}, {1}};
  EXPECT_TRUE(contains(invalid_argument_message([&] { PolynomialSurface::fit(x, y, opt); }),
                       "terms[1] has 1 exponents"));
  opt.terms.clear();
  opt.input_names = {"only_one"};
  EXPECT_TRUE(contains(invalid_argument_message([&] { PolynomialSurface::fit(x, y, opt); }),
                       "input_names"));
  // Three levels per input cannot separate x0³ from x0.
  const Eigen::MatrixXd grid = to_matrix(full_factorial_design({{"a", 0, 1, 3}, {"b", 0, 1, 5}}));
  PolynomialOptions cubic_opt;
  cubic_opt.degree = 3;
  EXPECT_TRUE(contains(
      invalid_argument_message([&] { PolynomialSurface::fit(grid, grid.col(1), cubic_opt); }),
      "rank deficient: term 'x0"));
  const auto s = PolynomialSurface::fit(x, y, {});
  EXPECT_TRUE(contains(invalid_argument_message([&] { (void)s.predict_mean(Eigen::MatrixXd::Zero(2, 3)); }),
                       "points have 3 columns but the model has 2 inputs"));
  DegreeSelectionOptions sel;
  sel.max_degree = 5;
  EXPECT_TRUE(contains(invalid_argument_message([&] { select_polynomial_degree(x, y, {}, sel); }),
                       "max_degree"));
}

TEST(PolynomialSurfaceIo, SavedAndLoadedSurfacePredictsIdentically) {
  const Eigen::MatrixXd x = random_points(25, {0.05, 0.2}, {0.6, 0.9}, 12);
  Eigen::VectorXd y = gaussian_noise(25, 0.05, 13);
  for (int i = 0; i < 25; ++i) y(i) += cubic(x(i, 0), x(i, 1));
  PolynomialOptions opt;
  opt.degree = 3;
  opt.input_names = {"mu_r", "mu_s"};
  const auto s = PolynomialSurface::fit(x, y, opt);
  const auto path = std::filesystem::temp_directory_path() / "demcal_test_polynomial_surface.json";
  save_surrogate(s, path);
  const auto loaded = load_surrogate(path);
  std::filesystem::remove(path);
  ASSERT_EQ(loaded->kind(), "polynomial_surface");
  const auto& back = dynamic_cast<const PolynomialSurface&>(*loaded);
  EXPECT_EQ(back.term_names(), s.term_names());
  EXPECT_EQ(back.input_names(), s.input_names());
  EXPECT_EQ(back.coefficients(), s.coefficients());  // exact
  EXPECT_EQ(back.standard_errors(), s.standard_errors());
  const Eigen::MatrixXd pts = random_points(50, {0.0, 0.1}, {0.7, 1.0}, 14);
  const Prediction a = s.predict(pts), b = loaded->predict(pts);
  EXPECT_EQ(a.mean, b.mean);
  EXPECT_EQ(a.variance, b.variance);
  EXPECT_EQ(s.gradient(pts), loaded->gradient(pts));
  EXPECT_EQ(s.leave_one_out().mean, loaded->leave_one_out().mean);

  auto j = to_json(s);
  EXPECT_EQ(j["coefficients_input_units"].size(), 10u);  // informational, for readers
  j.erase("coefficients_scaled_inputs");
  EXPECT_TRUE(contains(invalid_argument_message([&] { polynomial_surface_from_json(j); }),
                       "missing key 'coefficients_scaled_inputs'"));
  EXPECT_TRUE(contains(invalid_argument_message([&] { gaussian_process_from_json(to_json(s)); }),
                       "'kind' is 'polynomial_surface'"));
}

}  // namespace
