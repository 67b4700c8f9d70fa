#pragma once
// Small builders shared by the physics tests: one material, one interaction,
// the engine's defaults everywhere else.

#include "dem/simulation.hpp"
#include "dem/wall/plane_wall.hpp"

#include <memory>

namespace demcal::dem::testing {

inline Material sand(double youngs_modulus_pa = 1e7) {
  Material m;
  m.name = "sand";
  m.density_kg_m3 = 2650.0;
  m.youngs_modulus_pa = youngs_modulus_pa;
  m.poisson_ratio = 0.3;
  return m;
}

inline InteractionParameters interaction(double restitution, double mu_s, double mu_r = 0.0) {
  InteractionParameters p;
  p.restitution = restitution;
  p.sliding_friction = mu_s;
  p.rolling_friction = mu_r;
  return p;
}

struct Scene {
  std::unique_ptr<Simulation> sim;
  int material = 0;
};

// One material "sand" meeting itself (and walls of the same material) with `params`.
inline Scene make_scene(SimulationOptions options, const InteractionParameters& params,
                        double youngs_modulus_pa = 1e7) {
  Scene s;
  s.sim = std::make_unique<Simulation>(std::move(options));
  s.material = s.sim->add_material(sand(youngs_modulus_pa));
  s.sim->set_interaction(s.material, s.material, params);
  return s;
}

inline SimulationOptions options_in_box(const Vec3& lo, const Vec3& hi, const Vec3& gravity) {
  SimulationOptions o;
  o.domain.lower_m = lo;
  o.domain.upper_m = hi;
  o.gravity_m_s2 = gravity;
  return o;
}

}  // namespace demcal::dem::testing
