#include "surrogate/sobol_indices.hpp"

#include <gsl/gsl_qrng.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>

namespace demcal::surrogate {
namespace {

const std::string kWho = "sobol indices";

struct Estimates {
  Eigen::VectorXd first, total;
  double mean = 0.0, variance = 0.0;
};

// fa, fb: N values; fab: N x p, column i from A with column i replaced by B's.
Estimates estimate(const Eigen::VectorXd& fa, const Eigen::VectorXd& fb, const Eigen::MatrixXd& fab,
                   const std::vector<Eigen::Index>& rows) {
  const auto n = static_cast<double>(rows.size());
  const Eigen::Index p = fab.cols();
  double sum = 0.0;
  for (Eigen::Index r : rows) sum += fa(r) + fb(r);
  Estimates e;
  e.mean = sum / (2.0 * n);
  // Pooled over A and B, with the mean subtracted: the raw second moment minus mean²
  // would lose digits when the mean is large next to the spread.
  double ss = 0.0;
  for (Eigen::Index r : rows) ss += std::pow(fa(r) - e.mean, 2) + std::pow(fb(r) - e.mean, 2);
  e.variance = ss / (2.0 * n - 1.0);
  e.first.setZero(p);
  e.total.setZero(p);
  for (Eigen::Index i = 0; i < p; ++i) {
    double v = 0.0, vt = 0.0;
    for (Eigen::Index r : rows) {
      v += fb(r) * (fab(r, i) - fa(r));
      vt += std::pow(fa(r) - fab(r, i), 2);
    }
    e.first(i) = v / n / e.variance;
    e.total(i) = 0.5 * vt / n / e.variance;
  }
  return e;
}

double quantile(std::vector<double> v, double prob) {
  std::sort(v.begin(), v.end());
  const double pos = prob * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const auto hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

Eigen::VectorXd evaluate_block(const BatchFunction& f, const Eigen::MatrixXd& x) {
  Eigen::VectorXd y = f(x);
  if (y.size() != x.rows())
    throw std::invalid_argument(kWho + ": f returned " + std::to_string(y.size()) + " values for " +
                                std::to_string(x.rows()) + " points");
  for (Eigen::Index r = 0; r < y.size(); ++r)
    if (!std::isfinite(y(r))) {
      std::string at;
      for (Eigen::Index j = 0; j < x.cols(); ++j) at += (j ? ", " : "") + std::to_string(x(r, j));
      throw std::invalid_argument(kWho + ": f is not finite at (" + at + ")");
    }
  return y;
}

}  // namespace

SobolIndices sobol_indices_batch(const BatchFunction& f, const std::vector<double>& lower,
                                 const std::vector<double>& upper, const SobolOptions& options) {
  if (!f) throw std::invalid_argument(kWho + ": f is empty");
  if (lower.size() != upper.size())
    throw std::invalid_argument(kWho + ": lower has " + std::to_string(lower.size()) +
                                " entries but upper has " + std::to_string(upper.size()));
  if (lower.empty()) throw std::invalid_argument(kWho + ": lower/upper are empty (no inputs)");
  for (std::size_t j = 0; j < lower.size(); ++j)
    if (!std::isfinite(lower[j]) || !std::isfinite(upper[j]) || !(upper[j] > lower[j]))
      throw std::invalid_argument(kWho + ": upper[" + std::to_string(j) + "] must exceed lower[" +
                                  std::to_string(j) + "]");
  if (options.base_samples < 16)
    throw std::invalid_argument(kWho + ": base_samples must be >= 16, got " +
                                std::to_string(options.base_samples));
  if (options.bootstrap_resamples < 0)
    throw std::invalid_argument(kWho + ": bootstrap_resamples must be >= 0");
  if (!(options.confidence_level > 0.0 && options.confidence_level < 1.0))
    throw std::invalid_argument(kWho + ": confidence_level must be in (0, 1)");
  const auto p = static_cast<Eigen::Index>(lower.size());
  const auto n = static_cast<Eigen::Index>(options.base_samples);

  // Base matrices A and B on the unit cube: one 2p-dimensional sequence, A from its first p
  // coordinates and B from the rest, so that A and B are independent.
  Eigen::MatrixXd a(n, p), b(n, p);
  std::vector<double> point(static_cast<std::size_t>(2 * p));
  if (options.sampling == SobolSampling::sobol_sequence) {
    if (2 * p > static_cast<Eigen::Index>(gsl_qrng_sobol->max_dimension))
      throw std::invalid_argument(kWho + ": the Sobol sequence supports at most " +
                                  std::to_string(gsl_qrng_sobol->max_dimension / 2) +
                                  " inputs; use SobolSampling::pseudo_random");
    std::unique_ptr<gsl_qrng, decltype(&gsl_qrng_free)> q(
        gsl_qrng_alloc(gsl_qrng_sobol, static_cast<unsigned>(2 * p)), &gsl_qrng_free);
    if (!q) throw std::bad_alloc();
    for (Eigen::Index r = 0; r < n; ++r) {
      gsl_qrng_get(q.get(), point.data());
      for (Eigen::Index j = 0; j < p; ++j) {
        a(r, j) = point[static_cast<std::size_t>(j)];
        b(r, j) = point[static_cast<std::size_t>(p + j)];
      }
    }
  } else {
    std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937),
                                                          &gsl_rng_free);
    if (!rng) throw std::bad_alloc();
    gsl_rng_set(rng.get(), static_cast<unsigned long>(options.seed));
    for (Eigen::Index r = 0; r < n; ++r)
      for (Eigen::Index j = 0; j < 2 * p; ++j) (j < p ? a(r, j) : b(r, j - p)) = gsl_rng_uniform(rng.get());
  }
  for (Eigen::Index j = 0; j < p; ++j) {
    const double lo = lower[static_cast<std::size_t>(j)], w = upper[static_cast<std::size_t>(j)] - lo;
    a.col(j) = (lo + w * a.col(j).array()).matrix();
    b.col(j) = (lo + w * b.col(j).array()).matrix();
  }

  const Eigen::VectorXd fa = evaluate_block(f, a);
  const Eigen::VectorXd fb = evaluate_block(f, b);
  Eigen::MatrixXd fab(n, p);
  for (Eigen::Index i = 0; i < p; ++i) {
    Eigen::MatrixXd ab = a;
    ab.col(i) = b.col(i);
    fab.col(i) = evaluate_block(f, ab);
  }

  std::vector<Eigen::Index> all(static_cast<std::size_t>(n));
  for (Eigen::Index r = 0; r < n; ++r) all[static_cast<std::size_t>(r)] = r;
  const Estimates e = estimate(fa, fb, fab, all);
  if (!(e.variance > 0.0))
    throw std::invalid_argument(kWho + ": f is constant over the box; its indices are undefined");

  SobolIndices out;
  out.first_order.assign(e.first.data(), e.first.data() + p);
  out.total.assign(e.total.data(), e.total.data() + p);
  out.mean = e.mean;
  out.variance = e.variance;
  out.evaluations = static_cast<std::size_t>(n * (p + 2));

  if (options.bootstrap_resamples > 0) {
    std::mt19937_64 rng(options.seed);
    const auto resamples = static_cast<std::size_t>(options.bootstrap_resamples);
    std::vector<std::vector<double>> s1(static_cast<std::size_t>(p)), st(static_cast<std::size_t>(p));
    std::vector<Eigen::Index> rows(static_cast<std::size_t>(n));
    for (std::size_t k = 0; k < resamples; ++k) {
      for (auto& r : rows) r = static_cast<Eigen::Index>(rng() % static_cast<std::uint64_t>(n));
      const Estimates eb = estimate(fa, fb, fab, rows);
      for (Eigen::Index i = 0; i < p; ++i) {
        s1[static_cast<std::size_t>(i)].push_back(eb.first(i));
        st[static_cast<std::size_t>(i)].push_back(eb.total(i));
      }
    }
    const double tail = 0.5 * (1.0 - options.confidence_level);
    for (std::size_t i = 0; i < static_cast<std::size_t>(p); ++i) {
      out.first_order_lower.push_back(quantile(s1[i], tail));
      out.first_order_upper.push_back(quantile(s1[i], 1.0 - tail));
      out.total_lower.push_back(quantile(st[i], tail));
      out.total_upper.push_back(quantile(st[i], 1.0 - tail));
    }
  }
  return out;
}

SobolIndices sobol_indices(const PointFunction& f, const std::vector<double>& lower,
                           const std::vector<double>& upper, const SobolOptions& options) {
  if (!f) throw std::invalid_argument(kWho + ": f is empty");
  const BatchFunction batch = [&f](const Eigen::MatrixXd& x) {
    Eigen::VectorXd y(x.rows());
    std::vector<double> row(static_cast<std::size_t>(x.cols()));
    for (Eigen::Index r = 0; r < x.rows(); ++r) {
      for (Eigen::Index j = 0; j < x.cols(); ++j) row[static_cast<std::size_t>(j)] = x(r, j);
      y(r) = f(row);
    }
    return y;
  };
  return sobol_indices_batch(batch, lower, upper, options);
}

SobolIndices sobol_indices(const SurrogateModel& model, const std::vector<double>& lower,
                           const std::vector<double>& upper, const SobolOptions& options) {
  if (lower.size() != model.input_dimension())
    throw std::invalid_argument(kWho + ": lower has " + std::to_string(lower.size()) +
                                " entries but the model has " +
                                std::to_string(model.input_dimension()) + " inputs");
  return sobol_indices_batch([&model](const Eigen::MatrixXd& x) { return model.predict_mean(x); },
                             lower, upper, options);
}

}  // namespace demcal::surrogate
