#include "dem/apparatus/apparatus.hpp"

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
  return o;
}

void require_positive(const char* apparatus, double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream s;
    s << apparatus << ": " << name << " must be a positive number (got " << value << ")";
    throw std::invalid_argument(s.str());
  }
}

double total_mass_kg(const Particles& particles) {
  double m = 0.0;
  for (double mi : particles.mass_kg) m += mi;
  return m;
}

}  // namespace demcal::dem::protocol
