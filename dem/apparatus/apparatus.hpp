#pragma once
// A laboratory test reproduced in the DEM: it builds its simulation from named
// dimensions, runs its own protocol (fill, settle, release, come to rest) and
// measures what the laboratory measures. Each apparatus ends its run by itself
// once the event is over and the bed is at rest, never after a fixed long time.

#include "dem/apparatus/granular_material.hpp"
#include "dem/simulation.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace demcal::dem {

// How an apparatus run is driven; the same for every apparatus.
struct RunProtocol {
  std::uint64_t seed = 1;
  int threads = 1;
  double time_step_fraction_of_rayleigh = 0.2;
  // "At rest": rms translational speed below this, checked every check_interval_s.
  double rest_speed_m_s = 5e-3;
  double check_interval_s = 0.01;
  // Caps on each phase, in simulated seconds: reaching one is reported, not hidden.
  double max_settle_s = 2.0;
  double max_flow_s = 60.0;
  // m(t) sampling and the stall rule: the flow has stopped when no mass passed
  // the orifice for stall_time_s.
  double sample_interval_s = 0.005;
  double stall_time_s = 0.1;
  // A run whose fill is estimated at more grains than this is refused before
  // anything is built: at ~1 kB a grain and ~1e7 grain-steps a second, 1e6
  // grains is a gigabyte and a tenth of a second a step, days for a run.
  // Larger runs are meant for coarse graining, a slice, or a distributed engine.
  double max_particles = 1e6;
  // How the engine stores particles (dem/particle_order.hpp): spatial order
  // changes the summation order, so results differ bit-wise from insertion order.
  ParticleOrder particle_order = ParticleOrder::kInsertion;
};

// Called after every step with the phase name ("fill", "settle", "discharge", ...);
// snapshots and progress lines hang here.
using StepObserver = std::function<void(const Simulation&, std::string_view phase)>;

struct ApparatusResult {
  nlohmann::json observables = nlohmann::json::object();  // stable names, SI units
  nlohmann::json series = nlohmann::json::object();       // m(t), surface profile, ...
  nlohmann::json details = nlohmann::json::object();      // phases, counts, rules used
};

class Apparatus {
 public:
  virtual ~Apparatus() = default;
  virtual std::string name() const = 0;
  virtual const Simulation& simulation() const = 0;
  // Runs the whole protocol. Throws (InstabilityError, runtime_error) when the
  // run fails; a clogged orifice is a result, not an error.
  virtual ApparatusResult run(const StepObserver& observe) = 0;
};

// Shared protocol steps.
namespace protocol {

// Steps until the rms speed is below rest_speed_m_s (and every inserter is
// done), or for at most max_s. Returns whether it came to rest; records the
// phase in `details`.
bool settle(Simulation& sim, const RunProtocol& p, double max_s, const StepObserver& observe,
            std::string_view phase, nlohmann::json& details);

// Simulation options for an apparatus: box, gravity -z, contact law, time step.
SimulationOptions options_for(const GranularMaterial& m, const RunProtocol& p, const Vec3& lower_m,
                              const Vec3& upper_m, std::array<bool, 3> periodic);

double total_mass_kg(const Particles& particles);

// Throws std::invalid_argument "<apparatus>: <name> must be a positive number (got v)"
// unless value is finite and > 0: the check every apparatus dimension needs.
void require_positive(const char* apparatus, double value, const char* name);

// The number of grains a fill of fill_mass_kg takes (the mass over the mean
// grain's, for the sizes as simulated, coarse graining included); throws
// std::invalid_argument naming the apparatus, the estimate and what to change
// when it exceeds p.max_particles.
double check_particle_count(const char* apparatus, double fill_mass_kg,
                            const SizeDistribution& sizes, double density_kg_m3,
                            const RunProtocol& p);

// The names of an ApparatusResult's `observables` that io/observable_registry.hpp does
// not declare measured by `apparatus_kind` ("sandglass", "conical_pile",
// "rectangular_container"): empty for every apparatus and engine measurement (the
// tests hold them to it), so that no run writes a name a reader does not know.
std::vector<std::string> observables_not_measured_by(std::string_view apparatus_kind,
                                                     const nlohmann::json& observables);

// The mass of p.max_particles + 1 mean grains: a capacity count need go no
// further, since a fill beyond it is refused anyway.
double particle_cap_kg(const SizeDistribution& sizes, double density_kg_m3, const RunProtocol& p);

}  // namespace protocol
}  // namespace demcal::dem
