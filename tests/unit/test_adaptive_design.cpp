// The adaptive design (issue 16) on analytic responses, no DEM: two observables with
// different gradient directions, an angle of repose that saturates in mu_s and a discharge
// time driven mostly by mu_s, each with seeded Gaussian run-to-run scatter.
//
// Criteria, fixed before the first measurement (per truth, over 5 seeds; the grid is the
// dense design of the recovery study's size, 7 x 7 points x 2 replicates = 98 runs, judged
// by the same fit-and-calibrate code, calibrate_runs):
//   (1) the adaptive design's runs, median over seeds, <= 98 / 3 (32);
//   (2) the median over seeds of its 95 % region's area over the grid's is within
//       [0.85, 1.15], or its region holds the truth in at least as many seeds as the grid's;
//   (3) it converges (not budget, not no_candidates) in >= 4 of 5 seeds;
//   (4) no corner piling: <= 25 % of its runs lie in a corner cell (both bound-scaled
//       coordinates within 0.1 of a bound).
// Out-of-range recordings (an angle of repose no point reaches) end with out_of_range after
// at most the start and two batches (<= 21 runs), in each of 3 seeds.
// A design resumed from the runs of a killed one (mid-start, mid-batch, between batches)
// asks for the same runs and ends with the same history as an uninterrupted one.
//
// The criteria above are unchanged since they were written. The method was changed once
// after the first measurement (docs/adaptive_design.md, "Measured"): with a 10 + 3 start,
// one replicate per batch up to 6 scatter dof, 4 GP starts and a 10 % area tolerance the
// interior truth passed only through the coverage clause (median area ratio 1.29, driven by
// the 6-dof scatter estimate) and the near-bound truth needed 33 runs in median.
#include "calibrate/adaptive_design.hpp"
#include "calibrate/runs_calibration.hpp"
#include "calibrate/weighted_variance_acquisition.hpp"
#include "tests/support/box_muller_normal.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace demcal::calibrate {
namespace {

constexpr double kAoRScatterDeg = 0.5;  // one run's scatter
constexpr double kTimeScatterFraction = 0.01;
constexpr double kAoRSigmaDeg = 0.5;  // the instrument's
constexpr double kTimeSigmaFraction = 0.01;

// Saturates in mu_s (a heap cannot get steeper than rolling friction lets it), rises with
// mu_r: its iso-lines run along mu_s at high mu_s.
double angle_of_repose_deg(double mu_r, double mu_s) {
  return 18.0 + 40.0 * (1.0 - std::exp(-mu_s / 0.2)) * mu_r / (mu_r + 0.15);
}
// Mostly mu_s, a little mu_r: its iso-lines cross the angle's.
double discharge_time_s(double mu_r, double mu_s) { return 6.0 * (1.0 + 0.6 * mu_s + 0.25 * mu_r); }

using Normal = demcal::testing::BoxMullerNormal;

std::vector<double> simulate(const RunRequest& run) {
  Normal n(run.seed);
  const double a = angle_of_repose_deg(run.theta[0], run.theta[1]);
  const double t = discharge_time_s(run.theta[0], run.theta[1]);
  return {a + kAoRScatterDeg * n(), t * (1.0 + kTimeScatterFraction * n())};
}

std::vector<std::vector<double>> evaluate(const std::vector<RunRequest>& batch) {
  std::vector<std::vector<double>> out;
  for (const auto& r : batch) out.push_back(simulate(r));
  return out;
}

std::vector<ParameterBounds> bounds() { return {{"mu_r", 0.05, 0.4}, {"mu_s", 0.2, 0.8}}; }

// One laboratory test at the truth (the DEM's scatter stands for the test-to-test scatter)
// plus the instrument's error.
std::vector<Recording> recordings_at(double mu_r, double mu_s, std::uint64_t seed,
                                     double aor_offset_deg = 0.0) {
  Normal n(0xabcdef00ULL + seed);
  const double a = angle_of_repose_deg(mu_r, mu_s) + aor_offset_deg;
  const double t = discharge_time_s(mu_r, mu_s);
  Recording aor{"heap",
                "angle_of_repose_deg",
                a + kAoRScatterDeg * n() + kAoRSigmaDeg * n(),
                kAoRSigmaDeg,
                1,
                "deg",
                1};
  Recording time{"sandglass",
                 "discharge_time_s",
                 t * (1.0 + kTimeScatterFraction * n()) + kTimeSigmaFraction * t * n(),
                 kTimeSigmaFraction * t,
                 1,
                 "s",
                 2};
  return {aor, time};
}

AdaptiveDesignOptions test_options(std::uint64_t seed) {
  AdaptiveDesignOptions o;
  o.seed = seed;
  return o;
}

// The dense grid: 7 x 7 points, 2 replicates each.
std::vector<RunResult> grid_runs(std::uint64_t seed) {
  std::vector<RunResult> runs;
  const auto b = bounds();
  std::size_t slot = 0;
  for (int rep = 0; rep < 2; ++rep)
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 7; ++j) {
        RunRequest r;
        r.batch = 0;
        r.slot = slot;
        r.theta = {b[0].lower + (b[0].upper - b[0].lower) * i / 6.0,
                   b[1].lower + (b[1].upper - b[1].lower) * j / 6.0};
        r.replicate = rep;
        r.seed = run_seed(seed + 1000, 0, slot);
        ++slot;
        runs.push_back({r, simulate(r)});
      }
  return runs;
}

bool holds(const RunsCalibration& c, double mu_r, double mu_s) {
  const CalibrationProblem problem(bounds(), c.targets);
  return region_contains(problem, c.result.region, Eigen::Vector2d(mu_r, mu_s));
}

double corner_fraction(const std::vector<RunResult>& runs) {
  const auto b = bounds();
  int in_corner = 0;
  for (const auto& r : runs) {
    bool corner = true;
    for (std::size_t j = 0; j < 2; ++j) {
      const double u = (r.request.theta[j] - b[j].lower) / (b[j].upper - b[j].lower);
      corner = corner && (u < 0.1 || u > 0.9);
    }
    in_corner += corner ? 1 : 0;
  }
  return static_cast<double>(in_corner) / static_cast<double>(runs.size());
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void check_against_grid(double mu_r, double mu_s, const std::string& label) {
  // 5 seeds in the suite; DEMCAL_ADAPTIVE_SEEDS=20 gives docs/adaptive_design.md's 1-20 rows.
  const char* const seeds_env = std::getenv("DEMCAL_ADAPTIVE_SEEDS");
  const int seeds = seeds_env ? std::max(1, std::atoi(seeds_env)) : 5;
  constexpr double kGridRuns = 98.0;
  std::vector<double> runs_used, area_ratio;
  int adaptive_holds = 0, grid_holds = 0, converged = 0;
  double worst_corner = 0.0;
  for (int s = 1; s <= seeds; ++s) {
    const auto seed = static_cast<std::uint64_t>(s);
    AdaptiveDesignProblem problem{bounds(), recordings_at(mu_r, mu_s, seed)};
    const AdaptiveDesignOptions options = test_options(seed);
    const auto adaptive = run_adaptive_design(problem, options, evaluate);
    const auto grid = calibrate_runs(bounds(), problem.recordings, grid_runs(seed),
                                     options.surrogate, options.calibration);
    const double ratio = adaptive.calibration.result.region.area / grid.result.region.area;
    runs_used.push_back(static_cast<double>(adaptive.runs.size()));
    area_ratio.push_back(ratio);
    const bool ah = holds(adaptive.calibration, mu_r, mu_s);
    const bool gh = holds(grid, mu_r, mu_s);
    adaptive_holds += ah ? 1 : 0;
    grid_holds += gh ? 1 : 0;
    converged += adaptive.history.status == AdaptiveDesignStatus::converged ? 1 : 0;
    worst_corner = std::max(worst_corner, corner_fraction(adaptive.runs));
    std::cout << label << " seed " << s << ": " << to_string(adaptive.history.status) << ", "
              << adaptive.runs.size() << " runs in " << adaptive.history.batches.size()
              << " batches, area " << adaptive.calibration.result.region.area << " vs grid "
              << grid.result.region.area << " (ratio " << ratio << "), truth inside: adaptive "
              << ah << " grid " << gh << ", corner fraction " << corner_fraction(adaptive.runs)
              << ", scatter sd adaptive " << adaptive.calibration.surrogates[0].scatter.sd << "/"
              << adaptive.calibration.surrogates[1].scatter.sd << " grid "
              << grid.surrogates[0].scatter.sd << "/" << grid.surrogates[1].scatter.sd << '\n';
    if (s == 1 || std::getenv("DEMCAL_ADAPTIVE_VERBOSE"))
      std::cout << adaptive.history.to_text({"mu_r", "mu_s"});
  }
  const double median_runs = median(runs_used), median_ratio = median(area_ratio);
  std::cout << label << ": median runs " << median_runs << " of the grid's " << kGridRuns
            << ", median area ratio " << median_ratio << ", truth inside adaptive "
            << adaptive_holds << "/" << seeds << ", grid " << grid_holds << "/" << seeds
            << ", converged " << converged << "/" << seeds << '\n';
  EXPECT_LE(median_runs, kGridRuns / 3.0);
  EXPECT_TRUE((median_ratio >= 0.85 && median_ratio <= 1.15) || adaptive_holds >= grid_holds)
      << "median area ratio " << median_ratio << ", truth inside adaptive " << adaptive_holds
      << " grid " << grid_holds;
  EXPECT_GE(converged, 4);
  EXPECT_LE(worst_corner, 0.25);
}

TEST(AdaptiveDesign, InteriorTruthMatchesTheDenseGridWithAThirdOfItsRuns) {
  check_against_grid(0.2, 0.45, "interior truth (0.2, 0.45)");
}

TEST(AdaptiveDesign, NearBoundTruthWithSaturatedAngleDoesNotPileIntoACorner) {
  check_against_grid(0.15, 0.75, "near-bound truth (0.15, 0.75)");
}

// AdaptiveDesignOptions::confirm_region_parts: a part of the 95 % region that holds no design
// point gets a run of the next batch (its reason says so) and keeps the design from being
// stable; a design that converges has no such part left. Over the near-bound truth's 5 seeds
// the rule must act at least once (seeds 3 and 5 had such a part when it was written), or
// this test tests nothing. Off (the default), no part is counted.
TEST(AdaptiveDesign, ARegionPartNoRunHasSeenGetsARunBeforeTheDesignStops) {
  int acted = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    AdaptiveDesignProblem problem{bounds(), recordings_at(0.15, 0.75, seed)};
    AdaptiveDesignOptions options = test_options(seed);
    const auto plain = run_adaptive_design(problem, options, evaluate);
    for (const auto& b : plain.history.batches) EXPECT_EQ(b.unconfirmed_parts, 0);
    options.confirm_region_parts = true;
    const auto result = run_adaptive_design(problem, options, evaluate);
    const auto& batches = result.history.batches;
    for (std::size_t k = 0; k < batches.size(); ++k) {
      if (!batches[k].complete || batches[k].unconfirmed_parts == 0) continue;
      ++acted;
      EXPECT_FALSE(batches[k].stable) << "seed " << seed << " batch " << k;
      if (k + 1 == batches.size()) continue;  // the budget ended it
      int confirming = 0;
      for (const auto& r : batches[k + 1].runs)
        confirming += r.reason.find("confirms or removes a part") != std::string::npos ? 1 : 0;
      EXPECT_EQ(confirming, std::min(batches[k].unconfirmed_parts, options.batch_size))
          << "seed " << seed << " batch " << k + 1;
    }
    if (result.history.status == AdaptiveDesignStatus::converged) {
      EXPECT_EQ(batches.back().unconfirmed_parts, 0) << "seed " << seed;
    }
    std::cout << "near-bound, confirm_region_parts, seed " << seed << ": "
              << to_string(result.history.status) << " after " << result.runs.size()
              << " runs (without: " << plain.runs.size() << ")\n";
  }
  EXPECT_GE(acted, 1);
}

TEST(AdaptiveDesign, RecordingsOutOfTheModelsRangeEndWithThatStatus) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    // 12 degrees above the truth's angle: above anything the model reaches (46.6 deg).
    AdaptiveDesignProblem problem{bounds(), recordings_at(0.35, 0.7, seed, 12.0)};
    const auto result = run_adaptive_design(problem, test_options(seed), evaluate);
    std::cout << "out of range, seed " << seed << ": " << to_string(result.history.status)
              << " after " << result.runs.size() << " runs: " << result.history.statement << '\n';
    EXPECT_EQ(result.history.status, AdaptiveDesignStatus::out_of_range);
    EXPECT_LE(result.runs.size(), 21u);
    EXPECT_NE(result.history.statement.find("out of the model's range"), std::string::npos);
  }
}

TEST(AdaptiveDesign, AResumedDesignEqualsAnUninterruptedOne) {
  AdaptiveDesignProblem problem{bounds(), recordings_at(0.2, 0.45, 7)};
  const AdaptiveDesignOptions options = test_options(7);
  const auto whole = run_adaptive_design(problem, options, evaluate);
  ASSERT_GE(whole.history.batches.size(), 3u);
  const std::size_t start = whole.history.batches[0].runs.size();
  const std::size_t after_batch_1 = start + whole.history.batches[1].runs.size();
  // Killed mid-start, at the end of batch 1, and in the middle of batch 2.
  for (const std::size_t kept : {start / 2, after_batch_1, after_batch_1 + 2}) {
    std::vector<RunResult> done(whole.runs.begin(), whole.runs.begin() + static_cast<long>(kept));
    // A run store forgets the reasons and keeps the runs in its own order.
    for (auto& r : done) r.request.reason.clear();
    std::reverse(done.begin(), done.end());
    AdaptiveDesign fresh(problem, options);
    const auto next = fresh.next_runs(done);
    ASSERT_FALSE(next.empty());
    EXPECT_EQ(next.front().batch, whole.runs[kept].request.batch) << "kept " << kept;
    EXPECT_EQ(next.front().slot, whole.runs[kept].request.slot) << "kept " << kept;
    EXPECT_EQ(next.front().theta, whole.runs[kept].request.theta) << "kept " << kept;
    const auto resumed = run_adaptive_design(problem, options, evaluate, done);
    ASSERT_EQ(resumed.runs.size(), whole.runs.size()) << "kept " << kept;
    for (std::size_t r = 0; r < whole.runs.size(); ++r) {
      EXPECT_EQ(resumed.runs[r].request.theta, whole.runs[r].request.theta);
      EXPECT_EQ(resumed.runs[r].request.seed, whole.runs[r].request.seed);
      EXPECT_EQ(resumed.runs[r].observables, whole.runs[r].observables);
    }
    EXPECT_EQ(resumed.history.to_json().dump(), whole.history.to_json().dump()) << "kept " << kept;
  }
  // Killed after the last run: nothing more to do, and the same ending.
  AdaptiveDesign fresh(problem, options);
  EXPECT_TRUE(fresh.next_runs(whole.runs).empty());
  EXPECT_EQ(fresh.history().to_json().dump(), whole.history.to_json().dump());
}

TEST(AdaptiveDesign, SameSeedSameDesignAndAForeignRunIsRejected) {
  AdaptiveDesignProblem problem{bounds(), recordings_at(0.2, 0.45, 3)};
  AdaptiveDesign a(problem, test_options(3)), b(problem, test_options(3)),
      c(problem, test_options(4));
  const auto first_a = a.next_runs({}), first_b = b.next_runs({}), first_c = c.next_runs({});
  ASSERT_EQ(first_a.size(), 12u);  // 8 points, 4 of them twice
  for (std::size_t k = 0; k < first_a.size(); ++k) EXPECT_EQ(first_a[k].theta, first_b[k].theta);
  EXPECT_NE(first_a[0].theta, first_c[0].theta);
  int replicates = 0;
  for (const auto& r : first_a) replicates += r.replicate > 0 ? 1 : 0;
  EXPECT_EQ(replicates, 4);
  RunResult foreign{first_c[0], simulate(first_c[0])};
  EXPECT_THROW(a.next_runs({foreign}), std::invalid_argument);
}

// The acquisition on the start's runs alone: a batch of distinct points, min_separation apart
// from each other and from the runs, each worth something. (A first version also required 4
// of the 6 to lie within 0.1 of the posterior's top-half nodes; 2 did: after the start the
// weighted IMSE spreads the batch along the discharge time's iso-line, e.g. its first choice
// was (0.353, 0.42) for the truth (0.2, 0.45). That expectation was dropped, not tuned for.)
TEST(AdaptiveDesign, TheBatchKeepsItsDistanceAndEachChoiceIsWorthSomething) {
  AdaptiveDesignProblem problem{bounds(), recordings_at(0.2, 0.45, 2)};
  const AdaptiveDesignOptions options = test_options(2);
  AdaptiveDesign design(problem, options);
  std::vector<RunResult> done;
  for (const auto& r : design.next_runs({})) done.push_back({r, simulate(r)});
  ASSERT_TRUE(design.next_runs(done).size() > 0);
  const RunsCalibration* c = design.latest_calibration();
  ASSERT_NE(c, nullptr);
  const CalibrationProblem cp(bounds(), c->targets);
  const PosteriorWeights w = posterior_weights(cp, options);
  EXPECT_NEAR(w.weights.sum(), 1.0, 1e-12);
  Eigen::MatrixXd design_points(static_cast<Eigen::Index>(done.size()), 2);
  for (std::size_t r = 0; r < done.size(); ++r)
    design_points.row(static_cast<Eigen::Index>(r)) << done[r].request.theta[0],
        done[r].request.theta[1];
  const std::vector<double> noise = {kAoRScatterDeg * kAoRScatterDeg, 0.0036};
  const auto batch = choose_batch(cp, w, noise, design_points, 6, options);
  ASSERT_EQ(batch.size(), 6u);
  std::vector<Eigen::VectorXd> taken;
  for (Eigen::Index r = 0; r < design_points.rows(); ++r)
    taken.push_back(cp.to_unit(design_points.row(r).transpose()));
  for (const auto& choice : batch) {
    EXPECT_GT(choice.value, 0.0);
    const Eigen::VectorXd u = cp.to_unit(choice.theta);
    for (const auto& t : taken) EXPECT_GE((u - t).norm(), options.min_separation);
    taken.push_back(u);
  }
  // Later choices are worth no more than the first: the believer has taken its variance.
  EXPECT_LE(batch.back().value, batch.front().value);
}

// The swing-damping weights (AdaptiveDesignOptions::acquisition_tempering and
// acquisition_weight_batches): tempering spreads the weight (a lower peak, more nodes to
// carry 99.9 %), the mean of a weighting with itself is itself, the mean of two keeps every
// node of both, and the joint drop of a batch valued by batch_variance_drop is the sum of its
// choices' values (each is the believer's increment), so the stopping rule's expected gain
// means the same whichever weights chose the batch.
TEST(AdaptiveDesign, TemperedAndAveragedWeightsAreProperWeightings) {
  AdaptiveDesignProblem problem{bounds(), recordings_at(0.2, 0.45, 2)};
  const AdaptiveDesignOptions options = test_options(2);
  AdaptiveDesign design(problem, options);
  std::vector<RunResult> done;
  for (const auto& r : design.next_runs({})) done.push_back({r, simulate(r)});
  ASSERT_TRUE(design.next_runs(done).size() > 0);
  const CalibrationProblem cp(bounds(), design.latest_calibration()->targets);
  const PosteriorWeights w = posterior_weights(cp, options);
  const PosteriorWeights t = posterior_weights(cp, options, 0.5);
  EXPECT_NEAR(t.weights.sum(), 1.0, 1e-12);
  EXPECT_LT(t.weights(0), w.weights(0));
  EXPECT_GE(t.points.rows(), w.points.rows());
  EXPECT_THROW(posterior_weights(cp, options, 0.0), std::invalid_argument);
  EXPECT_THROW(posterior_weights(cp, options, 1.5), std::invalid_argument);
  const PosteriorWeights same = average_weights(w, w);
  ASSERT_EQ(same.points.rows(), w.points.rows());
  EXPECT_NEAR(same.weights.sum(), 1.0, 1e-12);
  EXPECT_NEAR(same.weights(0), w.weights(0), 1e-12);
  EXPECT_TRUE(same.points.row(0).isApprox(w.points.row(0)));
  const PosteriorWeights both = average_weights(w, t);
  EXPECT_GE(both.points.rows(), t.points.rows());
  EXPECT_NEAR(both.weights.sum(), 1.0, 1e-12);
  for (Eigen::Index g = 1; g < both.weights.size(); ++g)
    EXPECT_LE(both.weights(g), both.weights(g - 1));
  Eigen::MatrixXd design_points(static_cast<Eigen::Index>(done.size()), 2);
  for (std::size_t r = 0; r < done.size(); ++r)
    design_points.row(static_cast<Eigen::Index>(r)) << done[r].request.theta[0],
        done[r].request.theta[1];
  const std::vector<double> noise = {kAoRScatterDeg * kAoRScatterDeg, 0.0036};
  const auto batch = choose_batch(cp, w, noise, design_points, 3, options);
  ASSERT_EQ(batch.size(), 3u);
  Eigen::MatrixXd chosen(3, 2);
  double sum = 0.0;
  for (Eigen::Index c = 0; c < 3; ++c) {
    chosen.row(c) = batch[static_cast<std::size_t>(c)].theta.transpose();
    sum += batch[static_cast<std::size_t>(c)].value;
  }
  EXPECT_NEAR(batch_variance_drop(cp, w, noise, chosen), sum, 1e-9 * std::max(1.0, sum));
}

// AdaptiveDesignOptions::space_filling_batch: the first batch after the start fills the
// high-posterior set: its new points are min_separation from the runs and from each other,
// lie where the posterior puts weight, say why they were chosen, and the design's record
// still values the next batch (expected gain between 0 and 1).
TEST(AdaptiveDesign, SpaceFillingBatchKeepsItsDistanceInsideTheHighPosteriorSet) {
  AdaptiveDesignProblem problem{bounds(), recordings_at(0.2, 0.45, 2)};
  AdaptiveDesignOptions options = test_options(2);
  options.space_filling_batch = true;
  AdaptiveDesign design(problem, options);
  std::vector<RunResult> done;
  for (const auto& r : design.next_runs({})) done.push_back({r, simulate(r)});
  const auto next = design.next_runs(done);
  ASSERT_EQ(next.size(), static_cast<std::size_t>(options.batch_size));
  const CalibrationProblem cp(bounds(), design.latest_calibration()->targets);
  const PosteriorWeights w = posterior_weights(cp, options);
  std::vector<Eigen::VectorXd> taken;
  for (const auto& r : done)
    taken.push_back(cp.to_unit(Eigen::Vector2d(r.request.theta[0], r.request.theta[1])));
  int filled = 0;
  for (const auto& r : next) {
    if (r.reason.find("space-filling") == std::string::npos) continue;  // a replicate
    ++filled;
    const Eigen::Vector2d theta(r.theta[0], r.theta[1]);
    const Eigen::VectorXd u = cp.to_unit(theta);
    for (const auto& t : taken) EXPECT_GE((u - t).norm(), options.min_separation);
    taken.push_back(u);
    bool on_a_weighted_node = false;
    for (Eigen::Index g = 0; g < w.points.rows(); ++g)
      on_a_weighted_node |= (w.points.row(g).transpose() - theta).norm() < 1e-12;
    EXPECT_TRUE(on_a_weighted_node) << theta.transpose();
  }
  EXPECT_GE(filled, 1);
  const auto& rec = design.history().batches.at(0);
  EXPECT_GT(rec.expected_area_gain, 0.0);
  EXPECT_LE(rec.expected_area_gain, 1.0);
}

TEST(AdaptiveDesign, OptionsValidateWithReadableErrors) {
  AdaptiveDesignOptions o;
  std::string error;
  EXPECT_TRUE(o.Validate(&error)) << error;
  o.batch_size = 0;
  EXPECT_FALSE(o.Validate(&error));
  EXPECT_NE(error.find("batch_size must be >= 1, got 0"), std::string::npos) << error;
  o = AdaptiveDesignOptions{};
  o.max_runs = 5;
  EXPECT_FALSE(o.Validate(&error));
  EXPECT_NE(error.find("max_runs"), std::string::npos) << error;
  o = AdaptiveDesignOptions{};
  o.surrogate.model = "polynomial";
  EXPECT_FALSE(o.Validate(&error));
  EXPECT_NE(error.find("gaussian_process"), std::string::npos) << error;
  o = AdaptiveDesignOptions{};
  o.calibration.confidence = 1.5;
  EXPECT_FALSE(o.Validate(&error));
  EXPECT_NE(error.find("confidence"), std::string::npos) << error;
  o = AdaptiveDesignOptions{};
  o.acquisition_weight_batches = 3;
  EXPECT_FALSE(o.Validate(&error));
  EXPECT_NE(error.find("acquisition_weight_batches must be 1 or 2, got 3"), std::string::npos)
      << error;
  o = AdaptiveDesignOptions{};
  o.acquisition_tempering = 0.0;
  EXPECT_FALSE(o.Validate(&error));
  EXPECT_NE(error.find("acquisition_tempering must be in (0, 1]"), std::string::npos) << error;
  EXPECT_THROW(AdaptiveDesign({bounds(), {}}, AdaptiveDesignOptions{}), std::invalid_argument);
  auto four = bounds();
  four.push_back({"e", 0.1, 0.9});
  four.push_back({"k", 1.0, 2.0});
  EXPECT_THROW(AdaptiveDesign({four, recordings_at(0.2, 0.45, 1)}, AdaptiveDesignOptions{}),
               std::invalid_argument);
}

}  // namespace
}  // namespace demcal::calibrate
