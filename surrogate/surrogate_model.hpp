#pragma once
// The common face of every surrogate, so that calibration can swap a polynomial for a
// Gaussian process without knowing which it holds.
//
// Conventions shared by all models: a table of points is an Eigen matrix with one row per
// point and one column per input, in the caller's (unscaled) units; a model scales inputs
// internally, but everything it returns is in the units it was given.

#include "surrogate/cross_validation.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace demcal::surrogate {

struct Prediction {
  Eigen::VectorXd mean;
  // Variance of the predicted mean (the surrogate's own uncertainty), without observation
  // noise: the term calibration adds to measurement noise and DEM scatter.
  Eigen::VectorXd variance;
};

class SurrogateModel {
 public:
  virtual ~SurrogateModel() = default;

  // Stable identifier used in saved files: "polynomial_surface" or "gaussian_process".
  virtual std::string kind() const = 0;
  // One line for logs, e.g. "polynomial surface, total degree 2, 6 terms".
  virtual std::string description() const = 0;
  virtual std::size_t input_dimension() const = 0;
  virtual const std::vector<std::string>& input_names() const = 0;

  // Points are rows; throws std::invalid_argument when the column count is wrong or a
  // value is not finite.
  virtual Prediction predict(const Eigen::MatrixXd& points) const = 0;
  virtual Eigen::VectorXd predict_mean(const Eigen::MatrixXd& points) const = 0;
  // d mean / d x per point (rows) and input (columns), in output units per input unit.
  virtual Eigen::MatrixXd gradient(const Eigen::MatrixXd& points) const = 0;

  // Closed form; see each model for what is re-estimated without the point.
  virtual LeaveOneOut leave_one_out() const = 0;

 protected:
  SurrogateModel() = default;
  SurrogateModel(const SurrogateModel&) = default;
  SurrogateModel(SurrogateModel&&) = default;
  SurrogateModel& operator=(const SurrogateModel&) = default;
  SurrogateModel& operator=(SurrogateModel&&) = default;
};

// Rows as produced by full_factorial_design(). Throws std::invalid_argument on ragged rows.
inline Eigen::MatrixXd to_matrix(const std::vector<std::vector<double>>& rows) {
  const std::size_t cols = rows.empty() ? 0 : rows.front().size();
  Eigen::MatrixXd m(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].size() != cols)
      throw std::invalid_argument("to_matrix: row " + std::to_string(i) + " has " +
                                  std::to_string(rows[i].size()) + " values, row 0 has " +
                                  std::to_string(cols));
    for (std::size_t j = 0; j < cols; ++j)
      m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = rows[i][j];
  }
  return m;
}

// Checks shared by the models; not part of the documented API.
namespace detail {

// Appends rather than writing "x" + std::to_string(j): GCC 12 raises a false -Wrestrict on
// operator+(const char*, std::string&&).
inline std::string default_input_name(Eigen::Index j) {
  std::string s = "x";
  s += std::to_string(j);
  return s;
}

inline std::string input_label(const std::vector<std::string>& names, Eigen::Index j) {
  const auto k = static_cast<std::size_t>(j);
  return k < names.size() ? "'" + names[k] + "'" : default_input_name(j);
}

inline std::vector<std::string> resolve_input_names(const std::string& who,
                                                    const std::vector<std::string>& names,
                                                    Eigen::Index p) {
  if (names.empty()) {
    std::vector<std::string> out;
    for (Eigen::Index j = 0; j < p; ++j) out.push_back(default_input_name(j));
    return out;
  }
  if (static_cast<Eigen::Index>(names.size()) != p)
    throw std::invalid_argument(who + ": input_names has " + std::to_string(names.size()) +
                                " names but x has " + std::to_string(p) + " columns");
  for (const auto& n : names)
    if (n.empty()) throw std::invalid_argument(who + ": input_names contains an empty name");
  return names;
}

inline void check_training_table(const std::string& who, const Eigen::MatrixXd& x,
                                 const Eigen::VectorXd& y, const std::vector<std::string>& names) {
  if (x.cols() == 0) throw std::invalid_argument(who + ": x has no columns (inputs)");
  if (x.rows() != y.size())
    throw std::invalid_argument(who + ": x has " + std::to_string(x.rows()) + " rows but y has " +
                                std::to_string(y.size()) + " values");
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    for (Eigen::Index j = 0; j < x.cols(); ++j)
      if (!std::isfinite(x(i, j)))
        throw std::invalid_argument(who + ": x(" + std::to_string(i) + ", " + std::to_string(j) +
                                    ") of input " + input_label(names, j) + " is not finite");
    if (!std::isfinite(y(i)))
      throw std::invalid_argument(who + ": y[" + std::to_string(i) + "] is not finite");
  }
}

inline void check_points(const std::string& who, const Eigen::MatrixXd& points, Eigen::Index p) {
  if (points.cols() != p)
    throw std::invalid_argument(who + ": points have " + std::to_string(points.cols()) +
                                " columns but the model has " + std::to_string(p) + " inputs");
  if (!points.allFinite()) throw std::invalid_argument(who + ": points contain a non-finite value");
}

// Scaling box: the given bounds, or the range of the data when none are given.
inline std::pair<Eigen::VectorXd, Eigen::VectorXd> resolve_box(
    const std::string& who, const Eigen::MatrixXd& x, const std::vector<double>& lower,
    const std::vector<double>& upper, const std::vector<std::string>& names) {
  const Eigen::Index p = x.cols();
  Eigen::VectorXd lo(p), hi(p);
  if (lower.empty() && upper.empty()) {
    lo = x.colwise().minCoeff().transpose();
    hi = x.colwise().maxCoeff().transpose();
    for (Eigen::Index j = 0; j < p; ++j)
      if (!(hi(j) > lo(j)))
        throw std::invalid_argument(who + ": input " + input_label(names, j) +
                                    " takes a single value in x; give lower/upper bounds");
    return {lo, hi};
  }
  if (static_cast<Eigen::Index>(lower.size()) != p || static_cast<Eigen::Index>(upper.size()) != p)
    throw std::invalid_argument(who + ": lower/upper must both have " + std::to_string(p) +
                                " entries (one per input), got " + std::to_string(lower.size()) +
                                " and " + std::to_string(upper.size()));
  for (Eigen::Index j = 0; j < p; ++j) {
    lo(j) = lower[static_cast<std::size_t>(j)];
    hi(j) = upper[static_cast<std::size_t>(j)];
    if (!std::isfinite(lo(j)) || !std::isfinite(hi(j)) || !(hi(j) > lo(j)))
      throw std::invalid_argument(who + ": upper must exceed lower for input " +
                                  input_label(names, j));
  }
  return {lo, hi};
}

}  // namespace detail
}  // namespace demcal::surrogate
