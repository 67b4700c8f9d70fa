#include "surrogate/gaussian_process.hpp"

#include <Eigen/Dense>
#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace demcal::surrogate {
namespace {

const std::string kWho = "gaussian process";
constexpr double kInf = std::numeric_limits<double>::infinity();

// Jitter escalation: relative to the mean diagonal of K, from none up to 1e-6. A factor
// whose reciprocal condition estimate is below kMinRcond leaves too few digits for the
// predictive variance sigma² - kᵀK⁻¹k, so the next level is tried; at the last level any
// successful factorization is accepted.
constexpr int kJitterLevels = 8;  // 0, 1e-12, 1e-11, ..., 1e-6
constexpr double kMinRcond = 1e-12;

// Rows of predictions processed together: bounds the memory of the m x n cross covariance.
constexpr Eigen::Index kPredictionChunk = 1024;

struct Factor {
  Eigen::LLT<Eigen::MatrixXd> llt;
  double jitter = 0.0;
};

std::optional<Factor> factorize_with_jitter(const Eigen::MatrixXd& K) {
  const double scale = K.diagonal().mean();
  const Eigen::Index n = K.rows();
  for (int level = 0; level < kJitterLevels; ++level) {
    const double jitter = level == 0 ? 0.0 : scale * std::pow(10.0, level - 13);
    Factor f;
    f.jitter = jitter;
    f.llt.compute(K + jitter * Eigen::MatrixXd::Identity(n, n));
    if (f.llt.info() != Eigen::Success) continue;
    if (f.llt.rcond() >= kMinRcond || level + 1 == kJitterLevels) return f;
  }
  return std::nullopt;
}

// Internal (unit box, standardized output) hyperparameters.
struct Params {
  Eigen::VectorXd length;
  double signal = 1.0;
  double nugget = 0.0;  // NuggetMode::estimated only
};

struct Problem {
  CovarianceKernel kernel = CovarianceKernel::matern52;
  NuggetMode mode = NuggetMode::none;
  Eigen::MatrixXd u;             // n x p, unit box
  Eigen::VectorXd ys;            // standardized
  Eigen::MatrixXd H;             // n x q mean basis
  Eigen::VectorXd point_nugget;  // n, standardized units (zeros unless fixed)
  std::vector<Eigen::MatrixXd> sqdiff;  // per input: (u_aj - u_bj)²
};

Eigen::MatrixXd mean_basis_of(MeanFunction mean, const Eigen::MatrixXd& u) {
  if (mean == MeanFunction::constant) return Eigen::MatrixXd::Ones(u.rows(), 1);
  Eigen::MatrixXd H(u.rows(), u.cols() + 1);
  H.col(0).setOnes();
  H.rightCols(u.cols()) = u;
  return H;
}

// Correlation matrix R and, if asked, the radial factors g(r) of every pair.
void correlations(const Problem& pb, const Eigen::VectorXd& length, Eigen::MatrixXd& R,
                  Eigen::MatrixXd* G) {
  const Eigen::Index n = pb.u.rows();
  Eigen::MatrixXd r2 = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t j = 0; j < pb.sqdiff.size(); ++j) {
    const double l = length(static_cast<Eigen::Index>(j));
    r2 += pb.sqdiff[j] / (l * l);
  }
  R.resize(n, n);
  if (G) G->resize(n, n);
  for (Eigen::Index b = 0; b < n; ++b)
    for (Eigen::Index a = 0; a < n; ++a) {
      const double r = std::sqrt(r2(a, b));
      R(a, b) = kernel_correlation(pb.kernel, r);
      if (G) (*G)(a, b) = kernel_radial_factor(pb.kernel, r);
    }
}

Eigen::MatrixXd covariance_with_nugget(const Problem& pb, const Params& prm,
                                                  const Eigen::MatrixXd& R) {
  Eigen::MatrixXd K = prm.signal * R;
  if (pb.mode == NuggetMode::estimated) K.diagonal().array() += prm.nugget;
  if (pb.mode == NuggetMode::fixed) K.diagonal() += pb.point_nugget;
  return K;
}

struct Evaluation {
  double log_likelihood = 0.0;  // standardized units
  Eigen::VectorXd gradient;     // w.r.t. log parameters, packed like the optimizer's vector
  Eigen::VectorXd beta;
  double jitter = 0.0;
};

// Profile log likelihood with the GLS mean; gradient by the envelope theorem (beta is
// optimal, so its own change does not contribute): 0.5 tr((a aᵀ - K⁻¹) dK).
std::optional<Evaluation> evaluate(const Problem& pb, const Params& prm, bool want_gradient) {
  const Eigen::Index n = pb.u.rows();
  Eigen::MatrixXd R, G;
  correlations(pb, prm.length, R, want_gradient ? &G : nullptr);
  const auto factor = factorize_with_jitter(covariance_with_nugget(pb, prm, R));
  if (!factor) return std::nullopt;
  const Eigen::MatrixXd kinv_h = factor->llt.solve(pb.H);
  const Eigen::LLT<Eigen::MatrixXd> a_llt(pb.H.transpose() * kinv_h);
  if (a_llt.info() != Eigen::Success) return std::nullopt;
  Evaluation ev;
  ev.jitter = factor->jitter;
  ev.beta = a_llt.solve(kinv_h.transpose() * pb.ys);
  const Eigen::VectorXd resid = pb.ys - pb.H * ev.beta;
  const Eigen::VectorXd alpha = factor->llt.solve(resid);
  const double log_det_half = factor->llt.matrixLLT().diagonal().array().log().sum();
  ev.log_likelihood = -0.5 * resid.dot(alpha) - log_det_half -
                      0.5 * static_cast<double>(n) * std::log(2.0 * std::numbers::pi);
  if (!std::isfinite(ev.log_likelihood)) return std::nullopt;
  if (want_gradient) {
    const Eigen::Index p = pb.u.cols();
    const Eigen::MatrixXd kinv = factor->llt.solve(Eigen::MatrixXd::Identity(n, n));
    const Eigen::MatrixXd W = alpha * alpha.transpose() - kinv;
    ev.gradient.resize(p + 1 + (pb.mode == NuggetMode::estimated ? 1 : 0));
    const Eigen::MatrixXd WG = W.cwiseProduct(G);
    for (Eigen::Index j = 0; j < p; ++j) {
      const double l = prm.length(j);
      ev.gradient(j) = 0.5 * prm.signal *
                       WG.cwiseProduct(pb.sqdiff[static_cast<std::size_t>(j)]).sum() / (l * l);
    }
    ev.gradient(p) = 0.5 * prm.signal * W.cwiseProduct(R).sum();
    if (pb.mode == NuggetMode::estimated) ev.gradient(p + 1) = 0.5 * prm.nugget * W.trace();
  }
  return ev;
}

Params unpack(const double* v, Eigen::Index p, NuggetMode mode) {
  Params prm;
  prm.length.resize(p);
  for (Eigen::Index j = 0; j < p; ++j) prm.length(j) = std::exp(v[j]);
  prm.signal = std::exp(v[p]);
  prm.nugget = mode == NuggetMode::estimated ? std::exp(v[p + 1]) : 0.0;
  return prm;
}

struct Objective {
  const Problem* problem = nullptr;
  int evaluations = 0;
  double best = kInf;  // of -log likelihood
  std::vector<double> best_x;
};

// Value returned where K cannot be factorized: large but finite, so that the line search
// backs off instead of propagating infinities.
constexpr double kFailedObjective = 1e30;

double negative_log_likelihood(unsigned dim, const double* x, double* grad, void* data) {
  auto* obj = static_cast<Objective*>(data);
  ++obj->evaluations;
  const Problem& pb = *obj->problem;
  std::optional<Evaluation> ev;
  try {  // nothing may propagate through NLopt's C code
    ev = evaluate(pb, unpack(x, pb.u.cols(), pb.mode), grad != nullptr);
  } catch (...) {
    ev.reset();
  }
  if (!ev) {
    if (grad) std::fill(grad, grad + dim, 0.0);
    return kFailedObjective;
  }
  if (grad)
    for (unsigned k = 0; k < dim; ++k) grad[k] = -ev->gradient(static_cast<Eigen::Index>(k));
  const double f = -ev->log_likelihood;
  if (f < obj->best) {
    obj->best = f;
    obj->best_x.assign(x, x + dim);
  }
  return f;
}

double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

void check_positive(double v, const std::string& what) {
  if (!(v > 0.0) || !std::isfinite(v))
    throw std::invalid_argument(kWho + ": " + what + " must be finite and > 0");
}

void check_bounds(const HyperparameterBounds& b) {
  const auto check = [](double lo, double hi, const std::string& name) {
    check_positive(lo, "bounds.min_" + name);
    check_positive(hi, "bounds.max_" + name);
    if (!(hi > lo))
      throw std::invalid_argument(kWho + ": bounds.max_" + name + " must exceed bounds.min_" + name);
  };
  check(b.min_length_scale, b.max_length_scale, "length_scale");
  check(b.min_signal_variance, b.max_signal_variance, "signal_variance");
  check(b.min_nugget_variance, b.max_nugget_variance, "nugget_variance");
}

// Multi-start L-BFGS on the log parameters; the first start is a fixed central guess, the
// others are drawn from `options.seed`.
std::pair<Params, MaximumLikelihoodReport> maximize_likelihood(const Problem& pb,
                                                               const GaussianProcessOptions& options,
                                                               const std::vector<std::string>& names) {
  const Eigen::Index p = pb.u.cols();
  MaximumLikelihoodReport report;
  check_bounds(options.bounds);
  if (options.starts < 1) throw std::invalid_argument(kWho + ": starts must be >= 1");
  if (options.max_evaluations < 10)
    throw std::invalid_argument(kWho + ": max_evaluations must be >= 10");
  const auto& b = options.bounds;
  const bool with_nugget = options.nugget == NuggetMode::estimated;
  const auto dim = static_cast<unsigned>(p + 1 + (with_nugget ? 1 : 0));
  std::vector<double> lower_b(dim), upper_b(dim), center(dim), draw_lo(dim), draw_hi(dim);
  // Starts are drawn from a narrower box of plausible values (clipped to the bounds):
  // corners of the full box are flat likelihood regions where L-BFGS stalls.
  const auto set = [&](unsigned k, double lo_v, double hi_v, double c, double dlo, double dhi) {
    lower_b[k] = std::log(lo_v);
    upper_b[k] = std::log(hi_v);
    center[k] = std::clamp(std::log(c), lower_b[k], upper_b[k]);
    draw_lo[k] = std::clamp(std::log(dlo), lower_b[k], upper_b[k]);
    draw_hi[k] = std::clamp(std::log(dhi), lower_b[k], upper_b[k]);
    if (!(draw_hi[k] > draw_lo[k])) {
      draw_lo[k] = lower_b[k];
      draw_hi[k] = upper_b[k];
    }
  };
  for (unsigned j = 0; j < static_cast<unsigned>(p); ++j)
    set(j, b.min_length_scale, b.max_length_scale, 0.3, 0.05, 2.0);
  set(static_cast<unsigned>(p), b.min_signal_variance, b.max_signal_variance, 1.0, 0.05, 20.0);
  if (with_nugget)
    set(dim - 1, b.min_nugget_variance, b.max_nugget_variance, 1e-3, 1e-8, 0.3);

  std::mt19937_64 rng(options.seed);
  Objective overall;
  overall.problem = &pb;
  for (int start = 0; start < options.starts; ++start) {
    std::vector<double> x0 = center;
    if (start > 0)
      for (unsigned k = 0; k < dim; ++k)
        x0[k] = draw_lo[k] + (draw_hi[k] - draw_lo[k]) * uniform01(rng);
    Objective obj;
    obj.problem = &pb;
    nlopt::opt opt(nlopt::LD_LBFGS, dim);
    opt.set_lower_bounds(lower_b);
    opt.set_upper_bounds(upper_b);
    opt.set_min_objective(negative_log_likelihood, &obj);
    opt.set_maxeval(options.max_evaluations);
    opt.set_ftol_rel(1e-10);
    opt.set_xtol_rel(1e-8);
    double f = 0.0;
    try {
      opt.optimize(x0, f);
    } catch (const std::runtime_error&) {
      // Round-off limits and line-search failures end a start early; the best point it
      // evaluated (recorded by the objective) is still a valid candidate.
    }
    report.evaluations += obj.evaluations;
    report.start_log_likelihoods.push_back(obj.best_x.empty() ? -kInf : -obj.best);
    if (!obj.best_x.empty() && obj.best < overall.best) {
      overall.best = obj.best;
      overall.best_x = obj.best_x;
      report.best_start = start;
    }
  }
  if (overall.best_x.empty())
    throw std::runtime_error(kWho + ": the likelihood could not be evaluated at any start: the "
                             "covariance matrix is never positive definite");
  Params best = unpack(overall.best_x.data(), p, options.nugget);
  // Within 1e-6 in log space counts as sitting on the bound.
  const auto note = [&](unsigned k, const std::string& name) {
    if (overall.best_x[k] <= lower_b[k] + 1e-6) report.at_bounds.push_back(name + " at lower bound");
    if (overall.best_x[k] >= upper_b[k] - 1e-6) report.at_bounds.push_back(name + " at upper bound");
  };
  for (Eigen::Index j = 0; j < p; ++j)
    note(static_cast<unsigned>(j), "length_scale[" + names[static_cast<std::size_t>(j)] + "]");
  note(static_cast<unsigned>(p), "signal_variance");
  if (with_nugget) note(dim - 1, "nugget_variance");
  return {best, report};
}

}  // namespace

std::string to_string(MeanFunction mean) {
  return mean == MeanFunction::constant ? "constant" : "linear";
}

std::string to_string(NuggetMode mode) {
  switch (mode) {
    case NuggetMode::none: return "none";
    case NuggetMode::estimated: return "estimated";
    case NuggetMode::fixed: return "fixed";
  }
  throw std::invalid_argument(kWho + ": unknown nugget mode enumerator");
}

MeanFunction mean_function_from_string(const std::string& name) {
  if (name == "constant") return MeanFunction::constant;
  if (name == "linear") return MeanFunction::linear;
  throw std::invalid_argument(kWho + ": unknown mean function '" + name +
                              "' (expected constant or linear)");
}

NuggetMode nugget_mode_from_string(const std::string& name) {
  if (name == "none") return NuggetMode::none;
  if (name == "estimated") return NuggetMode::estimated;
  if (name == "fixed") return NuggetMode::fixed;
  throw std::invalid_argument(kWho + ": unknown nugget mode '" + name +
                              "' (expected none, estimated or fixed)");
}

GaussianProcess GaussianProcess::fit(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                     const GaussianProcessOptions& options) {
  const auto names = detail::resolve_input_names(kWho, options.input_names, x.cols());
  detail::check_training_table(kWho, x, y, names);
  const Eigen::Index n = x.rows(), p = x.cols();
  const Eigen::Index q = options.mean == MeanFunction::constant ? 1 : p + 1;
  if (n < q + 2)
    throw std::invalid_argument(kWho + ": a " + to_string(options.mean) + " mean in " +
                                std::to_string(p) + " inputs needs at least " +
                                std::to_string(q + 2) + " points (x rows), got " + std::to_string(n));
  auto [lo, hi] = detail::resolve_box(kWho, x, options.lower, options.upper, names);
  if (options.nugget == NuggetMode::fixed) {
    if (static_cast<Eigen::Index>(options.nugget_variances.size()) != n)
      throw std::invalid_argument(kWho + ": nugget_variances has " +
                                  std::to_string(options.nugget_variances.size()) +
                                  " values but there are " + std::to_string(n) + " points");
    for (std::size_t i = 0; i < options.nugget_variances.size(); ++i)
      if (!(options.nugget_variances[i] >= 0.0) || !std::isfinite(options.nugget_variances[i]))
        throw std::invalid_argument(kWho + ": nugget_variances[" + std::to_string(i) +
                                    "] must be finite and >= 0");
  } else if (!options.nugget_variances.empty()) {
    throw std::invalid_argument(kWho + ": nugget_variances given but the nugget mode is '" +
                                to_string(options.nugget) + "', not 'fixed'");
  }

  State s;
  s.kernel = options.kernel;
  s.mean = options.mean;
  s.nugget_mode = options.nugget;
  s.input_names = names;
  s.lower = lo;
  s.upper = hi;
  s.x = x;
  s.y = y;
  s.output_mean = y.mean();
  const double sd = std::sqrt((y.array() - s.output_mean).square().sum() / static_cast<double>(n - 1));
  // A constant output has nothing to standardize; unit scale keeps the algebra defined.
  s.output_scale = sd > 0.0 ? sd : 1.0;
  const double var_scale = s.output_scale * s.output_scale;
  if (options.nugget == NuggetMode::fixed) {
    s.point_nugget_variances.resize(n);
    for (Eigen::Index i = 0; i < n; ++i)
      s.point_nugget_variances(i) = options.nugget_variances[static_cast<std::size_t>(i)] / var_scale;
  }

  Problem pb;
  pb.kernel = options.kernel;
  pb.mode = options.nugget;
  pb.u.resize(n, p);
  for (Eigen::Index j = 0; j < p; ++j) pb.u.col(j) = (x.col(j).array() - lo(j)) / (hi(j) - lo(j));
  pb.ys = (y.array() - s.output_mean) / s.output_scale;
  pb.H = mean_basis_of(options.mean, pb.u);
  pb.point_nugget = options.nugget == NuggetMode::fixed ? s.point_nugget_variances
                                                        : Eigen::VectorXd::Zero(n);
  for (Eigen::Index j = 0; j < p; ++j) {
    Eigen::MatrixXd d(n, n);
    for (Eigen::Index b = 0; b < n; ++b)
      for (Eigen::Index a = 0; a < n; ++a) d(a, b) = std::pow(pb.u(a, j) - pb.u(b, j), 2);
    pb.sqdiff.push_back(std::move(d));
  }
  {
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(pb.H);
    if (lu.rank() < q)
      throw std::invalid_argument(kWho + ": the " + to_string(options.mean) +
                                  " mean function is not identifiable from these points");
  }

  Params best;
  MaximumLikelihoodReport report;
  if (options.hyperparameters) {
    const auto& h = *options.hyperparameters;
    if (static_cast<Eigen::Index>(h.length_scales.size()) != p)
      throw std::invalid_argument(kWho + ": hyperparameters.length_scales has " +
                                  std::to_string(h.length_scales.size()) + " values but there are " +
                                  std::to_string(p) + " inputs");
    best.length.resize(p);
    for (Eigen::Index j = 0; j < p; ++j) {
      const double l = h.length_scales[static_cast<std::size_t>(j)];
      check_positive(l, "hyperparameters.length_scales[" + std::to_string(j) + "] (input " +
                            detail::input_label(names, j) + ")");
      best.length(j) = l / (hi(j) - lo(j));
    }
    check_positive(h.signal_variance, "hyperparameters.signal_variance");
    best.signal = h.signal_variance / var_scale;
    if (options.nugget == NuggetMode::estimated) {
      if (!(h.nugget_variance >= 0.0) || !std::isfinite(h.nugget_variance))
        throw std::invalid_argument(kWho + ": hyperparameters.nugget_variance must be finite and >= 0");
      best.nugget = h.nugget_variance / var_scale;
    }
  } else {
    std::tie(best, report) = maximize_likelihood(pb, options, names);
  }

  const auto ev = evaluate(pb, best, false);
  if (!ev)
    throw std::runtime_error(kWho + ": the covariance matrix is not positive definite even with "
                             "jitter 1e-6 x its mean diagonal; duplicate input points with no "
                             "nugget? use NuggetMode::estimated");
  s.length_scales = best.length;
  s.signal_variance = best.signal;
  s.nugget_variance = options.nugget == NuggetMode::estimated ? best.nugget : 0.0;
  s.mean_coefficients = ev->beta;
  s.jitter = ev->jitter;
  // Density of y in its own units: the standardization contributes its Jacobian.
  s.log_marginal_likelihood = ev->log_likelihood - static_cast<double>(n) * std::log(s.output_scale);
  GaussianProcess gp(std::move(s));
  gp.report_ = std::move(report);
  return gp;
}

GaussianProcess GaussianProcess::from_state(State s) {
  const std::string who = kWho + " state";
  const Eigen::Index p = s.x.cols(), n = s.x.rows();
  if (p < 1) throw std::invalid_argument(who + ": x has no columns");
  if (static_cast<Eigen::Index>(s.input_names.size()) != p)
    throw std::invalid_argument(who + ": input_names does not match the columns of x");
  detail::check_training_table(who, s.x, s.y, s.input_names);
  if (s.lower.size() != p || s.upper.size() != p || !((s.upper - s.lower).array() > 0.0).all())
    throw std::invalid_argument(who + ": lower/upper must have one entry per input, upper > lower");
  if (s.length_scales.size() != p || !(s.length_scales.array() > 0.0).all() ||
      !s.length_scales.allFinite())
    throw std::invalid_argument(who + ": length_scales must have one positive entry per input");
  if (!(s.signal_variance > 0.0) || !std::isfinite(s.signal_variance))
    throw std::invalid_argument(who + ": signal_variance must be finite and > 0");
  if (!(s.output_scale > 0.0) || !std::isfinite(s.output_scale) || !std::isfinite(s.output_mean))
    throw std::invalid_argument(who + ": output_mean/output_scale must be finite, scale > 0");
  if (!(s.nugget_variance >= 0.0) || !std::isfinite(s.nugget_variance))
    throw std::invalid_argument(who + ": nugget_variance must be finite and >= 0");
  if (s.nugget_mode == NuggetMode::fixed &&
      (s.point_nugget_variances.size() != n || !(s.point_nugget_variances.array() >= 0.0).all()))
    throw std::invalid_argument(who + ": point_nugget_variances must have one entry >= 0 per point");
  const Eigen::Index q = s.mean == MeanFunction::constant ? 1 : p + 1;
  if (s.mean_coefficients.size() != q || !s.mean_coefficients.allFinite())
    throw std::invalid_argument(who + ": mean_coefficients must have " + std::to_string(q) +
                                " finite entries");
  if (!(s.jitter >= 0.0) || !std::isfinite(s.jitter))
    throw std::invalid_argument(who + ": jitter must be finite and >= 0");
  return GaussianProcess(std::move(s));
}

GaussianProcess::GaussianProcess(State state) : state_(std::move(state)) {
  if (state_.nugget_mode != NuggetMode::estimated) state_.nugget_variance = 0.0;
  if (state_.nugget_mode != NuggetMode::fixed) state_.point_nugget_variances.resize(0);
  u_ = unit_box(state_.x);
  Eigen::MatrixXd K = cross_covariance(u_);
  if (state_.nugget_mode == NuggetMode::estimated) K.diagonal().array() += state_.nugget_variance;
  if (state_.nugget_mode == NuggetMode::fixed) K.diagonal() += state_.point_nugget_variances;
  K.diagonal().array() += state_.jitter;
  k_llt_.compute(K);
  if (k_llt_.info() != Eigen::Success)
    throw std::runtime_error(kWho + ": the covariance matrix is not positive definite with the "
                             "stored jitter");
  const Eigen::MatrixXd H = mean_basis(u_);
  const Eigen::VectorXd ys = (state_.y.array() - state_.output_mean) / state_.output_scale;
  alpha_ = k_llt_.solve(ys - H * state_.mean_coefficients);
  kinv_h_ = k_llt_.solve(H);
  hkh_llt_.compute(H.transpose() * kinv_h_);
  if (hkh_llt_.info() != Eigen::Success)
    throw std::invalid_argument(kWho + ": the mean function is not identifiable from these points");
}

std::string GaussianProcess::description() const {
  return "gaussian process, " + to_string(state_.kernel) + " kernel, " + to_string(state_.mean) +
         " mean, nugget " + to_string(state_.nugget_mode) + ", " +
         std::to_string(state_.x.rows()) + " points";
}

std::size_t GaussianProcess::input_dimension() const {
  return static_cast<std::size_t>(state_.x.cols());
}

GaussianProcessHyperparameters GaussianProcess::hyperparameters() const {
  GaussianProcessHyperparameters h;
  for (Eigen::Index j = 0; j < state_.x.cols(); ++j)
    h.length_scales.push_back(state_.length_scales(j) * (state_.upper(j) - state_.lower(j)));
  const double v = state_.output_scale * state_.output_scale;
  h.signal_variance = state_.signal_variance * v;
  h.nugget_variance = state_.nugget_variance * v;
  return h;
}

Eigen::VectorXd GaussianProcess::point_nugget_variances() const {
  const double v = state_.output_scale * state_.output_scale;
  if (state_.nugget_mode == NuggetMode::fixed) return state_.point_nugget_variances * v;
  return Eigen::VectorXd::Constant(state_.x.rows(), state_.nugget_variance * v);
}

Eigen::VectorXd GaussianProcess::mean_coefficients() const {
  const Eigen::VectorXd& beta = state_.mean_coefficients;
  Eigen::VectorXd c = state_.output_scale * beta;
  c(0) += state_.output_mean;
  for (Eigen::Index j = 1; j < beta.size(); ++j) {
    const double range = state_.upper(j - 1) - state_.lower(j - 1);
    c(j) = state_.output_scale * beta(j) / range;
    c(0) -= c(j) * state_.lower(j - 1);
  }
  return c;
}

double GaussianProcess::relative_jitter() const { return state_.jitter / state_.signal_variance; }

Eigen::MatrixXd GaussianProcess::unit_box(const Eigen::MatrixXd& points) const {
  Eigen::MatrixXd u(points.rows(), points.cols());
  for (Eigen::Index j = 0; j < points.cols(); ++j)
    u.col(j) = (points.col(j).array() - state_.lower(j)) / (state_.upper(j) - state_.lower(j));
  return u;
}

Eigen::MatrixXd GaussianProcess::mean_basis(const Eigen::MatrixXd& u) const {
  return mean_basis_of(state_.mean, u);
}

// sigma² rho between each row of u (unit box) and each training point.
Eigen::MatrixXd GaussianProcess::cross_covariance(const Eigen::MatrixXd& u) const {
  const Eigen::Index m = u.rows(), n = u_.rows();
  const Eigen::ArrayXd inv_l2 = state_.length_scales.array().square().inverse();
  Eigen::MatrixXd k(m, n);
  for (Eigen::Index b = 0; b < n; ++b)
    for (Eigen::Index a = 0; a < m; ++a) {
      const double r2 = ((u.row(a) - u_.row(b)).array().square().transpose() * inv_l2).sum();
      k(a, b) = state_.signal_variance * kernel_correlation(state_.kernel, std::sqrt(r2));
    }
  return k;
}

Eigen::VectorXd GaussianProcess::predict_mean(const Eigen::MatrixXd& points) const {
  detail::check_points(kWho, points, state_.x.cols());
  const Eigen::MatrixXd u = unit_box(points);
  Eigen::VectorXd mean(points.rows());
  for (Eigen::Index start = 0; start < u.rows(); start += kPredictionChunk) {
    const Eigen::Index m = std::min(kPredictionChunk, u.rows() - start);
    const Eigen::MatrixXd uc = u.middleRows(start, m);
    mean.segment(start, m) = mean_basis(uc) * state_.mean_coefficients + cross_covariance(uc) * alpha_;
  }
  return (state_.output_mean + state_.output_scale * mean.array()).matrix();
}

Prediction GaussianProcess::predict(const Eigen::MatrixXd& points) const {
  detail::check_points(kWho, points, state_.x.cols());
  const Eigen::MatrixXd u = unit_box(points);
  Prediction pr;
  pr.mean.resize(points.rows());
  pr.variance.resize(points.rows());
  for (Eigen::Index start = 0; start < u.rows(); start += kPredictionChunk) {
    const Eigen::Index m = std::min(kPredictionChunk, u.rows() - start);
    const Eigen::MatrixXd uc = u.middleRows(start, m);
    const Eigen::MatrixXd ks = cross_covariance(uc);
    const Eigen::MatrixXd hs = mean_basis(uc);
    pr.mean.segment(start, m) = hs * state_.mean_coefficients + ks * alpha_;
    const Eigen::MatrixXd v = k_llt_.matrixL().solve(ks.transpose());
    // Universal kriging: the GLS coefficients' own uncertainty adds rᵀ(HᵀK⁻¹H)⁻¹r.
    const Eigen::MatrixXd r = hs.transpose() - kinv_h_.transpose() * ks.transpose();
    const Eigen::MatrixXd w = hkh_llt_.matrixL().solve(r);
    pr.variance.segment(start, m) =
        (state_.signal_variance - v.colwise().squaredNorm().array() + w.colwise().squaredNorm().array())
            .max(0.0)
            .matrix()
            .transpose();
  }
  pr.mean = (state_.output_mean + state_.output_scale * pr.mean.array()).matrix();
  pr.variance *= state_.output_scale * state_.output_scale;
  return pr;
}

Eigen::MatrixXd GaussianProcess::gradient(const Eigen::MatrixXd& points) const {
  detail::check_points(kWho, points, state_.x.cols());
  const Eigen::MatrixXd u = unit_box(points);
  const Eigen::Index p = u.cols(), n = u_.rows();
  const Eigen::ArrayXd inv_l2 = state_.length_scales.array().square().inverse();
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(u.rows(), p);
  for (Eigen::Index a = 0; a < u.rows(); ++a) {
    Eigen::ArrayXd grad_u = Eigen::ArrayXd::Zero(p);
    for (Eigen::Index b = 0; b < n; ++b) {
      const Eigen::ArrayXd d = (u.row(a) - u_.row(b)).array().transpose();
      const double r = std::sqrt((d.square() * inv_l2).sum());
      grad_u -= state_.signal_variance * kernel_radial_factor(state_.kernel, r) * alpha_(b) * d * inv_l2;
    }
    if (state_.mean == MeanFunction::linear) grad_u += state_.mean_coefficients.tail(p).array();
    g.row(a) = (state_.output_scale * grad_u / (state_.upper - state_.lower).array()).transpose();
  }
  return g;
}

LeaveOneOut GaussianProcess::leave_one_out() const {
  const Eigen::Index n = state_.x.rows();
  const Eigen::MatrixXd kinv = k_llt_.solve(Eigen::MatrixXd::Identity(n, n));
  const Eigen::MatrixXd Q = kinv - kinv_h_ * hkh_llt_.solve(kinv_h_.transpose());
  const Eigen::VectorXd ys = (state_.y.array() - state_.output_mean) / state_.output_scale;
  const Eigen::VectorXd qy = Q * ys;
  LeaveOneOut loo;
  loo.observed = state_.y;
  loo.mean.resize(n);
  loo.variance.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    loo.mean(i) = state_.output_mean + state_.output_scale * (ys(i) - qy(i) / Q(i, i));
    loo.variance(i) = state_.output_scale * state_.output_scale / Q(i, i);
  }
  return loo;
}

}  // namespace demcal::surrogate
