#include "surrogate/surrogate_io.hpp"

#include "io/atomic_file.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>

namespace demcal::surrogate {
namespace {

using nlohmann::json;

const std::string kFormat = "demcal.surrogate";
constexpr int kVersion = 1;

// JSON has no NaN or infinity; they are written as null and read back as NaN.
json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json vector_json(const Eigen::VectorXd& v) {
  json a = json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(number(v(i)));
  return a;
}

json matrix_json(const Eigen::MatrixXd& m) {  // row by row
  json a = json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) a.push_back(vector_json(m.row(i).transpose()));
  return a;
}

const json& at(const json& j, const std::string& key) {
  if (!j.is_object() || !j.contains(key))
    throw std::invalid_argument("surrogate file: missing key '" + key + "'");
  return j.at(key);
}

double read_number(const json& v, const std::string& key) {
  if (v.is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!v.is_number()) throw std::invalid_argument("surrogate file: '" + key + "' must be a number");
  return v.get<double>();
}

double number_at(const json& j, const std::string& key) { return read_number(at(j, key), key); }

Eigen::VectorXd read_vector(const json& v, const std::string& key) {
  if (!v.is_array()) throw std::invalid_argument("surrogate file: '" + key + "' must be an array");
  Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i)
    out(static_cast<Eigen::Index>(i)) = read_number(v[i], key + "[" + std::to_string(i) + "]");
  return out;
}

Eigen::VectorXd vector_at(const json& j, const std::string& key) { return read_vector(at(j, key), key); }

Eigen::MatrixXd read_matrix(const json& j, const std::string& key, Eigen::Index cols_if_empty) {
  const json& v = at(j, key);
  if (!v.is_array()) throw std::invalid_argument("surrogate file: '" + key + "' must be an array of rows");
  const Eigen::Index rows = static_cast<Eigen::Index>(v.size());
  const Eigen::Index cols = rows > 0 && v[0].is_array() ? static_cast<Eigen::Index>(v[0].size()) : cols_if_empty;
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index i = 0; i < rows; ++i) {
    const std::string row_key = key + "[" + std::to_string(i) + "]";
    const Eigen::VectorXd r = read_vector(v[static_cast<std::size_t>(i)], row_key);
    if (r.size() != cols)
      throw std::invalid_argument("surrogate file: '" + row_key + "' has " + std::to_string(r.size()) +
                                  " values, expected " + std::to_string(cols));
    m.row(i) = r.transpose();
  }
  return m;
}

std::string read_string(const json& j, const std::string& key) {
  const json& v = at(j, key);
  if (!v.is_string()) throw std::invalid_argument("surrogate file: '" + key + "' must be a string");
  return v.get<std::string>();
}

std::vector<std::string> read_strings(const json& j, const std::string& key) {
  const json& v = at(j, key);
  if (!v.is_array()) throw std::invalid_argument("surrogate file: '" + key + "' must be an array");
  std::vector<std::string> out;
  for (const auto& s : v) {
    if (!s.is_string()) throw std::invalid_argument("surrogate file: '" + key + "' must hold strings");
    out.push_back(s.get<std::string>());
  }
  return out;
}

// The training points lie in the box the model standardises its inputs by (the fit
// refuses a run outside the design box, study/surrogate_fitting.cpp, with the same slack):
// a point far outside would make every prediction non-finite.
void check_training_in_box(const Eigen::MatrixXd& x, const Eigen::VectorXd& lower,
                           const Eigen::VectorXd& upper) {
  if (lower.size() != x.cols() || upper.size() != x.cols()) return;  // the state's own check
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    const double slack =
        1e-9 * (std::fabs(upper(c) - lower(c)) + std::fabs(upper(c)) + std::fabs(lower(c)));
    for (Eigen::Index r = 0; r < x.rows(); ++r)
      if (std::isfinite(x(r, c)) && (x(r, c) < lower(c) - slack || x(r, c) > upper(c) + slack))
        throw std::invalid_argument("surrogate file: 'training.x[" + std::to_string(r) + "][" +
                                    std::to_string(c) + "]' is " + json(x(r, c)).dump() +
                                    ", outside the model's box [lower, upper] = [" +
                                    json(lower(c)).dump() + ", " + json(upper(c)).dump() + "]");
  }
}

void check_header(const json& j, const std::string& kind) {
  if (read_string(j, "format") != kFormat)
    throw std::invalid_argument("surrogate file: 'format' is not '" + kFormat + "'");
  const json& version = at(j, "version");
  if (!version.is_number_integer() || version.get<int>() != kVersion)
    throw std::invalid_argument("surrogate file: unsupported 'version' (this build reads " +
                                std::to_string(kVersion) + ")");
  if (!kind.empty() && read_string(j, "kind") != kind)
    throw std::invalid_argument("surrogate file: 'kind' is '" + read_string(j, "kind") +
                                "', expected '" + kind + "'");
}

json header(const SurrogateModel& m) {
  json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["kind"] = m.kind();
  j["description"] = m.description();
  j["input_names"] = m.input_names();
  return j;
}

json training_json(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  return json{{"x", matrix_json(x)}, {"y", vector_json(y)}};
}

}  // namespace

json to_json(const PolynomialSurface& model) {
  const auto& s = model.state();
  json j = header(model);
  j["lower"] = vector_json(s.lower);
  j["upper"] = vector_json(s.upper);
  j["terms"] = s.terms;
  j["term_names"] = model.term_names();  // informational
  j["coefficients_scaled_inputs"] = vector_json(s.coefficients);
  j["standard_errors_scaled_inputs"] = vector_json(model.standard_errors());  // informational
  try {  // informational: the regression equation in the caller's units
    j["coefficients_input_units"] = vector_json(model.unscaled_coefficients());
    j["standard_errors_input_units"] = vector_json(model.unscaled_standard_errors());
  } catch (const std::logic_error&) {
    // The term set does not expand into itself; the scaled coefficients are all there is.
  }
  j["residual_sigma"] = number(s.residual_sigma);
  j["r_squared"] = number(model.r_squared());  // informational
  j["xtx_inverse"] = matrix_json(s.xtx_inverse);
  j["hat_diagonal"] = vector_json(s.hat_diagonal);
  j["training"] = training_json(s.x, s.y);
  return j;
}

json to_json(const GaussianProcess& model) {
  const auto& s = model.state();
  json j = header(model);
  j["kernel"] = to_string(s.kernel);
  j["mean"] = to_string(s.mean);
  j["nugget_mode"] = to_string(s.nugget_mode);
  j["lower"] = vector_json(s.lower);
  j["upper"] = vector_json(s.upper);
  j["output_mean"] = number(s.output_mean);
  j["output_scale"] = number(s.output_scale);
  j["length_scales_unit_box"] = vector_json(s.length_scales);
  j["signal_variance_standardized"] = number(s.signal_variance);
  j["nugget_variance_standardized"] = number(s.nugget_variance);
  j["point_nugget_variances_standardized"] = vector_json(s.point_nugget_variances);
  j["mean_coefficients_standardized"] = vector_json(s.mean_coefficients);
  j["jitter_standardized"] = number(s.jitter);
  j["log_marginal_likelihood"] = number(s.log_marginal_likelihood);
  const auto h = model.hyperparameters();
  j["hyperparameters_in_input_units"] = {  // informational
      {"length_scales", h.length_scales},
      {"signal_variance", h.signal_variance},
      {"nugget_variance", h.nugget_variance}};
  j["training"] = training_json(s.x, s.y);
  return j;
}

json to_json(const SurrogateModel& model) {
  if (const auto* p = dynamic_cast<const PolynomialSurface*>(&model)) return to_json(*p);
  if (const auto* g = dynamic_cast<const GaussianProcess*>(&model)) return to_json(*g);
  throw std::invalid_argument("surrogate file: cannot save a model of kind '" + model.kind() + "'");
}

PolynomialSurface polynomial_surface_from_json(const json& j) {
  check_header(j, "polynomial_surface");
  PolynomialSurface::State s;
  s.input_names = read_strings(j, "input_names");
  const auto p = static_cast<Eigen::Index>(s.input_names.size());
  s.lower = vector_at(j, "lower");
  s.upper = vector_at(j, "upper");
  const json& terms = at(j, "terms");
  try {
    s.terms = terms.get<std::vector<std::vector<int>>>();
  } catch (const json::exception&) {
    throw std::invalid_argument("surrogate file: 'terms' must be an array of integer arrays");
  }
  s.coefficients = vector_at(j, "coefficients_scaled_inputs");
  s.residual_sigma = number_at(j, "residual_sigma");
  s.xtx_inverse = read_matrix(j, "xtx_inverse", 0);
  s.hat_diagonal = vector_at(j, "hat_diagonal");
  const json& training = at(j, "training");
  s.x = read_matrix(training, "x", p);
  s.y = vector_at(training, "y");
  check_training_in_box(s.x, s.lower, s.upper);
  return PolynomialSurface::from_state(std::move(s));
}

GaussianProcess gaussian_process_from_json(const json& j) {
  check_header(j, "gaussian_process");
  GaussianProcess::State s;
  s.kernel = covariance_kernel_from_string(read_string(j, "kernel"));
  s.mean = mean_function_from_string(read_string(j, "mean"));
  s.nugget_mode = nugget_mode_from_string(read_string(j, "nugget_mode"));
  s.input_names = read_strings(j, "input_names");
  const auto p = static_cast<Eigen::Index>(s.input_names.size());
  s.lower = vector_at(j, "lower");
  s.upper = vector_at(j, "upper");
  s.output_mean = number_at(j, "output_mean");
  s.output_scale = number_at(j, "output_scale");
  s.length_scales = vector_at(j, "length_scales_unit_box");
  s.signal_variance = number_at(j, "signal_variance_standardized");
  s.nugget_variance = number_at(j, "nugget_variance_standardized");
  s.point_nugget_variances = vector_at(j, "point_nugget_variances_standardized");
  s.mean_coefficients = vector_at(j, "mean_coefficients_standardized");
  s.jitter = number_at(j, "jitter_standardized");
  s.log_marginal_likelihood = number_at(j, "log_marginal_likelihood");
  const json& training = at(j, "training");
  s.x = read_matrix(training, "x", p);
  s.y = vector_at(training, "y");
  check_training_in_box(s.x, s.lower, s.upper);
  return GaussianProcess::from_state(std::move(s));
}

namespace {

std::unique_ptr<SurrogateModel> load_polynomial_surface(const json& j) {
  return std::make_unique<PolynomialSurface>(polynomial_surface_from_json(j));
}
std::unique_ptr<SurrogateModel> load_gaussian_process(const json& j) {
  return std::make_unique<GaussianProcess>(gaussian_process_from_json(j));
}

// The stored kinds, by the "kind" a file names: a run-time table, as the fitted kinds
// (surrogate_fit.cpp).
struct StoredKind {
  const char* kind;
  std::unique_ptr<SurrogateModel> (*load)(const json&);
};
constexpr StoredKind kStoredKinds[] = {
    {"polynomial_surface", &load_polynomial_surface},
    {"gaussian_process", &load_gaussian_process},
};

}  // namespace

std::unique_ptr<SurrogateModel> surrogate_from_json(const json& j) {
  check_header(j, "");
  const std::string kind = read_string(j, "kind");
  for (const StoredKind& k : kStoredKinds)
    if (kind == k.kind) return k.load(j);
  throw std::invalid_argument("surrogate file: unknown 'kind' '" + kind + "'");
}

void save_surrogate(const SurrogateModel& model, const std::filesystem::path& path) {
  // demcal's one atomic writer: a killed process leaves the old file or none, never half.
  io::write_file_atomically(path, to_json(model).dump(2) + "\n");
}

std::unique_ptr<SurrogateModel> load_surrogate(const std::filesystem::path& path) {
  if (std::filesystem::is_directory(path))
    throw std::invalid_argument("surrogate file '" + path.string() +
                                "': is a directory; expected a surrogate JSON file");
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read surrogate file '" + path.string() + "'");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::parse_error& e) {
    throw std::invalid_argument("surrogate file '" + path.string() + "': not JSON: " + e.what());
  }
  try {
    return surrogate_from_json(j);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("'" + path.string() + "': " + e.what());
  }
}

}  // namespace demcal::surrogate
