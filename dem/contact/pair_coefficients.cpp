#include "dem/contact/pair_coefficients.hpp"

#include "dem/contact/contact_law.hpp"
#include "dem/contact/restitution_damping.hpp"

#include <cmath>
#include <stdexcept>

namespace demcal::dem {

void InteractionParameters::validate(const std::string& where) const {
  auto fail = [&](const std::string& what) { throw std::invalid_argument(where + what); };
  if (!(restitution > 0.0 && restitution <= 1.0))
    fail("restitution must lie in (0, 1]");
  if (!(sliding_friction >= 0.0) || !std::isfinite(sliding_friction))
    fail("sliding_friction must be >= 0");
  if (!(rolling_friction >= 0.0) || !std::isfinite(rolling_friction))
    fail("rolling_friction must be >= 0");
  if (!(rolling_stiffness_factor > 0.0)) fail("rolling_stiffness_factor must be > 0");
  if (!(rolling_damping_ratio >= 0.0)) fail("rolling_damping_ratio must be >= 0");
  if (!(surface_energy_j_m2 >= 0.0) || !std::isfinite(surface_energy_j_m2))
    fail("surface_energy_j_m2 must be >= 0");
  for (const RegisteredPartParameter& r : registered_part_parameters()) {
    if (r.parameter.legacy_field != nullptr) continue;  // checked above, with its own words
    if (!r.parameter.accepts(r.parameter.value_in(*this)))
      fail(std::string(r.parameter.key) + " is outside its range " +
           part_parameter_range_text(r.parameter));
  }
}

PairCoefficients resolve_pair(const Material& a, const Material& b,
                              const InteractionParameters& p, RestitutionModel model) {
  PairCoefficients c;
  const double ea = a.youngs_modulus(), eb = b.youngs_modulus();
  const double ga = a.shear_modulus(), gb = b.shear_modulus();
  const double na = a.poisson_ratio, nb = b.poisson_ratio;
  c.youngs_modulus_eff_pa = 1.0 / ((1.0 - na * na) / ea + (1.0 - nb * nb) / eb);
  c.shear_modulus_eff_pa = 1.0 / ((2.0 - na) / ga + (2.0 - nb) / gb);
  c.damping_beta = model == RestitutionModel::kExact ? damping_beta_for_restitution(p.restitution)
                                                     : linear_spring_damping_beta(p.restitution);
  c.sliding_friction = p.sliding_friction;
  c.rolling_friction = p.rolling_friction;
  c.rolling_stiffness_factor = p.rolling_stiffness_factor;
  c.rolling_damping_ratio = p.rolling_damping_ratio;
  c.surface_energy_j_m2 = p.surface_energy_j_m2;
  c.part_values = p.part_values;
  return c;
}

}  // namespace demcal::dem
