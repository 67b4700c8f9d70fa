#pragma once
// Beverloo's law for the mass flow rate out of an orifice of size D0:
//   circular hole of diameter D0:         W = C rho_bulk sqrt(g) (D0 - k d)^2.5
//   slot of width D0 and length L (the orifice of a periodic slice):
//                                         W = C rho_bulk sqrt(g) L (D0 - k d)^1.5
// with d the particle diameter; C ~ 0.55-0.65 and k ~ 1.4-1.5 for spheres.
// The fit linearises the law: y = (W / L_or_1)^(1/p), p = 2.5 or 1.5, is a
// straight line in D0 with slope s = (C rho_bulk sqrt g)^(1/p) and intercept
// -s k d, so a (weighted) straight-line fit gives C and k without an iterative
// solver.

#include "dem/wall/orifice_plate_wall.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <limits>
#include <vector>

namespace demcal::dem {

// What stays the same across the orifice sizes of one series.
struct BeverlooSetup {
  OrificeShape shape = OrificeShape::circle;
  double bulk_density_kg_m3 = 0.0;
  double gravity_m_s2 = 9.81;
  double particle_diameter_m = 0.0;
  double slot_length_m = 0.0;  // slot only: the length L of the slot
};

// Forward law. Throws std::invalid_argument naming the argument when the setup
// is invalid, c <= 0, or orifice_m <= k d (no flow predicted).
double beverloo_flow_rate_kg_s(const BeverlooSetup& setup, double orifice_m, double c, double k);

struct BeverlooFit {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double c = kNaN;
  double c_std_error = kNaN;
  double k = kNaN;
  double k_std_error = kNaN;
  double c_k_correlation = kNaN;
  // The line y = slope D0 + intercept, y = W^(1/2.5) (circle) or (W/L)^(1/1.5) (slot).
  double slope = kNaN;
  double intercept = kNaN;
  // Measured minus fitted flow rate, per point, in kg/s (the fitted rate is 0
  // where the fitted law predicts no flow).
  std::vector<double> residuals_kg_s;
  // Weighted sum of squared residuals of the line over (points - 2); NaN
  // unless errors were given and there are >= 3 points. Near 1 when the
  // scatter matches the stated errors.
  double reduced_chi_squared = kNaN;
  std::size_t points = 0;
  bool weighted = false;
};

// Fits C and k. flow_rate_std_error_kg_s is empty (unweighted fit, errors from
// the scatter) or one positive error per point (weights 1/sigma_y^2 with
// sigma_y propagated through the linearisation; the parameter errors are
// scaled up by sqrt(reduced chi^2) when the scatter exceeds the stated errors,
// never down). Needs >= 2 points at >= 2 distinct sizes; with exactly 2 the
// line is exact and the errors are NaN. Standard errors of C and k by the
// delta method. Throws std::invalid_argument naming the offending argument.
BeverlooFit fit_beverloo(const BeverlooSetup& setup, const std::vector<double>& orifice_m,
                         const std::vector<double>& flow_rate_kg_s,
                         const std::vector<double>& flow_rate_std_error_kg_s = {});

nlohmann::json to_json(const BeverlooFit& fit);

}  // namespace demcal::dem
