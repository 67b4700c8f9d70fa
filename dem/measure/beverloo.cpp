#include "dem/measure/beverloo.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace demcal::dem {
namespace {

std::string number(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

nlohmann::json finite_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

void require_positive(double x, const char* where, const char* name) {
  if (!(std::isfinite(x) && x > 0.0)) {
    throw std::invalid_argument(std::string(where) + ": " + name + " must be finite and > 0, got " +
                                number(x));
  }
}

void validate_setup(const BeverlooSetup& s, const char* where) {
  require_positive(s.bulk_density_kg_m3, where, "setup.bulk_density_kg_m3");
  require_positive(s.gravity_m_s2, where, "setup.gravity_m_s2");
  require_positive(s.particle_diameter_m, where, "setup.particle_diameter_m");
  if (s.shape == OrificeShape::slot) require_positive(s.slot_length_m, where, "setup.slot_length_m");
}

double exponent(const BeverlooSetup& s) { return s.shape == OrificeShape::circle ? 2.5 : 1.5; }

// Flow rate per unit C and per unit (D0 - k d)^p: rho sqrt(g), times L for a slot.
double prefactor(const BeverlooSetup& s) {
  const double a = s.bulk_density_kg_m3 * std::sqrt(s.gravity_m_s2);
  return s.shape == OrificeShape::circle ? a : a * s.slot_length_m;
}

}  // namespace

double beverloo_flow_rate_kg_s(const BeverlooSetup& setup, double orifice_m, double c, double k) {
  constexpr const char* kWhere = "beverloo_flow_rate_kg_s";
  validate_setup(setup, kWhere);
  require_positive(c, kWhere, "c");
  if (!std::isfinite(k)) throw std::invalid_argument("beverloo_flow_rate_kg_s: k must be finite");
  const double open_m = orifice_m - k * setup.particle_diameter_m;
  if (!(std::isfinite(orifice_m) && open_m > 0.0)) {
    throw std::invalid_argument("beverloo_flow_rate_kg_s: orifice_m = " + number(orifice_m) +
                                " must exceed k d = " + number(k * setup.particle_diameter_m) +
                                " m (the law predicts no flow)");
  }
  return c * prefactor(setup) * std::pow(open_m, exponent(setup));
}

BeverlooFit fit_beverloo(const BeverlooSetup& setup, const std::vector<double>& orifice_m,
                         const std::vector<double>& flow_rate_kg_s,
                         const std::vector<double>& flow_rate_std_error_kg_s) {
  constexpr const char* kWhere = "fit_beverloo";
  validate_setup(setup, kWhere);
  const std::size_t n = orifice_m.size();
  if (flow_rate_kg_s.size() != n) {
    throw std::invalid_argument("fit_beverloo: flow_rate_kg_s has " +
                                std::to_string(flow_rate_kg_s.size()) +
                                " points but orifice_m has " + std::to_string(n));
  }
  const bool weighted = !flow_rate_std_error_kg_s.empty();
  if (weighted && flow_rate_std_error_kg_s.size() != n) {
    throw std::invalid_argument("fit_beverloo: flow_rate_std_error_kg_s has " +
                                std::to_string(flow_rate_std_error_kg_s.size()) +
                                " points but orifice_m has " + std::to_string(n) +
                                " (give one error per point, or none)");
  }
  if (n < 2) {
    throw std::invalid_argument("fit_beverloo: orifice_m needs at least 2 points, got " +
                                std::to_string(n));
  }
  for (std::size_t i = 0; i < n; ++i) {
    require_positive(orifice_m[i], kWhere, "orifice_m");
    // A zero rate is a clog, which the law does not describe.
    require_positive(flow_rate_kg_s[i], kWhere, "flow_rate_kg_s");
    if (weighted) require_positive(flow_rate_std_error_kg_s[i], kWhere, "flow_rate_std_error_kg_s");
  }

  const double p = exponent(setup);
  const double a = prefactor(setup);
  const double d = setup.particle_diameter_m;
  // y = (W / a)^(1/p) = C^(1/p) (D0 - k d): the same line as (W/L)^(1/p)
  // divided by (rho sqrt g)^(1/p), which keeps y on the scale of D0 (metres)
  // so the sums are well conditioned whatever the units of W.
  std::vector<double> y(n), w(n, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    y[i] = std::pow(flow_rate_kg_s[i] / a, 1.0 / p);
    if (weighted) {
      // dy/dW = y / (p W): a relative error of W becomes 1/p of it in y.
      const double sigma_y = y[i] * flow_rate_std_error_kg_s[i] / (p * flow_rate_kg_s[i]);
      w[i] = 1.0 / (sigma_y * sigma_y);
    }
  }
  double sw = 0.0, mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sw += w[i];
    mx += w[i] * orifice_m[i];
    my += w[i] * y[i];
  }
  mx /= sw;
  my /= sw;
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += w[i] * (orifice_m[i] - mx) * (orifice_m[i] - mx);
    sxy += w[i] * (orifice_m[i] - mx) * (y[i] - my);
  }
  if (!(sxx > 0.0)) {
    throw std::invalid_argument("fit_beverloo: orifice_m needs at least 2 distinct sizes");
  }
  const double slope = sxy / sxx;  // C^(1/p)
  const double intercept = my - slope * mx;
  if (!(slope > 0.0)) {
    throw std::invalid_argument(
        "fit_beverloo: flow_rate_kg_s does not grow with orifice_m; Beverloo's law cannot be "
        "fitted to these points");
  }

  BeverlooFit f;
  f.points = n;
  f.weighted = weighted;
  f.c = std::pow(slope, p);
  f.k = -intercept / (slope * d);
  // Report the line in the documented variables, y = (W / L_or_1)^(1/p).
  const double to_documented = std::pow(setup.bulk_density_kg_m3 * std::sqrt(setup.gravity_m_s2),
                                        1.0 / p);
  f.slope = slope * to_documented;
  f.intercept = intercept * to_documented;

  f.residuals_kg_s.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double open_m = std::max(0.0, orifice_m[i] - f.k * d);
    f.residuals_kg_s[i] = flow_rate_kg_s[i] - f.c * a * std::pow(open_m, p);
  }

  if (n >= 3) {
    double chi2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double r = y[i] - (intercept + slope * orifice_m[i]);
      chi2 += w[i] * r * r;
    }
    const double dof = static_cast<double>(n - 2);
    // Unweighted: the scatter is the only error estimate. Weighted: the stated
    // errors, inflated if the points scatter more than they claim (discharge
    // rate errors from a fit of a cumulative curve tend to be too small).
    double scale = chi2 / dof;
    if (weighted) {
      f.reduced_chi_squared = chi2 / dof;
      scale = std::max(1.0, f.reduced_chi_squared);
    }
    const double var_s = scale / sxx;
    const double var_b = scale * (1.0 / sw + mx * mx / sxx);
    const double cov_sb = -scale * mx / sxx;
    // Delta method: C = s^p, k = -b / (s d).
    const double dc_ds = p * f.c / slope;
    const double dk_ds = -f.k / slope;
    const double dk_db = -1.0 / (slope * d);
    const double var_c = dc_ds * dc_ds * var_s;
    const double var_k = dk_ds * dk_ds * var_s + dk_db * dk_db * var_b + 2.0 * dk_ds * dk_db * cov_sb;
    const double cov_ck = dc_ds * (dk_ds * var_s + dk_db * cov_sb);
    f.c_std_error = std::sqrt(var_c);
    f.k_std_error = std::sqrt(std::max(0.0, var_k));
    if (var_c > 0.0 && var_k > 0.0) f.c_k_correlation = cov_ck / std::sqrt(var_c * var_k);
  }
  return f;
}

nlohmann::json to_json(const BeverlooFit& f) {
  nlohmann::json r = nlohmann::json::array();
  for (double x : f.residuals_kg_s) r.push_back(finite_or_null(x));
  return {{"c", finite_or_null(f.c)},
          {"c_std_error", finite_or_null(f.c_std_error)},
          {"k", finite_or_null(f.k)},
          {"k_std_error", finite_or_null(f.k_std_error)},
          {"c_k_correlation", finite_or_null(f.c_k_correlation)},
          {"slope", finite_or_null(f.slope)},
          {"intercept", finite_or_null(f.intercept)},
          {"residuals_kg_s", std::move(r)},
          {"reduced_chi_squared", finite_or_null(f.reduced_chi_squared)},
          {"points", f.points},
          {"weighted", f.weighted}};
}

}  // namespace demcal::dem
