#include "surrogate/surrogate_fit.hpp"

#include "surrogate/surrogate_io.hpp"

#include <cmath>
#include <map>
#include <stdexcept>

namespace demcal::surrogate {
namespace {

struct PointMeans {
  Eigen::MatrixXd x;
  Eigen::VectorXd y;
  Eigen::VectorXd replicates;
};

// Rows with a finite y, grouped; checks that replicates share their inputs.
std::map<int, std::vector<Eigen::Index>> groups_of(const ReplicatedData& d) {
  if (d.x.rows() != d.y.size() || static_cast<Eigen::Index>(d.group.size()) != d.y.size())
    throw std::invalid_argument(d.output_name + ": x, y and group differ in length");
  std::map<int, std::vector<Eigen::Index>> g;
  for (Eigen::Index i = 0; i < d.y.size(); ++i) {
    if (!std::isfinite(d.y(i))) continue;
    auto& rows = g[d.group[static_cast<std::size_t>(i)]];
    if (!rows.empty()) {
      const Eigen::Index r0 = rows.front();
      const double scale = 1.0 + d.x.row(r0).cwiseAbs().maxCoeff();
      if ((d.x.row(i) - d.x.row(r0)).cwiseAbs().maxCoeff() > 1e-9 * scale)
        throw std::invalid_argument(d.output_name + ": rows " + std::to_string(r0) + " and " +
                                    std::to_string(i) + " are replicates of point " +
                                    std::to_string(d.group[static_cast<std::size_t>(i)]) +
                                    " but their inputs differ");
    }
    rows.push_back(i);
  }
  return g;
}

PointMeans point_means(const ReplicatedData& d) {
  const auto g = groups_of(d);
  PointMeans m;
  m.x.resize(static_cast<Eigen::Index>(g.size()), d.x.cols());
  m.y.resize(static_cast<Eigen::Index>(g.size()));
  m.replicates.resize(static_cast<Eigen::Index>(g.size()));
  Eigen::Index k = 0;
  for (const auto& [id, rows] : g) {
    double s = 0.0;
    for (Eigen::Index r : rows) s += d.y(r);
    m.x.row(k) = d.x.row(rows.front());
    m.y(k) = s / static_cast<double>(rows.size());
    m.replicates(k) = static_cast<double>(rows.size());
    ++k;
  }
  return m;
}

nlohmann::json vec(const Eigen::VectorXd& v) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(std::isfinite(v(i)) ? nlohmann::json(v(i)) : nlohmann::json());
  return a;
}

Eigen::VectorXd vec_from(const nlohmann::json& a) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(a.size()));
  for (std::size_t i = 0; i < a.size(); ++i)
    v(static_cast<Eigen::Index>(i)) = a[i].is_null() ? std::nan("") : a[i].get<double>();
  return v;
}

double finite_or_nan(const nlohmann::json& j) { return j.is_null() ? std::nan("") : j.get<double>(); }
nlohmann::json json_number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

// polynomial: total degree given, or chosen by leave-one-out.
double fit_polynomial_kind(const ReplicatedData& data, const SurrogateSpec& spec,
                           const PointMeans& means, FittedSurrogate& f) {
  double replicates_per_point = 1.0;
  // Fitted to the point means: leave-one-out then leaves out a whole point,
  // not one replicate whose twin stays in and flatters the error.
  PolynomialOptions po;
  po.input_names = data.input_names;
  po.lower = data.lower;
  po.upper = data.upper;
  replicates_per_point = means.replicates.mean();
  if (spec.degree == 0) {
    DegreeSelection sel = select_polynomial_degree(means.x, means.y, po);
    f.degrees_tried = sel.degrees;
    f.degree_cv_rmse = sel.cv_rmse;
    f.model = std::make_shared<PolynomialSurface>(std::move(sel.surface));
  } else {
    po.degree = spec.degree;
    f.model = std::make_shared<PolynomialSurface>(PolynomialSurface::fit(means.x, means.y, po));
  }
  return replicates_per_point;
}

// gaussian_process: the nugget from the replicates, estimated, or none.
double fit_gaussian_process_kind(const ReplicatedData& data, const SurrogateSpec& spec,
                                 const PointMeans& means, FittedSurrogate& f) {
  const std::string& name = data.output_name;
  double replicates_per_point = 1.0;
  GaussianProcessOptions go;
  go.kernel = spec.kernel;
  go.mean = spec.mean;
  go.input_names = data.input_names;
  go.lower = data.lower;
  go.upper = data.upper;
  go.starts = spec.starts;
  go.seed = spec.seed;
  if (spec.nugget == "estimated") {
    Eigen::MatrixXd x(static_cast<Eigen::Index>(f.runs), data.x.cols());
    Eigen::VectorXd y(static_cast<Eigen::Index>(f.runs));
    Eigen::Index k = 0;
    for (Eigen::Index i = 0; i < data.y.size(); ++i)
      if (std::isfinite(data.y(i))) {
        x.row(k) = data.x.row(i);
        y(k++) = data.y(i);
      }
    go.nugget = NuggetMode::estimated;
    f.model = std::make_shared<GaussianProcess>(GaussianProcess::fit(x, y, go));
  } else if (spec.nugget == "replicates") {
    if (!std::isfinite(f.scatter.sd))
      throw std::invalid_argument(name + ": nugget = \"replicates\" needs replicates (two or more runs at a "
                                         "point); the design has none. Add replicates or use nugget = "
                                         "\"estimated\"");
    go.nugget = NuggetMode::fixed;
    for (Eigen::Index i = 0; i < means.y.size(); ++i)
      go.nugget_variances.push_back(f.scatter.sd * f.scatter.sd / means.replicates(i));
    replicates_per_point = means.replicates.mean();
    f.model = std::make_shared<GaussianProcess>(GaussianProcess::fit(means.x, means.y, go));
  } else {
    go.nugget = NuggetMode::none;
    replicates_per_point = means.replicates.mean();
    f.model = std::make_shared<GaussianProcess>(GaussianProcess::fit(means.x, means.y, go));
  }
  return replicates_per_point;
}

// The run-time table of surrogate kinds, in registration order (the order messages list
// them in). A kind fits FittedSurrogate::model (and what it reports of its own choice) and
// returns the replicates per point its error is compared against the scatter with.
using KindFit = double (*)(const ReplicatedData&, const SurrogateSpec&, const PointMeans&,
                           FittedSurrogate&);
struct SurrogateKind {
  const char* name;
  KindFit fit;
};
constexpr SurrogateKind kSurrogateKinds[] = {
    {"gaussian_process", &fit_gaussian_process_kind},
    {"polynomial", &fit_polynomial_kind},
};

const SurrogateKind& surrogate_kind(const std::string& model, const std::string& output_name) {
  for (const SurrogateKind& k : kSurrogateKinds)
    if (model == k.name) return k;
  std::string known;
  for (const SurrogateKind& k : kSurrogateKinds)
    known += std::string(known.empty() ? "" : " or ") + "\"" + k.name + "\"";
  throw std::invalid_argument(output_name + ": surrogate model must be " + known + ", not \"" +
                              model + "\"");
}

}  // namespace

std::vector<std::string> surrogate_model_names() {
  std::vector<std::string> names;
  for (const SurrogateKind& k : kSurrogateKinds) names.emplace_back(k.name);
  return names;
}

ReplicateScatter replicate_scatter(const ReplicatedData& data) {
  ReplicateScatter s;
  double ss = 0.0;
  int runs = 0;
  for (const auto& [id, rows] : groups_of(data)) {
    ++s.points;
    runs += static_cast<int>(rows.size());
    if (rows.size() < 2) continue;
    double mean = 0.0;
    for (Eigen::Index r : rows) mean += data.y(r);
    mean /= static_cast<double>(rows.size());
    for (Eigen::Index r : rows) ss += (data.y(r) - mean) * (data.y(r) - mean);
    s.degrees_of_freedom += static_cast<int>(rows.size()) - 1;
  }
  s.sd = s.degrees_of_freedom > 0 ? std::sqrt(ss / s.degrees_of_freedom) : std::nan("");
  s.mean_replicates = s.points > 0 ? static_cast<double>(runs) / s.points : 0.0;
  return s;
}

ScatterTrend replicate_scatter_trend(const ReplicatedData& data) {
  std::vector<Eigen::Index> first_rows;
  std::vector<double> variances;
  std::vector<int> dofs;
  for (const auto& [id, rows] : groups_of(data)) {
    if (rows.size() < 2) continue;
    double mean = 0.0;
    for (Eigen::Index r : rows) mean += data.y(r);
    mean /= static_cast<double>(rows.size());
    double ss = 0.0;
    for (Eigen::Index r : rows) ss += (data.y(r) - mean) * (data.y(r) - mean);
    first_rows.push_back(rows.front());
    variances.push_back(ss / static_cast<double>(rows.size() - 1));
    dofs.push_back(static_cast<int>(rows.size()) - 1);
  }
  const auto n = static_cast<Eigen::Index>(first_rows.size());
  const Eigen::Index p = data.x.cols();
  Eigen::MatrixXd u(n, p);
  for (Eigen::Index k = 0; k < n; ++k)
    for (Eigen::Index j = 0; j < p; ++j) {
      const auto jj = static_cast<std::size_t>(j);
      const bool boxed =
          jj < data.lower.size() && jj < data.upper.size() && data.upper[jj] > data.lower[jj];
      const double x = data.x(first_rows[static_cast<std::size_t>(k)], j);
      u(k, j) = boxed ? (x - data.lower[jj]) / (data.upper[jj] - data.lower[jj]) : x;
    }
  return fit_scatter_trend(u, Eigen::Map<const Eigen::VectorXd>(variances.data(), n),
                           Eigen::Map<const Eigen::VectorXi>(dofs.data(), n));
}

FittedSurrogate fit_surrogate(const ReplicatedData& data, const SurrogateSpec& spec) {
  const std::string& name = data.output_name;
  const SurrogateKind& kind = surrogate_kind(spec.model, name);
  if (spec.nugget != "replicates" && spec.nugget != "estimated" && spec.nugget != "none")
    throw std::invalid_argument(name + ": nugget must be \"replicates\", \"estimated\" or \"none\", not \"" +
                                spec.nugget + "\"");
  FittedSurrogate f;
  f.output_name = name;
  f.spec = spec;
  f.scatter = replicate_scatter(data);
  f.scatter_trend = replicate_scatter_trend(data);
  const PointMeans means = point_means(data);
  for (Eigen::Index i = 0; i < data.y.size(); ++i) f.runs += std::isfinite(data.y(i)) ? 1 : 0;
  if (means.y.size() < 3)
    throw std::invalid_argument(name + ": " + std::to_string(means.y.size()) +
                                " design points with a value; a surrogate needs at least 3");
  const double replicates_per_point = kind.fit(data, spec, means, f);
  f.loo = f.model->leave_one_out();
  f.validation = validation_metrics(f.loo);
  if (std::isfinite(f.scatter.sd) && f.scatter.sd > 0.0) {
    f.scatter_check = check_against_scatter(f.validation.rmse, f.scatter.sd, name,
                                            static_cast<int>(std::lround(replicates_per_point)),
                                            f.scatter.degrees_of_freedom);
  } else {
    f.scatter_check.within_scatter = true;
    f.scatter_check.surrogate_error = f.validation.rmse;
    f.scatter_check.message = name + ": no replicates, so the DEM's own scatter is unknown; leave-one-out RMSE " +
                              std::to_string(f.validation.rmse);
  }
  if (f.scatter_trend.tested && f.scatter_trend.p_value < kScatterTrendAlpha)
    f.scatter_check.message += "; " + describe(f.scatter_trend, kScatterTrendAlpha);
  return f;
}

nlohmann::json FittedSurrogate::to_json() const {
  nlohmann::json j;
  j["output"] = output_name;
  j["spec"] = {{"model", spec.model},   {"degree", spec.degree},           {"kernel", surrogate::to_string(spec.kernel)},
               {"mean", surrogate::to_string(spec.mean)}, {"nugget", spec.nugget}, {"starts", spec.starts},
               {"seed", spec.seed}};
  j["model"] = surrogate::to_json(*model);
  j["description"] = model->description();
  j["runs"] = runs;
  j["replicate_scatter"] = {{"sd", json_number(scatter.sd)},
                            {"degrees_of_freedom", scatter.degrees_of_freedom},
                            {"points", scatter.points},
                            {"mean_replicates", scatter.mean_replicates}};
  {
    nlohmann::json coefficients = nlohmann::json::array();
    for (double v : scatter_trend.log_variance_coefficients) coefficients.push_back(json_number(v));
    j["scatter_trend"] = {{"tested", scatter_trend.tested},
                          {"log_variance_coefficients", coefficients},
                          {"likelihood_ratio", json_number(scatter_trend.likelihood_ratio)},
                          {"degrees_of_freedom", scatter_trend.degrees_of_freedom},
                          {"p_value", json_number(scatter_trend.p_value)},
                          {"sd_smallest", json_number(scatter_trend.sd_smallest)},
                          {"sd_largest", json_number(scatter_trend.sd_largest)},
                          {"points", scatter_trend.points}};
  }
  j["validation"] = {{"q_squared", json_number(validation.q_squared)},
                     {"rmse", json_number(validation.rmse)},
                     {"press", json_number(validation.press)},
                     {"max_abs_standardized_residual", json_number(validation.max_abs_standardized_residual)},
                     {"standardized_residuals", vec(validation.standardized_residuals)}};
  j["leave_one_out"] = {{"observed", vec(loo.observed)}, {"mean", vec(loo.mean)}, {"variance", vec(loo.variance)}};
  j["scatter_check"] = {{"within_scatter", scatter_check.within_scatter},
                        {"surrogate_error", json_number(scatter_check.surrogate_error)},
                        {"message", scatter_check.message}};
  if (!degrees_tried.empty()) {
    nlohmann::json rmse = nlohmann::json::array();
    for (double v : degree_cv_rmse) rmse.push_back(json_number(v));
    j["degree_search"] = {{"degrees", degrees_tried}, {"cv_rmse", rmse}};
  }
  return j;
}

FittedSurrogate fitted_surrogate_from_json(const nlohmann::json& j) {
  FittedSurrogate f;
  f.output_name = j.at("output").get<std::string>();
  const auto& s = j.at("spec");
  f.spec.model = s.at("model").get<std::string>();
  f.spec.degree = s.at("degree").get<int>();
  f.spec.kernel = covariance_kernel_from_string(s.at("kernel").get<std::string>());
  f.spec.mean = mean_function_from_string(s.at("mean").get<std::string>());
  f.spec.nugget = s.at("nugget").get<std::string>();
  f.spec.starts = s.at("starts").get<int>();
  f.spec.seed = s.at("seed").get<std::uint64_t>();
  f.model = std::shared_ptr<const SurrogateModel>(surrogate_from_json(j.at("model")));
  f.runs = j.at("runs").get<std::size_t>();
  const auto& r = j.at("replicate_scatter");
  f.scatter.sd = finite_or_nan(r.at("sd"));
  f.scatter.degrees_of_freedom = r.at("degrees_of_freedom").get<int>();
  f.scatter.points = r.at("points").get<int>();
  f.scatter.mean_replicates = r.at("mean_replicates").get<double>();
  if (j.contains("scatter_trend")) {  // absent from files written before 2026-12-06
    const auto& t = j.at("scatter_trend");
    f.scatter_trend.tested = t.at("tested").get<bool>();
    for (const auto& v : t.at("log_variance_coefficients"))
      f.scatter_trend.log_variance_coefficients.push_back(finite_or_nan(v));
    f.scatter_trend.likelihood_ratio = finite_or_nan(t.at("likelihood_ratio"));
    f.scatter_trend.degrees_of_freedom = t.at("degrees_of_freedom").get<int>();
    f.scatter_trend.p_value = finite_or_nan(t.at("p_value"));
    f.scatter_trend.sd_smallest = finite_or_nan(t.at("sd_smallest"));
    f.scatter_trend.sd_largest = finite_or_nan(t.at("sd_largest"));
    f.scatter_trend.points = t.at("points").get<int>();
  }
  const auto& l = j.at("leave_one_out");
  f.loo.observed = vec_from(l.at("observed"));
  f.loo.mean = vec_from(l.at("mean"));
  f.loo.variance = vec_from(l.at("variance"));
  f.validation = validation_metrics(f.loo);
  const auto& c = j.at("scatter_check");
  f.scatter_check.within_scatter = c.at("within_scatter").get<bool>();
  f.scatter_check.surrogate_error = finite_or_nan(c.at("surrogate_error"));
  f.scatter_check.message = c.at("message").get<std::string>();
  if (j.contains("degree_search")) {
    f.degrees_tried = j["degree_search"]["degrees"].get<std::vector<int>>();
    for (const auto& v : j["degree_search"]["cv_rmse"]) f.degree_cv_rmse.push_back(finite_or_nan(v));
  }
  return f;
}

}  // namespace demcal::surrogate
