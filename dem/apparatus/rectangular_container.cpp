#include "dem/apparatus/rectangular_container.hpp"

#include "dem/insertion/inserter.hpp"
#include "dem/measure/angle_of_repose.hpp"
#include "dem/wall/plane_wall.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace demcal::dem {

void RectangularContainerOptions::validate() const {
  protocol::require_positive("rectangular_container", width_m, "width_m");
  protocol::require_positive("rectangular_container", height_m, "height_m");
  protocol::require_positive("rectangular_container", fill_mass_kg, "fill_mass_kg");
  protocol::require_positive("rectangular_container", inlet_speed_m_s, "inlet_speed_m_s");
  if ((thickness_m > 0.0) == (thickness_diameters > 0.0))
    throw std::invalid_argument(
        "rectangular_container: give exactly one of thickness_m and thickness_diameters (> 0)");
  if (boundary != "walls" && boundary != "periodic")
    throw std::invalid_argument(
        "rectangular_container: boundary must be \"walls\" or \"periodic\", not \"" + boundary +
        "\"");
  if (inlet_height_m < 0.0 || inlet_height_m >= height_m)
    throw std::invalid_argument("rectangular_container: inlet_height_m must lie in [0, height_m)");
}

RectangularContainer::RectangularContainer(const RectangularContainerOptions& options,
                                           const GranularMaterial& material,
                                           const RunProtocol& protocol)
    : o_(options), protocol_(protocol) {
  o_.validate();
  if (!material.sizes)
    throw std::invalid_argument("rectangular_container: the material has no size distribution");
  auto sizes = scaled_sizes(material.sizes, o_.reduction.coarse_graining_factor);
  diameter_m_ = mean_diameter_m(*sizes);
  const double d_max = sizes->max_diameter_m();
  thickness_m_ = o_.thickness_m > 0.0 ? o_.thickness_m : o_.thickness_diameters * diameter_m_;
  const bool periodic = o_.boundary == "periodic";
  if (thickness_m_ < (periodic ? 2.7 : 1.1) * d_max) {
    std::ostringstream s;
    s << "rectangular_container: the thickness (" << thickness_m_
      << " m) is too thin for particles of " << d_max << " m"
      << (periodic ? " with a periodic boundary (at least 2.7 diameters)" : "");
    throw std::invalid_argument(s.str());
  }
  protocol::check_particle_count("rectangular_container", o_.fill_mass_kg, *sizes,
                                 material.particle.density_kg_m3, protocol);
  const double half = 0.5 * o_.width_m;
  const double inlet_half = 0.5 * (o_.inlet_width_m > 0.0 ? o_.inlet_width_m : 8.0 * diameter_m_);
  const double inlet_z = o_.inlet_height_m > 0.0 ? o_.inlet_height_m : 0.8 * o_.height_m;
  const double inlet_top = std::min(o_.height_m, inlet_z + 5.0 * diameter_m_);
  if (inlet_half >= half)
    throw std::invalid_argument("rectangular_container: the inlet is wider than the container");

  // A heap of this mass must fit the width even at a low 20 degrees, or it
  // would bank against the side walls and the angle would be the walls'.
  const double area = o_.fill_mass_kg / (0.6 * material.particle.density_kg_m3 * thickness_m_);
  const double base_half_width = std::sqrt(area / std::tan(20.0 * std::numbers::pi / 180.0));
  if (base_half_width > 0.9 * half) {
    std::ostringstream s;
    s << "rectangular_container: fill_mass_kg = " << o_.fill_mass_kg << " kg forms a heap about "
      << 2.0 * base_half_width << " m wide, more than the container's width_m = " << o_.width_m
      << " m allows; lower fill_mass_kg or widen the container";
    throw std::invalid_argument(s.str());
  }

  const double m = 3.0 * d_max;
  sim_ = std::make_unique<Simulation>(protocol::options_for(
      material, protocol, {-half - m, 0.0 - (periodic ? 0.0 : m), -m},
      {half + m, thickness_m_ + (periodic ? 0.0 : m), o_.height_m + m}, {false, periodic, false}));
  const InstalledMaterials mat =
      install_materials(*sim_, material, o_.reduction, wall_group_names());
  const int p = mat.particle;
  const int ends = mat.wall_for("end_walls"), sides = mat.wall_for("side_walls");
  sim_->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), mat.wall_for("floor"));
  sim_->add_wall(std::make_unique<PlaneWall>(Vec3{-half, 0, 0}, Vec3{1, 0, 0}), ends);
  sim_->add_wall(std::make_unique<PlaneWall>(Vec3{half, 0, 0}, Vec3{-1, 0, 0}), ends);
  if (!periodic) {
    sim_->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 1, 0}), sides);
    sim_->add_wall(std::make_unique<PlaneWall>(Vec3{0, thickness_m_, 0}, Vec3{0, -1, 0}), sides);
  }
  PourOptions pour;
  pour.material = p;
  pour.density_kg_m3 = material.particle.density_kg_m3;
  pour.amount.mass_kg = o_.fill_mass_kg;
  pour.velocity_m_s = {0, 0, -o_.inlet_speed_m_s};
  pour.gravity_m_s2 = {0, 0, -9.81};
  sim_->add_inserter(make_pour_inserter(
      make_box_region({-inlet_half, 0.0, inlet_z}, {inlet_half, thickness_m_, inlet_top}),
      std::move(sizes), pour));
}

ApparatusResult RectangularContainer::run(const StepObserver& observe) {
  ApparatusResult r;
  Simulation& sim = *sim_;
  r.details["apparatus"] = name();
  r.details["boundary"] = o_.boundary;
  r.details["thickness_m"] = thickness_m_;
  r.details["thickness_diameters"] = thickness_m_ / diameter_m_;
  r.details["particle_diameter_m"] = diameter_m_;
  r.details["release"] = "poured from a narrow inlet above the centre, as the paper describes";
  r.details["pile_settled"] =
      protocol::settle(sim, protocol_, protocol_.max_flow_s, observe, "pour", r.details);
  r.details["particles"] = sim.particles().size();
  const auto& pp = sim.particles();
  const double band = o_.median_band_diameters * diameter_m_;
  const bool all = thickness_m_ < 2.0 * band;
  std::vector<Vec3> pos;
  std::vector<double> rad;
  for (std::size_t i = 0; i < pp.size(); ++i)
    if (all || std::abs(pp.position_m[i].y - 0.5 * thickness_m_) < band) {
      pos.push_back(pp.position_m[i]);
      rad.push_back(pp.radius_m[i]);
    }
  r.details["median_plane_rule"] = all ? "all particles (the container is thinner than the band)"
                                       : "particles within " +
                                             std::to_string(o_.median_band_diameters) +
                                             " diameters of the median plane";
  try {
    SliceAoROptions a;
    a.long_axis = 0;
    r.series["pile"] = to_json(measure_slice_angle_of_repose(pos, rad, a));
    r.observables["angle_of_repose_deg"] = r.series["pile"]["angle_of_repose_deg"];
    r.observables["angle_of_repose_uncertainty_deg"] =
        r.series["pile"]["angle_of_repose_uncertainty_deg"];
  } catch (const std::runtime_error& e) {
    r.observables["angle_of_repose_deg"] = nullptr;
    r.details["angle_of_repose_error"] = e.what();
  }
  return r;
}

}  // namespace demcal::dem
