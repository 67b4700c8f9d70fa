#pragma once
// Fitting a surrogate to a replicated design: the step between a table of runs
// and a model the calibration can use. A design run with replicates (the same
// point, different seeds) measures the simulator's own scatter; that scatter
// is what a surrogate cannot and should not reproduce, and what calibration
// must add to the measurement noise. This file decides how replicates enter
// each kind of model, validates the fit by leave-one-out, and compares the
// surrogate's error with the scatter.

#include "surrogate/cross_validation.hpp"
#include "surrogate/gaussian_process.hpp"
#include "surrogate/polynomial_surface.hpp"
#include "surrogate/scatter_trend.hpp"
#include "surrogate/surrogate_model.hpp"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace demcal::surrogate {

// Rows of runs; rows with the same `group` are replicates of one design point
// (their x must be equal). Rows whose y is NaN (not measured, failed) are dropped.
struct ReplicatedData {
  std::vector<std::string> input_names;
  std::vector<double> lower, upper;  // the design box: the models' scaling box
  Eigen::MatrixXd x;
  Eigen::VectorXd y;
  std::vector<int> group;
  std::string output_name;  // e.g. "angle_of_repose_deg"
};

// The surrogate kinds fit_surrogate knows, in registration order ("gaussian_process",
// "polynomial"): SurrogateSpec::model names one. The study reader's table of the same kinds
// (config/models/surrogate_models.hpp) is checked against this list by a test.
std::vector<std::string> surrogate_model_names();

struct SurrogateSpec {
  std::string model = "gaussian_process";  // | "polynomial"
  // polynomial: total degree 1..4, or 0 = chosen by leave-one-out cross-validation.
  int degree = 0;
  CovarianceKernel kernel = CovarianceKernel::matern52;
  MeanFunction mean = MeanFunction::constant;
  // Gaussian process noise:
  //   "replicates": the model is fitted to the mean of each point, with a nugget
  //                 per point = pooled replicate variance / replicates at it (the
  //                 issue's "set per point from replicate variance"); needs
  //                 replicates somewhere in the design.
  //   "estimated":  fitted to every run, one nugget by maximum likelihood.
  //   "none":       fitted to the point means, interpolating them.
  std::string nugget = "replicates";
  int starts = 8;
  std::uint64_t seed = 1;
};

// The simulator's run-to-run scatter at fixed inputs, pooled over the points
// with replicates: sqrt(sum over points of sum (y - point mean)^2 / sum (n_i - 1)).
struct ReplicateScatter {
  double sd = 0.0;            // NaN when no point has two runs
  int degrees_of_freedom = 0;
  int points = 0;             // distinct points
  double mean_replicates = 0.0;
};
ReplicateScatter replicate_scatter(const ReplicatedData& data);

// The test of scatter_trend.hpp on the points with replicates, the inputs scaled to the
// design box (data.lower, data.upper).
ScatterTrend replicate_scatter_trend(const ReplicatedData& data);

// Above this p the scatter is read as constant over the inputs; below it the surrogate's
// check says that it changes (FittedSurrogate::scatter_check.message).
inline constexpr double kScatterTrendAlpha = 0.01;

struct FittedSurrogate {
  std::shared_ptr<const SurrogateModel> model;
  std::string output_name;
  SurrogateSpec spec;
  ReplicateScatter scatter;
  ScatterTrend scatter_trend;      // whether the scatter changes over the inputs
  LeaveOneOut loo;                 // over what the model was fitted to
  ValidationMetrics validation;
  ScatterCheck scatter_check;
  std::vector<int> degrees_tried;  // polynomial with degree 0: the CV search
  std::vector<double> degree_cv_rmse;
  std::size_t runs = 0;            // rows used
  // The model, spec, scatter and validation, for the saved surrogate file.
  nlohmann::json to_json() const;
};

// Throws std::invalid_argument naming the output when there is too little
// data, inputs of one group differ, or the spec is invalid.
FittedSurrogate fit_surrogate(const ReplicatedData& data, const SurrogateSpec& spec);

// Reads back what FittedSurrogate::to_json wrote (model, spec, scatter,
// validation); the LOO vectors are restored too.
FittedSurrogate fitted_surrogate_from_json(const nlohmann::json& j);

}  // namespace demcal::surrogate
