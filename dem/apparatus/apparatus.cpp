#include "dem/apparatus/apparatus.hpp"

#include "dem/apparatus/granular_material.hpp"
#include "io/observable_registry.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace demcal::dem::protocol {

bool settle(Simulation& sim, const RunProtocol& p, double max_s, const StepObserver& observe,
            std::string_view phase, nlohmann::json& details) {
  const double start = sim.time_s();
  double next_check = start + p.check_interval_s;
  bool rested = false;
  while (sim.time_s() - start < max_s) {
    sim.step();
    if (observe) observe(sim, phase);
    if (sim.time_s() >= next_check) {
      next_check += p.check_interval_s;
      if (sim.insertion_finished() && sim.rms_speed_m_s() < p.rest_speed_m_s) {
        rested = true;
        break;
      }
    }
  }
  details["phases"].push_back({{"phase", phase},
                               {"start_s", start},
                               {"end_s", sim.time_s()},
                               {"at_rest", rested},
                               {"rms_speed_m_s", sim.rms_speed_m_s()}});
  return rested;
}

SimulationOptions options_for(const GranularMaterial& m, const RunProtocol& p, const Vec3& lower_m,
                              const Vec3& upper_m, std::array<bool, 3> periodic) {
  SimulationOptions o;
  o.domain.lower_m = lower_m;
  o.domain.upper_m = upper_m;
  o.domain.periodic = periodic;
  o.gravity_m_s2 = {0.0, 0.0, -9.81};
  o.contact = m.contact;
  o.restitution_model = m.restitution_model;
  o.time_step_fraction_of_rayleigh = p.time_step_fraction_of_rayleigh;
  o.seed = p.seed;
  o.threads = p.threads;
  o.particle_order = p.particle_order;
  return o;
}

std::vector<std::string> observables_not_measured_by(std::string_view apparatus_kind,
                                                     const nlohmann::json& observables) {
  std::vector<std::string> wrong;
  for (const auto& [name, value] : observables.items())
    if (!io::measures(apparatus_kind, name)) wrong.push_back(name);
  return wrong;
}

void require_positive(const char* apparatus, double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream s;
    s << apparatus << ": " << name << " must be a positive number (got " << value << ")";
    throw std::invalid_argument(s.str());
  }
}

double check_particle_count(const char* apparatus, double fill_mass_kg,
                            const SizeDistribution& sizes, double density_kg_m3,
                            const RunProtocol& p) {
  const double grain_kg = mean_grain_mass_kg(sizes, density_kg_m3);
  const double grains = fill_mass_kg / grain_kg;
  if (!(grains <= p.max_particles)) {
    std::ostringstream s;
    s.precision(3);
    s << apparatus << ": the fill of " << fill_mass_kg << " kg is about " << grains << " grains of "
      << grain_kg
      << " kg (the mean grain as simulated), more than protocol.max_particles = " << p.max_particles
      << " allows; coarse-grain it (coarse_graining_factor), take a periodic slice, lower "
         "fill_mass_kg, "
         "or raise protocol.max_particles";
    throw std::invalid_argument(s.str());
  }
  return grains;
}

double particle_cap_kg(const SizeDistribution& sizes, double density_kg_m3, const RunProtocol& p) {
  return (p.max_particles + 1.0) * mean_grain_mass_kg(sizes, density_kg_m3);
}

double total_mass_kg(const Particles& particles) {
  double m = 0.0;
  for (double mi : particles.mass_kg) m += mi;
  return m;
}

}  // namespace demcal::dem::protocol
