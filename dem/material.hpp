#pragma once
// A material (a "species" in DEM parlance): what a particle or a wall is made of.
// Walls are materials too, so particle–wall contacts get their own coefficients.

#include <string>

namespace demcal::dem {

struct Material {
  std::string name;
  double density_kg_m3 = 2650.0;
  // Give either Young's modulus or the shear modulus; the other follows from
  // the Poisson ratio (isotropic elasticity). Zero means "not given".
  double youngs_modulus_pa = 0.0;
  double shear_modulus_pa = 0.0;
  double poisson_ratio = 0.3;

  double youngs_modulus() const;
  double shear_modulus() const;
  // Throws std::invalid_argument naming the field when a value is out of its
  // physical range or when neither modulus (or both, inconsistently) is given.
  void validate() const;
};

// Rayleigh time of a sphere of this material: the period of the Rayleigh
// surface wave across it, the usual yardstick for a stable DEM time step.
double rayleigh_time_s(const Material& m, double radius_m);

}  // namespace demcal::dem
