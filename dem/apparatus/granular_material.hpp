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

#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace demcal::dem {

class Simulation;

struct GranularMaterial {
  Material particle;
  Material wall;
  InteractionParameters particle_particle;
  InteractionParameters particle_wall;
  // Walls of a named group that touch the grains with an interaction of their
  // own instead of particle_wall: a hopper lined with the sand itself above a
  // bare floor, say. Each apparatus names its groups (wall_group_names());
  // groups an apparatus does not have are not used by it.
  std::map<std::string, InteractionParameters> particle_wall_by_group;
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

// Mass of the mean grain, density pi/6 (mean d^3): what a fill mass is divided by
// to count grains (the grain caps, the lattice's capacity).
double mean_grain_mass_kg(const SizeDistribution& sizes, double density_kg_m3);

// Mass a lattice fill of `region` takes (its sites times the mean particle
// mass), for a lattice spaced (1 + lattice_gap) largest diameters. Counting
// stops once the capacity exceeds needed_kg: whether a region holds a fill is
// then known in time proportional to the fill, however large the region (the
// answer is exact whenever it is below needed_kg).
double lattice_capacity_kg(const Region& region, const SizeDistribution& sizes,
                           double density_kg_m3, const Domain& domain,
                           double lattice_gap = FillOptions{}.lattice_gap,
                           double needed_kg = std::numeric_limits<double>::infinity());

// The material indices an apparatus builds its particles and walls with.
struct InstalledMaterials {
  int particle = -1;
  int wall = -1;  // the walls that follow particle_wall
  // One more wall material for each of the apparatus' groups that has an
  // interaction of its own (the same wall material, another interaction).
  std::map<std::string, int> wall_by_group;

  // The material of the walls of `group`: its own when it has one, else `wall`.
  int wall_for(const std::string& group) const;
};

// Adds both materials and the interactions, with the reduction applied (the
// modulus, the surface energy scaled for coarse graining), and the air drag
// when the material has it. `wall_groups` are the apparatus' group names:
// each that has an entry in particle_wall_by_group gets a wall material of
// its own. Without such entries the indices and interactions are the ones a
// material without groups always had, so runs stay bit-identical.
InstalledMaterials install_materials(Simulation& sim, const GranularMaterial& material,
                                     const ModelReduction& reduction,
                                     const std::vector<std::string>& wall_groups = {});

}  // namespace demcal::dem
