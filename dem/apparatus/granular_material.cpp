#include "dem/apparatus/granular_material.hpp"

#include "dem/insertion/inserter.hpp"
#include "dem/simulation.hpp"

#include <numbers>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace demcal::dem {
namespace {

class ScaledSizes final : public SizeDistribution {
 public:
  ScaledSizes(std::shared_ptr<const SizeDistribution> base, double factor)
      : base_(std::move(base)), factor_(factor) {}
  double sample_diameter_m(Random& rng) const override {
    return factor_ * base_->sample_diameter_m(rng);
  }
  double min_diameter_m() const override { return factor_ * base_->min_diameter_m(); }
  double max_diameter_m() const override { return factor_ * base_->max_diameter_m(); }
  double mean_diameter_cubed_m3() const override {
    return factor_ * factor_ * factor_ * base_->mean_diameter_cubed_m3();
  }
  std::string describe() const override {
    if (factor_ == 1.0) return base_->describe();
    std::ostringstream s;
    s << base_->describe() << " x " << factor_ << " (coarse-grained)";
    return s.str();
  }

 private:
  std::shared_ptr<const SizeDistribution> base_;
  double factor_;
};

}  // namespace

std::unique_ptr<SizeDistribution> scaled_sizes(std::shared_ptr<const SizeDistribution> base,
                                               double factor) {
  if (!base) throw std::invalid_argument("scaled_sizes: no size distribution");
  if (!(factor > 0.0) || !std::isfinite(factor))
    throw std::invalid_argument("coarse_graining_factor must be a positive number");
  return std::make_unique<ScaledSizes>(std::move(base), factor);
}

double mean_diameter_m(const SizeDistribution& sizes) {
  return std::cbrt(sizes.mean_diameter_cubed_m3());
}

double mean_grain_mass_kg(const SizeDistribution& sizes, double density_kg_m3) {
  return density_kg_m3 * std::numbers::pi / 6.0 * sizes.mean_diameter_cubed_m3();
}

double lattice_capacity_kg(const Region& region, const SizeDistribution& sizes,
                           double density_kg_m3, const Domain& domain, double lattice_gap,
                           double needed_kg) {
  const double grain_kg = mean_grain_mass_kg(sizes, density_kg_m3);
  std::size_t sites = 0;
  for_each_lattice_site(region, sizes.max_diameter_m(), lattice_gap, domain, [&](const Vec3&) {
    ++sites;
    return !(static_cast<double>(sites) * grain_kg > needed_kg);
  });
  return static_cast<double>(sites) * grain_kg;
}

int InstalledMaterials::wall_for(const std::string& group) const {
  const auto it = wall_by_group.find(group);
  return it == wall_by_group.end() ? wall : it->second;
}

InstalledMaterials install_materials(Simulation& sim, const GranularMaterial& m,
                                     const ModelReduction& reduction,
                                     const std::vector<std::string>& wall_groups) {
  Material particle = m.particle;
  if (reduction.shear_modulus_pa > 0.0) {
    particle.shear_modulus_pa = reduction.shear_modulus_pa;
    particle.youngs_modulus_pa = 0.0;
  }
  InstalledMaterials installed;
  installed.particle = sim.add_material(particle);
  installed.wall = sim.add_material(m.wall);
  // Each contact part's parameters scale as the part declares, so that a parcel
  // of factor f keeps the dimensionless group of the grains it stands for (JKR:
  // pull-off 3 pi gamma R* over weight goes as gamma / R^2, so gamma f^2).
  const double f = reduction.coarse_graining_factor;
  const auto reduced = [f](InteractionParameters params) {
    for (const RegisteredPartParameter& r : registered_part_parameters())
      if (r.parameter.coarse_graining_exponent != 0.0)
        r.parameter.value_in(params) = r.parameter.coarse_grained(r.parameter.value_in(params), f);
    return params;
  };
  sim.set_interaction(installed.particle, installed.particle, reduced(m.particle_particle));
  sim.set_interaction(installed.particle, installed.wall, reduced(m.particle_wall));
  for (const std::string& group : wall_groups) {
    const auto own = m.particle_wall_by_group.find(group);
    if (own == m.particle_wall_by_group.end()) continue;
    Material wall = m.wall;
    wall.name += " (" + group + ")";  // a material's name is unique in a simulation
    const int w = sim.add_material(wall);
    sim.set_interaction(installed.particle, w, reduced(own->second));
    installed.wall_by_group.emplace(group, w);
  }
  if (m.air_drag) sim.add_body_force(std::make_unique<AirDrag>(*m.air_drag, f));
  return installed;
}

}  // namespace demcal::dem
