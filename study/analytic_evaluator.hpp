#pragma once
// A run evaluator (study/run_evaluator.hpp) without a DEM: smooth closed-form
// observables of the study's parameters plus seeded Gaussian noise, so that
// the whole workflow — design, runs, surrogates, calibration (`demcal study`)
// and the diagnosis of missing physics (`demcal diagnose`) — runs end to end
// in seconds (tests/unit/test_workflow_golden.cpp). Its numbers stand for no
// material: what it makes testable is the pipeline around the runs.
//
// What it reads, from the study resolved for the run (absent keys count as 0):
//   mu_r    interaction.particle_particle.rolling_friction
//   mu_s    interaction.particle_particle.sliding_friction
//   mu_w    interaction.particle_wall.sliding_friction         (candidate wall_friction)
//   gamma   interaction.particle_particle.surface_energy_j_m2  (candidate cohesion), J/m2
//   drag    air.drag_scale                                     (candidate air_drag)
//   spread  material.size.relative_half_width                  (candidate size_spread)
//   the apparatus' boundary and thickness_diameters: a container between walls
//   ("walls") feels the walls by w = 1 / thickness_diameters, a periodic one not (w = 0).
// What it gives (every apparatus):
//   angle_of_repose_deg = 15 + 25 tanh(2.5 mu_r) + 12 mu_s + 20 w mu_w
//                         + 4000 gamma (1 + 6 w) - 0.5 drag              + N(0, aor_noise_deg)
//   bulk_density_kg_m3  = density (0.62 - 0.06 mu_s - 0.04 tanh(3 mu_r) - 0.05 w
//                         - 60 gamma + 0.03 spread) (1 + N(0, bulk_density_relative_noise))
// and, for a sandglass, discharge_time_s = 2 (1 + 0.8 mu_s + 0.5 mu_r + 200 gamma
// + 0.2 drag) (1 + N(0, discharge_relative_noise)). The noise is drawn from the
// run's seed and the apparatus' name alone (a portable generator and Box-Muller),
// so a run's result depends on its key as a DEM run's does.
//
// Its records carry "evaluator": {"kind": "analytic", ...}: a run store filled by
// it must not be read as DEM runs (their keys are the same hashes).

#include "study/run_evaluator.hpp"

#include <memory>

namespace demcal::study {

struct AnalyticEvaluatorOptions {
  double aor_noise_deg = 0.4;                  // sd of the angle of repose
  double bulk_density_relative_noise = 0.003;  // relative sd of the bulk density
  double discharge_relative_noise = 0.01;      // relative sd of the discharge time
};

class AnalyticEvaluator final : public RunEvaluator {
 public:
  explicit AnalyticEvaluator(AnalyticEvaluatorOptions options = {});
  // Throws ConfigError (naming the key) when a parameter it reads is not a number.
  std::unique_ptr<PreparedRun> prepare(const RunRequest& request) const override;

 private:
  AnalyticEvaluatorOptions options_;
};

}  // namespace demcal::study
