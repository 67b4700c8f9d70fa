// Issue 16's proof on the lined recovery study, as a REPLAY: the "DEM" is an emulator built
// from the 100 checked-in runs of studies/sandglass-recovery-lined (doe.csv: 5 x 5 points x 4
// replicates): per observable the Gaussian process the grid's own calibration fits (its mean),
// plus Gaussian noise with the grid's measured replicate scatter (pooled sd), seeded by the
// run's seed. Where the grid's runs gave no angle (the mu_s = 0.2 row: the lined floor spread
// the pile flat) the emulator gives none below mu_s = 0.2875 either. This is not DEM: it
// tests the design's statistics on a response the size and shape of the real one.
//
// For each of 20 laboratories (recordings made as tests/unit/test_recovery_over_noise_seeds.cpp
// makes them: the mean of ten of the 200 truth runs at (0.25, 0.45), truth_runs.csv, plus the
// instrument's error) it calibrates (a) the 100-run grid (its real DEM runs) and (b) an
// adaptive design with the default options run against the emulator, with the same code
// (calibrate::calibrate_runs), and prints per laboratory runs, area ratio, truth inside,
// mu_s identified; then the medians. Options: --truth mu_r,mu_s makes the recordings from the
// emulator's noise-free mean there instead (a point near a bound, one where the AoR saturates),
// --emulator-labs 1 draws each laboratory's ten tests from the emulator at the truth (so that
// the emulator's own error at the truth, shared by all 20 laboratories, is not charged to the
// design), --offset-aor DEG adds DEG to every recorded angle (out of the model's range).
//
//   build/bench/demcal_adaptive_replay [--labs 20] [--truth 0.1,0.85] [--emulator-labs 1]
//                                      [--offset-aor 12] [--lab-seed-base 1000]
//                                      [--weight-batches 2] [--tempering 0.5] [--max-runs 32]
//                                      [--space-filling 1] [--confirm-parts 1]
#include "calibrate/adaptive_design.hpp"
#include "calibrate/calibration_problem.hpp"
#include "calibrate/confidence_region.hpp"
#include "calibrate/runs_calibration.hpp"
#include "calibrate/weighted_variance_acquisition.hpp"
#include "config/doe_csv.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace demcal;
using calibrate::RunRequest;
using calibrate::RunResult;

namespace {

const std::string kDir = std::string(DEMCAL_SOURCE_DIR) + "/studies/sandglass-recovery-lined/";
const double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<std::pair<double, double>> truth_runs() {
  std::ifstream in(kDir + "truth_runs.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::pair<double, double>> runs;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string seed, aor, time;
    std::getline(row, seed, ',');
    std::getline(row, aor, ',');
    std::getline(row, time, ',');
    runs.emplace_back(std::stod(aor), std::stod(time));
  }
  return runs;
}

std::vector<calibrate::Recording> recordings(double aor, double time) {
  calibrate::Recording a{"sandglass", "angle_of_repose_deg", aor, 0.5, 10, "deg", 0};
  calibrate::Recording t{"sandglass", "discharge_time_s", time, 0.01 * time, 10, "s", 0};
  return {a, t};
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? kNaN : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Judged {
  double area = kNaN;
  bool inside = false, mu_s_identified = false;
};

Judged judge(const calibrate::RunsCalibration& c, const std::vector<calibrate::ParameterBounds>& b,
             const Eigen::Vector2d& truth) {
  Judged j;
  j.area = c.result.region.area;
  const calibrate::CalibrationProblem problem(b, c.targets);
  j.inside = c.result.region.available && calibrate::region_contains(problem, c.result.region, truth);
  j.mu_s_identified = c.result.identified.size() > 1 && c.result.identified[1];
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  int labs = 20;
  bool fixed_truth = false;
  Eigen::Vector2d truth(0.25, 0.45);
  double offset_aor = 0.0;
  bool emulator_labs = false;
  // Seeds of the laboratories' draws (emulator tests: base + 4000 + k, instrument error:
  // base + k) and of their designs (base - 1000 + k): another base gives another set of
  // laboratories, for checking a method on cases it was not tuned on.
  std::uint64_t lab_seed_base = 1000;
  // The swing-damping options of AdaptiveDesignOptions (defaults: off).
  int weight_batches = 1;
  double tempering = 1.0;
  bool confirm_parts = false;
  // A smaller run budget: what the region is when the design must stop there (diagnostic).
  int max_runs = calibrate::AdaptiveDesignOptions{}.max_runs;
  bool space_filling = false;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--labs") labs = std::stoi(v);
    else if (k == "--truth") {
      fixed_truth = true;
      truth << std::stod(v.substr(0, v.find(','))), std::stod(v.substr(v.find(',') + 1));
    } else if (k == "--offset-aor") offset_aor = std::stod(v);
    else if (k == "--emulator-labs") emulator_labs = v == "1";
    else if (k == "--lab-seed-base") lab_seed_base = std::stoull(v);
    else if (k == "--weight-batches") weight_batches = std::stoi(v);
    else if (k == "--tempering") tempering = std::stod(v);
    else if (k == "--max-runs") max_runs = std::stoi(v);
    else if (k == "--space-filling") space_filling = v == "1";
    else if (k == "--confirm-parts") confirm_parts = v == "1";
    else {
      std::cerr << "unknown option " << k << "\n";
      return 2;
    }
  }
  const std::vector<calibrate::ParameterBounds> bounds{{"mu_r", 0.05, 0.6}, {"mu_s", 0.2, 0.9}};
  const config::DoeCsv grid_csv = config::read_doe_csv(kDir + "doe.csv");
  const int ia = grid_csv.observable_index("angle_of_repose_deg");
  const int it = grid_csv.observable_index("discharge_time_s");
  std::vector<RunResult> grid;
  for (std::size_t i = 0; i < grid_csv.rows.size(); ++i) {
    const auto& r = grid_csv.rows[i];
    RunResult x;
    x.request.batch = 0;
    x.request.slot = i;
    x.request.theta = r.parameters;
    x.request.replicate = r.replicate;
    x.request.seed = r.seed;
    x.observables = {r.observables[static_cast<std::size_t>(ia)],
                     r.observables[static_cast<std::size_t>(it)]};
    grid.push_back(x);
  }
  calibrate::AdaptiveDesignOptions options;  // the defaults, as [design] kind = "adaptive"
  options.acquisition_weight_batches = weight_batches;
  options.acquisition_tempering = tempering;
  options.confirm_region_parts = confirm_parts;
  options.max_runs = max_runs;
  options.space_filling_batch = space_filling;
  if (std::string error; !options.Validate(&error)) {
    std::cerr << error << "\n";
    return 2;
  }
  std::printf("adaptive options: acquisition_weight_batches %d, acquisition_tempering %g, max_runs %d, "
              "space_filling_batch %d, confirm_region_parts %d\n",
              weight_batches, tempering, max_runs, space_filling ? 1 : 0, confirm_parts ? 1 : 0);
  // The emulator: the grid's GPs (fitted against any recordings: the fit does not use them).
  const auto emulator = calibrate::calibrate_runs(bounds, recordings(30.0, 0.53), grid,
                                                  options.surrogate, options.calibration);
  const double sd_aor = emulator.surrogates[0].scatter.sd, sd_time = emulator.surrogates[1].scatter.sd;
  std::printf("emulator: GP means of the 100-run grid; noise sd AoR %.3f deg, time %.4f s\n", sd_aor,
              sd_time);
  const auto mean_at = [&](const std::vector<double>& theta) {
    Eigen::MatrixXd x(1, 2);
    x << theta[0], theta[1];
    return std::pair<double, double>{emulator.surrogates[0].model->predict_mean(x)(0),
                                     emulator.surrogates[1].model->predict_mean(x)(0)};
  };
  const calibrate::RunEvaluator evaluate = [&](const std::vector<RunRequest>& batch) {
    std::vector<std::vector<double>> out;
    for (const RunRequest& r : batch) {
      std::mt19937_64 rng(r.seed);
      std::normal_distribution<double> unit(0.0, 1.0);
      const auto [a, t] = mean_at(r.theta);
      const double aor = a + sd_aor * unit(rng), time = t + sd_time * unit(rng);
      out.push_back({r.theta[1] < 0.2875 ? kNaN : aor, time});
    }
    return out;
  };

  const auto truth_tests = truth_runs();
  {
    // The emulator's own error at the truth: what every laboratory made from truth_runs.csv
    // shares, and what a design that learns the emulator well is charged with.
    double a = 0.0, t = 0.0;
    for (const auto& r : truth_tests) a += r.first / truth_tests.size(), t += r.second / truth_tests.size();
    const auto [ea, et] = mean_at({truth(0), truth(1)});
    std::printf("at the truth (%.3g, %.3g): emulator AoR %.3f deg, time %.4f s; truth_runs.csv mean (%zu runs) "
                "AoR %.3f deg, time %.4f s\n", truth(0), truth(1), ea, et, truth_tests.size(), a, t);
  }
  std::vector<double> runs, ratios;
  // The swing: the area changes of the batches after the scatter has its degrees of freedom
  // (from then on only the area, the point and the gain keep a design running), over all
  // laboratories; and how many of them exceed area_tolerance.
  std::vector<double> late_changes;
  int inside_a = 0, inside_g = 0, mus_a = 0, mus_g = 0;
  std::printf("lab  runs  batches  status            area_adaptive  area_grid  ratio  inside(a/g)  mu_s id(a/g)\n");
  for (int k = 1; k <= labs; ++k) {
    double aor = 0.0, time = 0.0;
    if (emulator_labs) {
      // The laboratory's ten tests drawn from the emulator itself at the truth.
      const auto [a, t] = mean_at({truth(0), truth(1)});
      std::mt19937_64 lab(lab_seed_base + 4000 + static_cast<std::uint64_t>(k));
      std::normal_distribution<double> z(0.0, 1.0);
      aor = a + sd_aor / std::sqrt(10.0) * z(lab);
      time = t + sd_time / std::sqrt(10.0) * z(lab);
    } else if (fixed_truth) {
      const auto [a, t] = mean_at({truth(0), truth(1)});
      aor = a, time = t;
    } else {
      for (int i = 10 * (k - 1); i < 10 * k; ++i) {
        aor += truth_tests.at(static_cast<std::size_t>(i)).first / 10.0;
        time += truth_tests.at(static_cast<std::size_t>(i)).second / 10.0;
      }
    }
    std::mt19937_64 rng(lab_seed_base + static_cast<std::uint64_t>(k));
    std::normal_distribution<double> unit(0.0, 1.0);
    aor += 0.5 * unit(rng) + offset_aor;
    time += 0.01 * time * unit(rng);
    calibrate::AdaptiveDesignProblem problem{bounds, recordings(aor, time)};
    calibrate::AdaptiveDesignOptions o = options;
    o.seed = lab_seed_base - 1000 + static_cast<std::uint64_t>(k);
    const auto adaptive = calibrate::run_adaptive_design(problem, o, evaluate);
    const auto g = calibrate::calibrate_runs(bounds, problem.recordings, grid, o.surrogate, o.calibration);
    const Judged ja = judge(adaptive.calibration, bounds, truth), jg = judge(g, bounds, truth);
    runs.push_back(static_cast<double>(adaptive.runs.size()));
    for (const auto& b : adaptive.history.batches)
      if (b.complete && b.index > 0 && std::isfinite(b.area_change) &&
          b.scatter_degrees_of_freedom >= o.scatter_degrees_of_freedom)
        late_changes.push_back(b.area_change);
    ratios.push_back(ja.area / jg.area);
    inside_a += ja.inside, inside_g += jg.inside, mus_a += ja.mu_s_identified, mus_g += jg.mu_s_identified;
    std::printf("%3d  %4zu  %7zu  %-16s  %13.4f  %9.4f  %5.2f  %d/%d          %d/%d\n", k,
                adaptive.runs.size(), adaptive.history.batches.size(),
                calibrate::to_string(adaptive.history.status), ja.area, jg.area, ja.area / jg.area,
                ja.inside, jg.inside, ja.mu_s_identified, jg.mu_s_identified);
    if (!ja.mu_s_identified) {
      // Why not: the 95 % region's mu_s extent reaches a bound, or the best point is
      // rank deficient with mu_s in its weakest direction (calibration.cpp, kWeakShare).
      const auto& r = adaptive.calibration.result;
      const auto& e = r.region.extent.at(1);
      const auto& m = r.minima.at(0);
      std::printf("     mu_s not identified: 95 %% region mu_s %.3f-%.3f%s%s; best point (%.3f, %.3f)%s\n",
                  e.lower, e.upper, e.touches_lower_bound ? ", reaches the lower bound" : "",
                  e.touches_upper_bound ? ", reaches the upper bound" : "", m.theta(0), m.theta(1),
                  m.rank_deficient ? ", rank deficient there" : "");
    }
    std::printf("     scatter sd (adaptive / grid): AoR %.3f / %.3f, time %.4f / %.4f; surrogate variance / noise "
                "(adaptive / grid) %.2f / %.2f\n",
                adaptive.calibration.surrogates[0].scatter.sd, g.surrogates[0].scatter.sd,
                adaptive.calibration.surrogates[1].scatter.sd, g.surrogates[1].scatter.sd,
                adaptive.history.batches.back().surrogate_variance_ratio,
                calibrate::weighted_surrogate_variance(
                    calibrate::CalibrationProblem(bounds, g.targets),
                    calibrate::posterior_weights(calibrate::CalibrationProblem(bounds, g.targets), o)));
    if (k == 1 || adaptive.history.status != calibrate::AdaptiveDesignStatus::converged)
      std::printf("     %s\n", adaptive.history.statement.c_str());
    // DEMCAL_REPLAY_HISTORY=k prints laboratory k's design history.
    if (const char* h = std::getenv("DEMCAL_REPLAY_HISTORY"); h && std::atoi(h) == k)
      std::printf("%s\n", adaptive.history.to_text({"mu_r", "mu_s"}).c_str());
    std::fflush(stdout);
  }
  std::vector<double> sorted_runs = runs;
  std::sort(sorted_runs.begin(), sorted_runs.end());
  std::printf("runs per lab: median %.1f (%.0f to %.0f); area adaptive / grid: median %.3f (%.3f to %.3f)\n",
              median(runs), sorted_runs.front(), sorted_runs.back(), median(ratios),
              *std::min_element(ratios.begin(), ratios.end()),
              *std::max_element(ratios.begin(), ratios.end()));
  const auto swinging = std::count_if(late_changes.begin(), late_changes.end(),
                                      [&](double c) { return c > options.area_tolerance; });
  std::printf("swing: area change of the batches after the scatter's dof are reached: median %.3f, "
              "%td of %zu above area_tolerance %.2f\n",
              median(late_changes), swinging, late_changes.size(), options.area_tolerance);
  std::printf("truth inside: adaptive %d/%d, grid %d/%d; mu_s identified: adaptive %d/%d, grid %d/%d\n",
              inside_a, labs, inside_g, labs, mus_a, labs, mus_g, labs);
  return 0;
}
