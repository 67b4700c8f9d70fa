#pragma once
// Step 3 of the missing-physics workflow, the thorough part: how strongly the recordings
// favour one model (the base model, or the base model with a candidate module and its
// parameter) over another.
//
// Likelihood: Gaussian in the standardized residuals, with its normalisation, because
// sigma_total differs between models through the surrogate variance:
//
//   -2 log L(theta) = chi^2(theta) + sum_i log(2 pi sigma_total_i(theta)^2).
//
// BIC = -2 log L(theta_hat) + k ln n (k parameters, n targets): smaller is better.
//
// Evidence (marginal likelihood) Z = integral of L(theta) pi(theta) over the box, with the
// uniform prior pi = 1 / prod_j (upper_j - lower_j):
//
//   Laplace: log Z = log L(theta_hat) + log pi + (k/2) log(2 pi) + 1/2 log det(Cov),
//            Cov the Gauss-Newton covariance in parameter units. Exact for a model linear
//            in theta whose Gaussian lies well inside the bounds. With theta_hat on a bound
//            the Gaussian is cut there: log 2 is subtracted per parameter on a bound (exact
//            when the likelihood is flat across the bound, an upper bound otherwise).
//   Grid:    Z = sum_nodes w_k exp(log_posterior_k) (2 pi)^(-n/2) / prod(range), the
//            likelihood-ratio grid's nodes with their cell measures (grid_cell_measures);
//            k <= 3 only. Accurate when the grid resolves the peak (region.resolved).
//
// Both are reported; the one used (log_evidence) is Laplace where the covariance exists and
// theta_hat lies off the bounds; else the grid when it resolves the region; else Laplace
// with its bound correction; else the unresolved grid; else none (NaN). A coarse grid
// misses a narrow peak, which is why it is not preferred when unresolved.
//
// The Bayes factor between two models fitted to the same targets is exp(log Z_a - log Z_b).
// It depends on the prior ranges: widening a candidate parameter's bounds tenfold costs its
// model a factor of 10 (the Occam factor), which is why bounds must be physical.

#include "calibrate/calibration.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace demcal::calibrate {

enum class EvidenceMethod { laplace, grid, none };
const char* to_string(EvidenceMethod method);  // "laplace", "grid", "none"

struct ModelEvidence {
  std::string model;  // e.g. "base" or "cohesion"
  int parameters = 0, targets = 0;
  double chi_square_min = 0.0;
  double log_likelihood_max = 0.0;  // log L(theta_hat), normalised
  double bic = 0.0;
  double log_prior_density = 0.0;  // -sum_j log(range_j)

  bool laplace_available = false;  // the Gauss-Newton covariance exists
  int parameters_at_bound = 0;     // of theta_hat, within 1e-6 of the range
  double log_evidence_laplace = 0.0;  // with the log 2 per bound parameter; NaN if unavailable

  bool grid_available = false;      // the likelihood-ratio grid exists (k <= 3)
  bool grid_resolved = false;       // region.resolved: >= 5 nodes across the region per axis
  double log_evidence_grid = 0.0;   // NaN if unavailable

  EvidenceMethod method = EvidenceMethod::none;
  double log_evidence = 0.0;  // by `method`; NaN for none
  std::vector<std::string> notes;

  // Identity of the data: Bayes factors need the same targets (setup, observable, value).
  std::vector<TargetSummary> data;

  nlohmann::json to_json() const;  // NaN -> null
};

// Throws std::invalid_argument when the result has no minimum.
ModelEvidence model_evidence(const CalibrationResult& result, const std::string& model_name);

// Kass & Raftery (1995), on the Bayes factor B of a over b: "not worth more than a bare
// mention" (1-3), "positive" (3-20), "strong" (20-150), "very strong" (> 150); below 1
// the same words for b over a.
std::string kass_raftery_strength(double bayes_factor);

struct BayesFactor {
  std::string model_a, model_b;
  double log_bayes_factor = 0.0;  // log Z_a - log Z_b
  double bayes_factor = 0.0;      // exp of it (may be inf)
  double delta_bic = 0.0;         // BIC_a - BIC_b (negative favours a)
  std::string strength;           // kass_raftery_strength(bayes_factor)
  std::string reading;            // e.g. "cohesion is favoured over base: Bayes factor 140 (very strong)."
  nlohmann::json to_json() const;
};

// a over b. Throws std::invalid_argument when the two were fitted to different targets
// (naming the first that differs) or either has no evidence.
BayesFactor bayes_factor(const ModelEvidence& a, const ModelEvidence& b);

}  // namespace demcal::calibrate
