#include "dem/apparatus/poured_slab_pile.hpp"

#include "dem/apparatus/apparatus.hpp"

#include "dem/insertion/inserter.hpp"
#include "dem/insertion/region.hpp"
#include "dem/size_distribution.hpp"
#include "dem/wall/plane_wall.hpp"

#include <stdexcept>

namespace demcal::dem {

std::unique_ptr<Simulation> make_poured_slab_pile(const PouredSlabPileOptions& o) {
  const double d = o.diameter_m;
  const double slab = o.slab_thickness_diameters * d;
  const double half = 0.5 * o.box_length_m;
  SimulationOptions so;
  so.domain.lower_m = {-half, 0.0, -0.001};
  so.domain.upper_m = {half, slab, o.box_height_m};
  so.domain.periodic = {false, true, false};
  so.contact.rolling = o.rolling_model;
  so.time_step_s = o.time_step_s;
  so.seed = o.seed;
  so.threads = o.threads;
  so.particle_order = o.particle_order;
  so.worker_parking = o.worker_parking;
  so.worker_parking_options = o.worker_parking_options;
  auto sim = std::make_unique<Simulation>(so);

  Material grain;
  grain.name = "grain";
  grain.density_kg_m3 = o.density_kg_m3;
  grain.youngs_modulus_pa = o.youngs_modulus_pa;
  grain.poisson_ratio = o.poisson_ratio;
  Material wall = grain;
  wall.name = "wall";
  const int g = sim->add_material(grain);
  const int w = sim->add_material(wall);
  InteractionParameters pp;
  pp.restitution = o.restitution;
  pp.sliding_friction = o.sliding_friction;
  pp.rolling_friction = o.rolling_friction;
  InteractionParameters pw = pp;
  pw.sliding_friction = o.wall_sliding_friction;
  pw.rolling_friction = o.wall_rolling_friction;
  sim->set_interaction(g, g, pp);
  sim->set_interaction(g, w, pw);

  sim->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), w);
  sim->add_wall(std::make_unique<PlaneWall>(Vec3{-half, 0, 0}, Vec3{1, 0, 0}), w);
  sim->add_wall(std::make_unique<PlaneWall>(Vec3{half, 0, 0}, Vec3{-1, 0, 0}), w);

  if (o.particles == 0) return sim;
  const double ix = o.inlet_half_width_diameters * d;
  PourOptions pour;
  pour.material = g;
  pour.density_kg_m3 = o.density_kg_m3;
  pour.amount.count = o.particles;
  pour.velocity_m_s = {0, 0, -o.inlet_speed_m_s};
  pour.batch_volume_fraction = o.batch_volume_fraction;
  pour.gravity_m_s2 = so.gravity_m_s2;
  sim->add_inserter(
      make_pour_inserter(make_box_region({-ix, 0.0, o.inlet_bottom_m}, {ix, slab, o.inlet_top_m}),
                         make_monodisperse(d), pour));
  return sim;
}

std::unique_ptr<Simulation> copy_across_slab(const PouredSlabPileOptions& o,
                                             const Particles& grains, int copies) {
  if (copies < 1) throw std::invalid_argument("copy_across_slab needs at least one copy");
  PouredSlabPileOptions box = o;
  box.particles = 0;
  box.slab_thickness_diameters = o.slab_thickness_diameters * copies;
  auto sim = make_poured_slab_pile(box);
  const int grain = sim->material_index("grain");
  const double slab_m = o.slab_thickness_diameters * o.diameter_m;
  for (int k = 0; k < copies; ++k)
    for (std::size_t i = 0; i < grains.size(); ++i)
      sim->add_particle(grains.position_m[i] + Vec3{0.0, k * slab_m, 0.0}, grains.radius_m[i],
                        grain, grains.velocity_m_s[i]);
  return sim;
}

bool run_until_at_rest(Simulation& sim, double rest_speed_m_s, double max_time_s,
                       double check_interval_s) {
  RunProtocol p;
  p.rest_speed_m_s = rest_speed_m_s;
  p.check_interval_s = check_interval_s;
  nlohmann::json details;
  return protocol::settle(sim, p, max_time_s - sim.time_s(), nullptr, "pour", details);
}

}  // namespace demcal::dem
