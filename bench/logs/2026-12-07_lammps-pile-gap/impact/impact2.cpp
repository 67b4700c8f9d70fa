// Experiment (not committed): one grain's oblique impact on the floor, demcal side.
#include "dem/simulation.hpp"
#include "dem/wall/plane_wall.hpp"
#include <cstdio>
#include <cstdlib>
#include <memory>
using namespace demcal::dem;
int main(int argc, char** argv) {
  const double vx0 = std::atof(argv[1]), vz0 = std::atof(argv[2]);
  const double wy0 = argc > 3 ? std::atof(argv[3]) : 0.0;
  const double R = 0.5e-3;
  SimulationOptions o;
  o.domain.lower_m = {-0.5, -0.05, -0.001};
  o.domain.upper_m = {0.5, 0.05, 0.05};
  o.gravity_m_s2 = {0, 0, 0};
  o.contact.rolling = "epsd"; o.restitution_model = RestitutionModel::kLinearSpringFormula;
  o.time_step_s = argc > 4 ? std::atof(argv[4]) : 1.0034561847539284e-05;
  Simulation sim(o);
  Material sand; sand.name = "sand"; sand.density_kg_m3 = 2650; sand.youngs_modulus_pa = 1e7; sand.poisson_ratio = 0.3;
  Material glass; glass.name = "glass"; glass.density_kg_m3 = 2650; glass.youngs_modulus_pa = 1e7; glass.poisson_ratio = 0.3;
  const int s = sim.add_material(sand), g = sim.add_material(glass);
  InteractionParameters pp; pp.restitution = 0.6; pp.sliding_friction = 0.5; pp.rolling_friction = 0.1; pp.rolling_stiffness_factor = 1.5;
  InteractionParameters pw = pp; pw.sliding_friction = 0.9; pw.rolling_friction = 0.3; if (argc > 5) pp.rolling_friction = std::atof(argv[5]); if (argc > 6) { pw.rolling_damping_ratio = std::atof(argv[6]); pp.rolling_damping_ratio = pw.rolling_damping_ratio; }
  sim.set_interaction(s, s, pp); sim.set_interaction(s, g, pw); sim.set_interaction(g, g, pw);
  sim.add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), g);
  sim.add_particle({0, 0, 0.01 + 2 * R + 1e-6}, R, s, Vec3{vx0, 0, vz0}, Vec3{0, wy0, 0});
  sim.add_particle({0, 0, 0.01}, R, s, Vec3{0, 0, 0}, Vec3{0, 0, 0});
  const double t_out[] = {0.5e-3, 1e-3, 2e-3};
  for (double t : t_out) {
    sim.run_until(t);
    const auto& p = sim.particles();
    for (std::size_t q = 0; q < 2; ++q) std::printf("t %.4g id %d vx %.6f vz %.6f wy %.4f\n", sim.time_s(), (int)p.id[q],
                p.velocity_m_s[q].x, p.velocity_m_s[q].z, p.omega_rad_s[q].y);
  }

}
