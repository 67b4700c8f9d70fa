#pragma once
// The [diagnosis] table of a study config: how `demcal diagnose` looks for the
// physics the base model left out (calibrate/discrepancy_diagnosis.hpp).
// Every key is optional:
//
//   [diagnosis]
//   candidates = ["cohesion", "grain_cohesion", "wall_friction", "air_drag", "size_spread"]
//                                     # default: every one config/physics_candidates.hpp knows
//   alpha = 0.01                      # significance of the goodness-of-fit test, (0, 0.5)
//   hold_out = ["conical_pile"]       # setups whose recordings are predicted, never fitted
//   probe_replicates = 2              # DEM runs per setup at the base fit with the candidate
//                                     #   switched on (its sensitivity), 1..100
//   leading = 2                       # candidates that get an extended design, 1..10
//   extended_points = 16              # Latin hypercube points in (parameters, candidate), 4..10000
//   design_extensions = 2             # rounds the base design may grow by before anything is
//                                     #   said, reproduced or not, 0..10 (0: never): each round
//                                     #   runs when the base fit sits on a design bound or the
//                                     #   surrogates there are less sure than the DEM scatters
//   candidate_refinements = 0         # rounds a leading candidate's extended design may be
//                                     #   densified about the candidate's own fit, 0..5 (0:
//                                     #   never): each runs when a fitted target's surrogate is
//                                     #   less sure there than one DEM run scatters. Off by
//                                     #   default: measured and not adopted (issue 19, stage 5,
//                                     #   tests/concealed/stage5/README.md)
//   required_log_bayes_factor = 3.0   # ln B a candidate must reach over the base model AND
//                                     #   over a generic model discrepancy to be named, [0, 50]
//                                     #   (3 = a Bayes factor of 20, "strong"); below it the
//                                     #   mismatch is reported as unexplained
//   probe_grid = 200                  # the probes run at the base fit snapped to 1/probe_grid of
//                                     #   each range, 2..100000: diagnoses of nearly equal
//                                     #   recordings (noise seeds) share the probe runs; a coarse
//                                     #   grid trades a probe slightly off the fit for that
//   [diagnosis.cohesion]              # opt, per candidate: its range and probe value
//   lower = 0.0
//   upper = 5e-3
//   probe = 2e-3
//   [diagnosis.plausible]             # opt, per design parameter: [lower, upper] of the values
//   mu_r = [0.0, 0.5]                 #   the material can have (enclosing the design's box).
//   mu_s = [0.1, 1.0]                 #   The base design never grows beyond them, and a base
//                                     #   fit that sits on one of them counts as a mismatch:
//                                     #   the recordings are matched only by a value the
//                                     #   material cannot have, so the candidates are probed

#include "config/toml_reader.hpp"
#include "surrogate/full_factorial_design.hpp"

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace demcal::config {

struct CandidateRange {
  std::optional<double> lower, upper, probe;
};

struct DiagnosisConfig {
  std::vector<std::string> candidates;  // names, in the order to report
  double alpha = 0.01;
  std::vector<std::string> hold_out;  // setup names
  int probe_replicates = 2;
  int leading = 2;
  int extended_points = 16;
  int design_extensions = 2;
  int candidate_refinements = 0;
  double required_log_bayes_factor = 3.0;
  int probe_grid = 200;
  std::map<std::string, CandidateRange> ranges;  // per candidate, what the study overrides
  // Per design parameter (by name), [lower, upper] of the material's plausible values;
  // a parameter not listed has none (only the default rule: a lower bound of 0 is physical).
  std::map<std::string, std::pair<double, double>> plausible;
  std::size_t line = 0;
};

// Reads [diagnosis] if present; `setups` are the study's apparatus names (for hold_out),
// `design` the study's design parameters with their boxes (for [diagnosis.plausible]; empty
// when the study has no [design]).
std::optional<DiagnosisConfig> read_diagnosis(reader::Table& root,
                                              const std::vector<std::string>& setups,
                                              const std::vector<surrogate::ParameterRange>& design);

}  // namespace demcal::config
