// Model discrepancy as a competitor (issue 19): the generic discrepancy of
// calibrate/model_discrepancy.hpp against the named candidates, on the analytic world of
// tests/support/analytic_world.hpp (two base parameters, three sandglass orifices with
// discharge time and AoR, three container thicknesses with AoR, candidates cohesion, wall
// friction and moisture), with the effect no candidate has that this suite added: a constant
// offset of every discharge time (1 s; it was first 0.3 s, detected in 3 of 5 seeds only since a
// higher mu_s absorbs most of it -- judged "discrepancy" in all 3, with no target standing out --
// so it was raised to test the decision rather than the detection).
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
// widened intervals contain the base ones; every estimate lies inside its interval and the
// bounds, also when the unbounded step leaves a tight box (and the statement says so);
// option and input errors.
#include "calibrate/discrepancy_diagnosis.hpp"
#include "calibrate/model_discrepancy.hpp"
#include "tests/support/analytic_world.hpp"

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

using namespace demcal::testing::analytic_world;

// ---------------------------------------------------------------------------------------
// Detection
// ---------------------------------------------------------------------------------------
// The competitor

struct Judged {
  std::vector<double> y;
  DiscrepancyDiagnosis d;
  DiscrepancyEvidence disc;
  ExplanationDecision decision;
};

Judged judge(int e, double phi, unsigned long seed) {
  DiagnosisOptions o = quick_options();
  o.leading_candidates = kCandidates;  // every candidate refitted: the best is compared
  Judged j;
  const WorldRun run = diagnose(e, phi, seed, o);
  j.y = run.y;
  j.d = run.d;
  // What the workflow calls after diagnose_discrepancy (base_targets() ends with the held-out
  // ones).
  const DiscrepancyJudgement judged = judge_against_discrepancy(base_bounds(), base_targets(run.y),
                                                                kHeldOut, j.d, setup_variables());
  EXPECT_TRUE(judged.available) << judged.note;
  j.disc = judged.discrepancy;
  j.decision = judged.decision;
  // Every estimate lies inside its own interval, and both inside the bounds, wherever the
  // unconstrained Laplace step went; a step past a bound is said.
  const auto bounds = base_bounds();
  for (std::size_t k = 0; k < bounds.size(); ++k) {
    const double value = j.disc.theta(static_cast<Eigen::Index>(k));
    const double free_value = j.disc.unconstrained_theta(static_cast<Eigen::Index>(k));
    EXPECT_LE(bounds[k].lower, j.disc.lower[k]);
    EXPECT_LE(j.disc.lower[k], value);
    EXPECT_LE(value, j.disc.upper[k]);
    EXPECT_LE(j.disc.upper[k], bounds[k].upper);
    if ((free_value < bounds[k].lower || free_value > bounds[k].upper) &&
        j.decision.verdict == Explanation::discrepancy) {
      EXPECT_NE(j.decision.statement.find("held to the design's range"), std::string::npos);
    }
  }
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

// A candidate that beats the discrepancy by the margin but not the base model is not named,
// and the statement says which of the two stood in the way (it said "not better than a
// generic discrepancy, Bayes factor 63" on a cross-engine null, stop 51).
TEST(ModelDiscrepancy, ACandidateThatDoesNotBeatTheBaseModelIsNotNamedAndItIsSaid) {
  const Judged j = judge(kCohesion, kCohesionTruth, 100);
  ASSERT_EQ(j.decision.verdict, Explanation::physics) << j.decision.statement;
  std::vector<ModelEvidence> evidences;
  for (const auto& f : j.d.fits) evidences.push_back(f.evidence);
  const auto best = std::max_element(evidences.begin(), evidences.end(),
                                     [](const ModelEvidence& a, const ModelEvidence& b) {
                                       return a.log_evidence < b.log_evidence;
                                     });
  ModelEvidence base = j.d.base_evidence;
  base.log_evidence = best->log_evidence - 1.0;  // the candidate over the base: e^1, short of e^3
  const ExplanationDecision d = decide_explanation(j.d.detection, base, evidences, j.disc);
  EXPECT_EQ(d.verdict, Explanation::discrepancy);
  EXPECT_NE(d.statement.find("is better than a generic discrepancy"), std::string::npos)
      << d.statement;
  EXPECT_NE(d.statement.find("but not better than the base model itself"), std::string::npos)
      << d.statement;
  EXPECT_EQ(d.statement.find("is not better than a generic discrepancy"), std::string::npos)
      << d.statement;
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

TEST(ModelDiscrepancy, AnEstimatePastABoundIsHeldToTheBoxAndSaid) {
  // The discrepancy's Laplace step extrapolates and can leave the design box (a fresh
  // concealed study printed "mu_s = 1.65 (1.08-1.1)"). Boxed tightly around the base fit of
  // a discharge-time offset (+-0.002), the step must leave it; the values and intervals
  // stay inside, and the statement says where the unbounded fit went.
  const Judged j = judge(kTimeBias, 1.0, 400);
  ASSERT_EQ(j.decision.verdict, Explanation::discrepancy);
  const Eigen::VectorXd theta_hat = j.d.base.minima.front().theta;
  auto bounds = base_bounds();
  for (std::size_t k = 0; k < bounds.size(); ++k) {
    bounds[k].lower = theta_hat(static_cast<Eigen::Index>(k)) - 0.002;
    bounds[k].upper = theta_hat(static_cast<Eigen::Index>(k)) + 0.002;
  }
  const CalibrationProblem boxed(bounds, without_held_out(base_targets(j.y)));
  const DiscrepancyEvidence disc = discrepancy_evidence(boxed, theta_hat, setup_variables());
  int outside = 0;
  for (std::size_t k = 0; k < bounds.size(); ++k) {
    const auto kk = static_cast<Eigen::Index>(k);
    const double free_value = disc.unconstrained_theta(kk);
    if (free_value < bounds[k].lower || free_value > bounds[k].upper) ++outside;
    EXPECT_LE(bounds[k].lower, disc.lower[k]);
    EXPECT_LE(disc.lower[k], disc.theta(kk));
    EXPECT_LE(disc.theta(kk), disc.upper[k]);
    EXPECT_LE(disc.upper[k], bounds[k].upper);
    EXPECT_LE(bounds[k].lower, disc.base_lower[k]);
    EXPECT_LE(disc.base_upper[k], bounds[k].upper);
  }
  ASSERT_GE(outside, 1) << "the step stayed inside +-0.002; the test needs a tighter box";
  std::vector<ModelEvidence> evidences;
  for (const auto& f : j.d.fits) evidences.push_back(f.evidence);
  const ExplanationDecision d =
      decide_explanation(j.d.detection, j.d.base_evidence, evidences, disc);
  ASSERT_EQ(d.verdict, Explanation::discrepancy) << d.statement;
  EXPECT_NE(d.statement.find("Unbounded, the fit with the discrepancy would put"),
            std::string::npos)
      << d.statement;
  EXPECT_NE(d.statement.find("held to the design's range"), std::string::npos) << d.statement;
  EXPECT_TRUE(d.statement.find("above the upper bound") != std::string::npos ||
              d.statement.find("below the lower bound") != std::string::npos)
      << d.statement;
  std::printf("[model discrepancy] boxed: %s\n", d.statement.c_str());
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
