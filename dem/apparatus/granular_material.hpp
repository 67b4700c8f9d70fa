#pragma once
// The granular material an apparatus is filled with, and the wall material it
// is built of: what a study calibrates. Sizes are drawn by number.

#include "dem/air_drag.hpp"
#include "dem/contact/contact_law.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/domain.hpp"
#include "dem/insertion/inserter.hpp"
#include "dem/insertion/region.hpp"
#include "dem/material.hpp"
#include "dem/size_distribution.hpp"

#include <memory>
#include <optional>

namespace demcal::dem {

class Simulation;

struct GranularMaterial {
  Material particle;
  Material wall;
  InteractionParameters particle_particle;
  InteractionParameters particle_wall;
  ContactLawSpec contact;
  std::shared_ptr<const SizeDistribution> sizes;
  RestitutionModel restitution_model = RestitutionModel::kExact;
  // The still air the grains fall through, when its drag is modelled (dem/air_drag.hpp).
  std::optional<AirProperties> air_drag;
};

// The model reductions a design of experiments can afford, each a stated
// approximation (justified per study):
//  - a periodic slice instead of the whole apparatus (Derakhshani et al.: with
//    periodic boundaries the pile in the median plane stops feeling the
//    thickness at 4 particle diameters);
//  - coarse graining: every particle scaled by a factor f, geometry kept; the
//    surface energy is scaled by f^2, which keeps the grains' Bond number
//    (pull-off 3 pi gamma R* over weight), and the air drag of a parcel is
//    that of its f^3 grains (so it falls at their terminal velocity);
//  - a reduced shear modulus (AoR does not change once G is above ~1e7 Pa).
struct ModelReduction {
  bool slice = false;
  double slice_thickness_diameters = 4.0;
  double coarse_graining_factor = 1.0;
  double shear_modulus_pa = 0.0;  // 0: keep the material's modulus
};

// A size distribution scaled by a factor, sharing the original.
std::unique_ptr<SizeDistribution> scaled_sizes(std::shared_ptr<const SizeDistribution> base,
                                               double factor);

// Volume-equivalent mean diameter, (mean d^3)^(1/3): the "d" in "4 d" and in Beverloo's law.
double mean_diameter_m(const SizeDistribution& sizes);

// Mass a lattice fill of `region` takes (its sites times the mean particle
// mass), for a lattice spaced (1 + lattice_gap) largest diameters.
double lattice_capacity_kg(const Region& region, const SizeDistribution& sizes,
                           double density_kg_m3, const Domain& domain,
                           double lattice_gap = FillOptions{}.lattice_gap);

// Adds both materials and both interactions, with the reduction applied (the
// modulus, the surface energy scaled for coarse graining), and the air drag
// when the material has it; returns {particle material index, wall material index}.
std::pair<int, int> install_materials(Simulation& sim, const GranularMaterial& material,
                                      const ModelReduction& reduction);

}  // namespace demcal::dem
