// Gaussian process: interpolation, closed-form leave-one-out against refitting, maximum
// likelihood on data drawn from a known process, gradients, variance, per-point nugget,
// JSON round trip and input checks.
#include "surrogate/cross_validation.hpp"
#include "surrogate/gaussian_process.hpp"
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

// A smooth response in physical-looking units: a friction in [0.05, 0.6] and a time in
// [1, 5] s.
double response(double a, double b) { return 30.0 + 8.0 * std::sin(5.0 * a) + 2.0 * b * a + 0.3 * b * b; }

const std::vector<double> kLo = {0.05, 1.0};
const std::vector<double> kHi = {0.6, 5.0};

Eigen::VectorXd responses(const Eigen::MatrixXd& x) {
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = response(x(i, 0), x(i, 1));
  return y;
}

std::vector<int> all_but(int n, int i) {
  std::vector<int> keep;
  for (int k = 0; k < n; ++k)
    if (k != i) keep.push_back(k);
  return keep;
}

TEST(GaussianProcess, InterpolatesWithoutNuggetAndIsCertainOnlyAtTheData) {
  const Eigen::MatrixXd x = random_points(25, kLo, kHi, 1);
  const Eigen::VectorXd y = responses(x);
  // Matérn by maximum likelihood; the squared exponential with given, moderate length
  // scales (at its likelihood optimum on smooth data it needs jitter, which spoils exact
  // interpolation by design).
  GaussianProcessOptions matern;
  matern.nugget = NuggetMode::none;
  matern.starts = 4;
  GaussianProcessOptions squared_exponential = matern;
  squared_exponential.kernel = CovarianceKernel::squared_exponential;
  squared_exponential.hyperparameters = GaussianProcessHyperparameters{{0.15, 1.0}, 30.0, 0.0};
  for (const auto& opt : {matern, squared_exponential}) {
    const auto gp = GaussianProcess::fit(x, y, opt);
    ASSERT_EQ(gp.relative_jitter(), 0.0) << gp.description();
    const Prediction at_data = gp.predict(x);
    const double range = y.maxCoeff() - y.minCoeff();
    const double signal = gp.hyperparameters().signal_variance;
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      EXPECT_NEAR(at_data.mean(i), y(i), 1e-8 * range) << gp.description() << " point " << i;
      EXPECT_LT(at_data.variance(i), 1e-8 * signal) << gp.description() << " point " << i;
    }
    // Walking outwards from the design point farthest from the centre of the box, the
    // variance keeps growing, to a sizeable fraction of the data's variance.
    Eigen::Index far = 0;
    const Eigen::RowVector2d centre(0.325, 3.0), half_range(0.275, 2.0);
    (((x.rowwise() - centre).array().rowwise() / half_range.array()).matrix().rowwise().squaredNorm()).maxCoeff(&far);
    const Eigen::RowVector2d outward = x.row(far) - centre;
    Eigen::MatrixXd ray(6, 2);
    for (int k = 0; k < 6; ++k) ray.row(k) = x.row(far) + 0.1 * k * k * outward;
    const Prediction along = gp.predict(ray);
    for (int k = 1; k < 6; ++k) EXPECT_GT(along.variance(k), along.variance(k - 1)) << gp.description() << " step " << k;
    const double data_variance = (y.array() - y.mean()).square().sum() / (y.size() - 1.0);
    EXPECT_GT(along.variance(5), 1e-3 * data_variance) << gp.description();
    // Many points at once give what one point at a time does.
    EXPECT_NEAR(gp.predict_mean(ray.row(3))(0), along.mean(3), 1e-12 * range);
    EXPECT_NEAR(gp.predict(ray.row(4)).variance(0), along.variance(4), 1e-10 * signal);
  }
}

TEST(GaussianProcess, ClosedFormLeaveOneOutEqualsRefittingWithFixedHyperparameters) {
  const int n = 20;
  const Eigen::MatrixXd x = random_points(n, kLo, kHi, 2);
  const Eigen::VectorXd y = responses(x) + gaussian_noise(n, 0.2, 3);
  struct Case {
    CovarianceKernel kernel;
    MeanFunction mean;
    NuggetMode nugget;
  };
  for (const Case c : {Case{CovarianceKernel::matern52, MeanFunction::linear, NuggetMode::estimated},
                       Case{CovarianceKernel::squared_exponential, MeanFunction::constant, NuggetMode::fixed},
                       Case{CovarianceKernel::matern52, MeanFunction::constant, NuggetMode::none}}) {
    GaussianProcessOptions opt;
    opt.kernel = c.kernel;
    opt.mean = c.mean;
    opt.nugget = c.nugget;
    opt.lower = kLo;  // the same box for every refit
    opt.upper = kHi;
    opt.starts = 3;
    if (c.nugget == NuggetMode::fixed)
      for (int i = 0; i < n; ++i) opt.nugget_variances.push_back(0.02 + 0.01 * (i % 4));
    const auto gp = GaussianProcess::fit(x, y, opt);
    const LeaveOneOut loo = gp.leave_one_out();
    const Eigen::VectorXd nugget = gp.point_nugget_variances();

    GaussianProcessOptions fixed = opt;
    fixed.hyperparameters = gp.hyperparameters();
    for (int i = 0; i < n; ++i) {
      const auto keep = all_but(n, i);
      if (c.nugget == NuggetMode::fixed) {
        fixed.nugget_variances.clear();
        for (int k : keep) fixed.nugget_variances.push_back(opt.nugget_variances[static_cast<std::size_t>(k)]);
      }
      const auto refit = GaussianProcess::fit(x(keep, Eigen::all), y(keep), fixed);
      ASSERT_EQ(refit.relative_jitter(), 0.0);
      const Prediction p = refit.predict(x.row(i));
      const std::string where = gp.description() + ", point " + std::to_string(i);
      EXPECT_NEAR(loo.mean(i), p.mean(0), 1e-8 * std::abs(p.mean(0))) << where;
      const double obs_var = p.variance(0) + nugget(i);
      EXPECT_NEAR(loo.variance(i), obs_var, 1e-6 * obs_var) << where;
    }
    const ValidationMetrics m = validation_metrics(loo);
    EXPECT_GT(m.q_squared, 0.9) << gp.description();
  }
}

// Matérn 5/2 written out independently of the library.
double matern52(double r) { return (1 + std::sqrt(5.0) * r + 5.0 / 3.0 * r * r) * std::exp(-std::sqrt(5.0) * r); }

TEST(GaussianProcess, MaximumLikelihoodRecoversKnownLengthScales) {
  // One draw from a process with length scales 0.15 and 0.6 on the unit square (signal
  // variance 4, noise variance 1e-4): the short one must come out short, the long one long.
  const int n = 80;
  const double l0 = 0.15, l1 = 0.6, signal = 4.0, noise = 1e-4;
  const Eigen::MatrixXd x = random_points(n, {0, 0}, {1, 1}, 31);
  Eigen::MatrixXd K(n, n);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const double r = std::hypot((x(a, 0) - x(b, 0)) / l0, (x(a, 1) - x(b, 1)) / l1);
      K(a, b) = signal * matern52(r) + (a == b ? noise : 0.0);
    }
  const Eigen::LLT<Eigen::MatrixXd> llt(K);
  ASSERT_EQ(llt.info(), Eigen::Success);
  const Eigen::VectorXd y = (10.0 + (llt.matrixL() * gaussian_noise(n, 1.0, 32)).array()).matrix();

  GaussianProcessOptions opt;
  opt.lower = {0, 0};
  opt.upper = {1, 1};
  opt.starts = 4;
  const auto gp = GaussianProcess::fit(x, y, opt);
  const auto h = gp.hyperparameters();
  EXPECT_GT(h.length_scales[0], l0 / 2);
  EXPECT_LT(h.length_scales[0], l0 * 2);
  EXPECT_GT(h.length_scales[1], l1 / 2);
  EXPECT_LT(h.length_scales[1], l1 * 2);
  EXPECT_GT(h.signal_variance, signal / 4);
  EXPECT_LT(h.signal_variance, signal * 4);
  EXPECT_EQ(gp.report().start_log_likelihoods.size(), 4u);
  EXPECT_TRUE(gp.report().at_bounds.empty() || gp.report().at_bounds[0].find("nugget") != std::string::npos);

  // The optimizer must beat the truth and be a local maximum: fitting with the
  // hyperparameters given, at the truth or nudged by 1 %, never scores higher.
  const auto score = [&](const GaussianProcessHyperparameters& hp) {
    GaussianProcessOptions fixed = opt;
    fixed.hyperparameters = hp;
    return GaussianProcess::fit(x, y, fixed).log_marginal_likelihood();
  };
  const double best = gp.log_marginal_likelihood();
  EXPECT_GE(best, score({{l0, l1}, signal, noise}) - 1e-9);
  EXPECT_NEAR(score(h), best, 1e-9 * std::abs(best));
  for (double f : {0.99, 1.01}) {
    for (std::size_t j = 0; j < 2; ++j) {
      auto nudged = h;
      nudged.length_scales[j] *= f;
      EXPECT_LT(score(nudged), best) << "length scale " << j << " x " << f;
    }
    auto nudged = h;
    nudged.signal_variance *= f;
    EXPECT_LT(score(nudged), best) << "signal variance x " << f;
  }
}

TEST(GaussianProcess, GradientOfTheMeanMatchesFiniteDifferences) {
  // Inputs of very different magnitude: the gradient must come back in input units. The
  // step is not tiny because these noiseless data make K ill-conditioned (large weights),
  // so the mean carries rounding noise of ~1e-11 relative.
  const std::vector<double> lo = {0.05, 1e3, -2.0}, hi = {0.6, 5e3, 2.0};
  const Eigen::MatrixXd x = random_points(30, lo, hi, 4);
  Eigen::VectorXd y(30);
  for (int i = 0; i < 30; ++i) y(i) = std::sin(6 * x(i, 0)) + 1e-3 * x(i, 1) + x(i, 2) * x(i, 2);
  for (auto kernel : {CovarianceKernel::matern52, CovarianceKernel::squared_exponential}) {
    for (auto mean : {MeanFunction::constant, MeanFunction::linear}) {
      GaussianProcessOptions opt;
      opt.kernel = kernel;
      opt.mean = mean;
      opt.starts = 2;
      const auto gp = GaussianProcess::fit(x, y, opt);
      const Eigen::MatrixXd pts = random_points(5, lo, hi, 5);
      const Eigen::MatrixXd g = gp.gradient(pts);
      for (Eigen::Index i = 0; i < pts.rows(); ++i)
        for (Eigen::Index j = 0; j < 3; ++j) {
          const double h = 1e-4 * (hi[static_cast<std::size_t>(j)] - lo[static_cast<std::size_t>(j)]);
          Eigen::MatrixXd pm(2, 3);
          pm.row(0) = pts.row(i);
          pm.row(1) = pts.row(i);
          pm(0, j) += h;
          pm(1, j) -= h;
          const Eigen::VectorXd f = gp.predict_mean(pm);
          const double fd = (f(0) - f(1)) / (2 * h);
          EXPECT_NEAR(g(i, j), fd, 1e-4 * (std::abs(fd) + 1.0 / (hi[static_cast<std::size_t>(j)] - lo[static_cast<std::size_t>(j)])))
              << gp.description() << " point " << i << " input " << j;
        }
    }
  }
}

TEST(GaussianProcess, PerPointNuggetIsHonoured) {
  const int n = 20;
  const Eigen::MatrixXd x = random_points(n, kLo, kHi, 6);
  Eigen::VectorXd y = responses(x);
  y(7) += 5.0;  // an outlier, declared as very noisy
  GaussianProcessOptions opt;
  opt.nugget = NuggetMode::fixed;
  opt.nugget_variances.assign(n, 0.0);
  opt.nugget_variances[7] = 1e8;
  opt.lower = kLo;
  opt.upper = kHi;
  opt.hyperparameters = GaussianProcessHyperparameters{{0.2, 2.0}, 20.0, 0.0};
  const auto gp = GaussianProcess::fit(x, y, opt);
  EXPECT_NEAR(gp.point_nugget_variances()(7), 1e8, 1e-6);
  EXPECT_EQ(gp.point_nugget_variances()(0), 0.0);

  // The noisy point carries (almost) no weight: the same as leaving it out.
  GaussianProcessOptions without = opt;
  without.nugget_variances.assign(n - 1, 0.0);
  const auto keep = all_but(n, 7);
  const auto gp_without = GaussianProcess::fit(x(keep, Eigen::all), y(keep), without);
  const Eigen::MatrixXd pts = random_points(20, kLo, kHi, 7);
  EXPECT_TRUE(gp.predict_mean(pts).isApprox(gp_without.predict_mean(pts), 1e-5));
  EXPECT_GT(std::abs(gp.predict_mean(x.row(7))(0) - y(7)), 3.0);
  // The others are interpolated.
  const Eigen::VectorXd at = gp.predict_mean(x);
  for (int i = 0; i < n; ++i) {
    if (i != 7) {
      EXPECT_NEAR(at(i), y(i), 1e-6) << "point " << i;
    }
  }
  // A moderate nugget pulls the fit partway: between the datum and the no-weight value.
  opt.nugget_variances[7] = 1.0;
  const double partial = GaussianProcess::fit(x, y, opt).predict_mean(x.row(7))(0);
  const double ignored = gp_without.predict_mean(x.row(7))(0);
  EXPECT_GT(partial, ignored + 0.1);
  EXPECT_LT(partial, y(7) - 0.1);
}

TEST(GaussianProcess, RepeatedPointsWithoutNuggetAreRescuedByJitter) {
  // Two runs at the same inputs make K singular when there is no nugget; jitter escalation
  // must find a factorization and say so.
  Eigen::MatrixXd x = random_points(12, kLo, kHi, 12);
  x.row(11) = x.row(3);
  const Eigen::VectorXd y = responses(x);
  GaussianProcessOptions opt;
  opt.nugget = NuggetMode::none;
  opt.hyperparameters = GaussianProcessHyperparameters{{0.2, 2.0}, 20.0, 0.0};
  const auto gp = GaussianProcess::fit(x, y, opt);
  EXPECT_GT(gp.relative_jitter(), 0.0);
  EXPECT_LE(gp.relative_jitter(), 1e-6);
  EXPECT_NEAR(gp.predict_mean(x.row(3))(0), y(3), 1e-3);
}

TEST(GaussianProcessIo, SavedAndLoadedProcessPredictsIdentically) {
  const int n = 18;
  const Eigen::MatrixXd x = random_points(n, kLo, kHi, 8);
  const Eigen::VectorXd y = responses(x) + gaussian_noise(n, 0.1, 9);
  GaussianProcessOptions opt;
  opt.mean = MeanFunction::linear;
  opt.nugget = NuggetMode::fixed;
  for (int i = 0; i < n; ++i) opt.nugget_variances.push_back(0.01 * (1 + i % 3));
  opt.input_names = {"mu_r", "t_s"};
  opt.starts = 2;
  const auto gp = GaussianProcess::fit(x, y, opt);
  // Seeded starts: the same options give the same fit.
  EXPECT_EQ(GaussianProcess::fit(x, y, opt).state().length_scales, gp.state().length_scales);
  const auto path = std::filesystem::temp_directory_path() / "demcal_test_gaussian_process.json";
  save_surrogate(gp, path);
  const auto loaded = load_surrogate(path);
  std::filesystem::remove(path);
  ASSERT_EQ(loaded->kind(), "gaussian_process");
  const auto& back = dynamic_cast<const GaussianProcess&>(*loaded);
  EXPECT_EQ(back.hyperparameters().length_scales, gp.hyperparameters().length_scales);
  EXPECT_EQ(back.log_marginal_likelihood(), gp.log_marginal_likelihood());
  EXPECT_EQ(back.mean_coefficients(), gp.mean_coefficients());
  EXPECT_EQ(back.point_nugget_variances(), gp.point_nugget_variances());
  EXPECT_EQ(back.input_names(), gp.input_names());
  const Eigen::MatrixXd pts = random_points(40, {0.0, 0.5}, {0.7, 5.5}, 10);
  const Prediction a = gp.predict(pts), b = loaded->predict(pts);
  EXPECT_EQ(a.mean, b.mean);
  EXPECT_EQ(a.variance, b.variance);
  EXPECT_EQ(gp.gradient(pts), loaded->gradient(pts));
  EXPECT_EQ(gp.leave_one_out().variance, loaded->leave_one_out().variance);

  auto j = to_json(gp);
  j["kernel"] = "cubic";
  EXPECT_TRUE(contains(invalid_argument_message([&] { gaussian_process_from_json(j); }), "cubic"));
}

TEST(GaussianProcess, RejectsBadInputNamingTheProblem) {
  const Eigen::MatrixXd x = random_points(10, kLo, kHi, 11);
  const Eigen::VectorXd y = responses(x);
  GaussianProcessOptions opt;
  opt.input_names = {"mu_r", "t_s"};
  EXPECT_TRUE(contains(invalid_argument_message([&] { GaussianProcess::fit(x, y.head(9), opt); }),
                       "x has 10 rows but y has 9"));
  Eigen::VectorXd yn = y;
  yn(4) = std::nan("");
  EXPECT_TRUE(contains(invalid_argument_message([&] { GaussianProcess::fit(x, yn, opt); }), "y[4]"));
  opt.mean = MeanFunction::linear;
  EXPECT_TRUE(contains(invalid_argument_message([&] { GaussianProcess::fit(x.topRows(4), y.head(4), opt); }),
                       "needs at least 5 points"));
  opt.mean = MeanFunction::constant;
  opt.nugget = NuggetMode::fixed;
  opt.nugget_variances.assign(9, 0.1);
  EXPECT_TRUE(contains(invalid_argument_message([&] { GaussianProcess::fit(x, y, opt); }),
                       "nugget_variances has 9 values but there are 10 points"));
  opt.nugget_variances.assign(10, 0.1);
  opt.nugget_variances[6] = -0.1;
  EXPECT_TRUE(contains(invalid_argument_message([&] { GaussianProcess::fit(x, y, opt); }),
                       "nugget_variances[6]"));
  opt.nugget = NuggetMode::estimated;
  EXPECT_TRUE(contains(invalid_argument_message([&] { GaussianProcess::fit(x, y, opt); }),
                       "not 'fixed'"));
  opt.nugget_variances.clear();
  opt.hyperparameters = GaussianProcessHyperparameters{{0.1, 0.0}, 1.0, 0.0};
  EXPECT_TRUE(contains(invalid_argument_message([&] { GaussianProcess::fit(x, y, opt); }),
                       "length_scales[1] (input 't_s')"));
  opt.hyperparameters.reset();
  opt.bounds.max_length_scale = 0.001;
  EXPECT_TRUE(contains(invalid_argument_message([&] { GaussianProcess::fit(x, y, opt); }),
                       "bounds.max_length_scale"));
  opt.bounds = {};
  opt.starts = 1;
  const auto gp = GaussianProcess::fit(x, y, opt);
  EXPECT_TRUE(contains(invalid_argument_message([&] { (void)gp.predict(Eigen::MatrixXd::Zero(1, 3)); }),
                       "3 columns"));
  EXPECT_TRUE(contains(invalid_argument_message([] { covariance_kernel_from_string("rbf"); }), "'rbf'"));
}

}  // namespace
