#pragma once
// How much a target's mean moves with a candidate physics' parameter phi, measured by probe
// runs at the base fit (the signature the score test ranks candidates by,
// calibrate/candidate_score.hpp), with its standard error.
//
// Two forms, chosen by what was run:
//   - two probes, at phi_a and phi_b (a candidate whose base value lies inside its range is
//     probed on both sides): the secant through their means, DEM against DEM, no surrogate
//     in it: s = (m_a - m_b) / (phi_a - phi_b), se = sd sqrt(1/n_a + 1/n_b) / |phi_a - phi_b|;
//   - one probe at phi_a against the surrogate's prediction at the base value phi_0 (the
//     surrogate was fitted with phi at phi_0): s = (m_a - mu) / (phi_a - phi_0),
//     se = sqrt(sd^2 / n_a + var_mu) / |phi_a - phi_0|.
// sd is the scatter of one DEM run (not of a recording's mean of several tests).
// Throws std::invalid_argument for equal phi values, a probe of fewer than one run, or a
// scatter or variance that is negative or not finite.

namespace demcal::calibrate {

// The mean of a probe's runs for one target, and how many runs it is the mean of.
struct ProbeMean {
  double phi = 0.0;   // the candidate parameter the probe ran at
  double mean = 0.0;  // the target's mean over the probe's runs
  double runs = 0.0;  // >= 1
};

struct ProbeSensitivity {
  double value = 0.0;           // d mean / d phi
  double standard_error = 0.0;  // from the runs' scatter (and the surrogate's variance)
};

ProbeSensitivity secant_sensitivity(const ProbeMean& a, const ProbeMean& b,
                                    double single_run_sd);

ProbeSensitivity sensitivity_against_prediction(const ProbeMean& a, double base_phi,
                                                double predicted_mean, double predicted_variance,
                                                double single_run_sd);

}  // namespace demcal::calibrate
