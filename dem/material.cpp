#include "dem/material.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace demcal::dem {

double Material::youngs_modulus() const {
  if (youngs_modulus_pa > 0.0) return youngs_modulus_pa;
  return 2.0 * shear_modulus_pa * (1.0 + poisson_ratio);
}

double Material::shear_modulus() const {
  if (shear_modulus_pa > 0.0) return shear_modulus_pa;
  return youngs_modulus_pa / (2.0 * (1.0 + poisson_ratio));
}

void Material::validate() const {
  const std::string where = "material '" + name + "': ";
  if (!(density_kg_m3 > 0.0) || !std::isfinite(density_kg_m3))
    throw std::invalid_argument(where + "density_kg_m3 must be a positive number");
  if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5))
    throw std::invalid_argument(where + "poisson_ratio must lie in (-1, 0.5)");
  if (youngs_modulus_pa <= 0.0 && shear_modulus_pa <= 0.0)
    throw std::invalid_argument(where +
                                "give youngs_modulus_pa or shear_modulus_pa (a positive number)");
  if (youngs_modulus_pa > 0.0 && shear_modulus_pa > 0.0) {
    const double implied = youngs_modulus_pa / (2.0 * (1.0 + poisson_ratio));
    if (std::abs(implied - shear_modulus_pa) > 1e-6 * implied)
      throw std::invalid_argument(where +
                                  "youngs_modulus_pa and shear_modulus_pa disagree with "
                                  "poisson_ratio; give only one of them");
  }
  if (!std::isfinite(youngs_modulus()))
    throw std::invalid_argument(where + "the elastic modulus is not finite");
}

double rayleigh_time_s(const Material& m, double radius_m) {
  const double nu = m.poisson_ratio;
  return std::numbers::pi * radius_m * std::sqrt(m.density_kg_m3 / m.shear_modulus()) /
         (0.1631 * nu + 0.8766);
}

}  // namespace demcal::dem
