#pragma once
// The DEM engine: particles, walls, a contact law, inserters and body forces,
// advanced by velocity Verlet. A Simulation is assembled (materials,
// interactions, walls, inserters, particles), then stepped. It knows nothing of
// files: configs are read and results written elsewhere.

#include "dem/body_force.hpp"
#include "dem/contact/contact_law.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/contact_batch.hpp"
#include "dem/domain.hpp"
#include "dem/insertion/inserter.hpp"
#include "dem/material.hpp"
#include "dem/neighbor_list.hpp"
#include "dem/particle_order.hpp"
#include "dem/particles.hpp"
#include "dem/random.hpp"
#include "dem/thread_team.hpp"
#include "dem/wall/wall.hpp"
#include "dem/wall_contact_batch.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace demcal::dem {

// Raised when the run goes unstable (NaN, runaway speed, a particle outside the
// box); the message says which particle, where, when, and what to change.
class InstabilityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SimulationOptions {
  Domain domain;
  Vec3 gravity_m_s2{0, 0, -9.81};
  ContactLawSpec contact;
  RestitutionModel restitution_model = RestitutionModel::kExact;
  // Time step: explicit when > 0, else this fraction of the smallest particle's
  // Rayleigh time. 0.2 is inside the 0.1–0.4 range commercial codes advise and
  // resolves a Hertz contact at impact speeds up to a few m/s with > 20 steps.
  double time_step_s = 0.0;
  double time_step_fraction_of_rayleigh = 0.2;
  // Verlet skin as a fraction of the largest diameter (0.3 d: rebuilds every ~10–50 steps in flows).
  double skin_fraction_of_diameter = 0.3;
  std::uint64_t seed = 1;
  int threads = 1;
  // Whether the thread team may park its workers when they slow it down, as on
  // a machine another process shares (dem/worker_parking.hpp). Results are the
  // same bit for bit whatever this is: it only moves chunks between threads.
  WorkerParking worker_parking = WorkerParking::kAdaptive;
  WorkerParkingOptions worker_parking_options;
  // Instability guard: a particle faster than this stops the run. 0 = derived
  // from the box: ten times the free-fall speed over its largest dimension.
  double max_speed_m_s = 0.0;
  // How particles are stored (dem/particle_order.hpp). With kSpatial they are
  // re-sorted at every neighbour build, so a particle's index changes during
  // the run: follow a particle by Particles::id, not by index.
  ParticleOrder particle_order = ParticleOrder::kInsertion;
};

// Net load the particles exert on one wall during the last step.
struct WallLoad {
  Vec3 force_n;
  Vec3 torque_nm;  // about the wall's reference point
  std::size_t contacts = 0;
};

struct EnergyBudget {
  double translational_j = 0.0;
  double rotational_j = 0.0;
  double potential_j = 0.0;  // of the body forces (gravity)
  double elastic_j = 0.0;    // stored in the contact springs at the last force evaluation
  double total_j() const { return translational_j + rotational_j + potential_j + elastic_j; }
};

class Simulation {
 public:
  explicit Simulation(SimulationOptions options);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // --- assembly ---
  int add_material(const Material& material);  // validates; returns its index
  int material_index(const std::string& name) const;  // throws if unknown
  // Coefficients for a pair of materials (symmetric). Every pair that can meet
  // must be given before the first step.
  void set_interaction(int material_a, int material_b, const InteractionParameters& params);
  int add_wall(std::unique_ptr<Wall> wall, int material);
  void add_inserter(std::unique_ptr<Inserter> inserter);
  void add_body_force(std::unique_ptr<BodyForce> force);
  std::size_t add_particle(const Vec3& position_m, double radius_m, int material,
                           const Vec3& velocity_m_s = {}, const Vec3& omega_rad_s = {});

  // --- running ---
  void step();
  void run_steps(std::int64_t steps);
  void run_until(double time_s);

  // --- state ---
  double time_s() const { return time_s_; }
  std::int64_t step_count() const { return steps_; }
  double time_step_s();  // resolves the step on first use
  // Indices are stable only with ParticleOrder::kInsertion; with kSpatial they
  // change at neighbour builds (ids do not).
  const Particles& particles() const { return particles_; }
  Particles& mutable_particles() { return particles_; }
  const std::vector<std::unique_ptr<Wall>>& walls() const { return walls_; }
  // For protocols that change a wall during the run (opening an orifice when
  // the fill has settled); call geometry_changed() afterwards.
  Wall& mutable_wall(std::size_t index) { return *walls_.at(index); }
  void geometry_changed() { rebuild_requested_ = true; }
  const std::vector<WallLoad>& wall_loads() const { return wall_loads_; }
  const std::vector<std::unique_ptr<Inserter>>& inserters() const { return inserters_; }
  bool insertion_finished() const;
  const SimulationOptions& options() const { return options_; }
  const std::vector<Material>& materials() const { return materials_; }
  // The material index wall `index` was added with.
  int wall_material(std::size_t index) const { return wall_material_.at(index); }
  // The interaction given for two materials, or nullptr when none was.
  const InteractionParameters* interaction(int material_a, int material_b) const {
    const std::size_t n = materials_.size();
    const auto& p = interactions_.at(static_cast<std::size_t>(material_a) * n + static_cast<std::size_t>(material_b));
    return p ? &*p : nullptr;
  }
  const ContactLaw& contact_law() const { return law_; }
  std::size_t neighbor_builds() const { return neighbors_.build_count(); }
  // The thread team's parking rule: where it settled, how often it probed and
  // switched; nullptr before the first step.
  const WorkerParkingPolicy* worker_parking() const {
    return team_ ? &team_->parking() : nullptr;
  }
  std::size_t contact_count() const { return contacts_; }  // particle and wall contacts, last step
  std::size_t neighbor_pair_count() const { return neighbors_.pair_count(); }
  EnergyBudget energy() const;
  double kinetic_energy_j() const;
  // Root-mean-square translational speed; the "at rest" criterion uses it.
  double rms_speed_m_s() const;
  // Particle-steps integrated so far (sum over steps of the particle count).
  double particle_steps() const { return particle_steps_; }

 private:
  void prepare();
  void check_hold_range(const std::set<int>& particle_materials,
                        const std::set<int>& wall_materials, double r_max);
  void run_inserters();
  void rebuild_neighbors();
  // Sorts the particles into spatial order and renames every index-keyed
  // state (pair and wall histories, the last step's forces) to match.
  void reorder_particles();
  void compute_forces();
  // Computes the forces, then calls finish(begin, end) on consecutive slices of
  // the particles, each a chunk of the team's run, once their forces are
  // final; finish returns the first unstable particle of its slice (or n).
  template <class Finish>
  void compute_forces(Finish&& finish);
  void split_ownership();
  // First particle of chunk m's slice in the kicks (m = chunks gives n).
  std::size_t slice_begin(int m) const;
  [[noreturn]] void report_instability(std::size_t particle) const;
  template <class Kernel, class Finish>
  void compute_contact_forces(const Kernel& kernel, Finish& finish);

  SimulationOptions options_;
  ContactLaw law_;
  std::vector<Material> materials_;
  std::vector<std::optional<InteractionParameters>> interactions_;  // dense, materials^2
  std::vector<PairCoefficients> coefficients_;                      // dense, materials^2
  std::vector<std::unique_ptr<Wall>> walls_;
  std::vector<int> wall_material_;
  std::vector<WallLoad> wall_loads_;
  std::vector<std::unique_ptr<Inserter>> inserters_;
  std::vector<std::unique_ptr<BodyForce>> body_forces_;
  Particles particles_;
  NeighborList neighbors_;
  Random rng_;

  struct WallCandidates;  // particles near each wall, with their contact history
  std::vector<WallCandidates> wall_candidates_;
  std::vector<Vec3> wall_offset_at_build_;
  std::vector<double> wall_change_times_;

  std::unique_ptr<ThreadTeam> team_;
  // What each chunk of a team run reports.
  struct alignas(64) ChunkScratch {
    bool moved_beyond_half_skin = false;  // since the last neighbour build
    double elastic_j = 0.0;
    std::size_t contacts = 0;
    std::size_t first_bad = 0;
  };
  std::vector<ChunkScratch> chunk_scratch_;
  std::vector<ContactBatch> contact_batches_;  // one per chunk
  std::vector<WallContactBatch> wall_contact_batches_;  // one per chunk
  // Chunk m owns particles [owner_begin_[m], owner_begin_[m+1]) in the force
  // loop (split so that each owns about as many listed pairs) and writes
  // forces on particles up to window_end_[m] (its partners). Set at each build.
  std::vector<std::size_t> owner_begin_;
  std::vector<std::size_t> window_end_;
  std::vector<double> ownership_cost_prefix_;  // scratch of split_ownership()
  // Per-chunk force buffers; summed in chunk order so results repeat exactly.
  std::vector<std::vector<Vec3>> thread_force_;
  std::vector<std::vector<Vec3>> thread_torque_;
  std::vector<std::vector<WallLoad>> thread_wall_loads_;  // [thread][wall]
  std::vector<Vec3> force_before_;   // last step's force, to undo the velocity prediction
  std::vector<Vec3> torque_before_;

  bool prepared_ = false;
  bool rebuild_requested_ = true;
  double dt_ = 0.0;
  double skin_m_ = 0.0;
  // Largest gap at which a part of the law holds a contact that touched (0
  // without adhesion): how far beyond touching the wall loop looks.
  double hold_range_m_ = 0.0;
  double max_speed_m_s_ = 0.0;
  double time_s_ = 0.0;
  std::int64_t steps_ = 0;
  std::int64_t next_id_ = 0;
  double elastic_energy_j_ = 0.0;
  std::size_t contacts_ = 0;
  double particle_steps_ = 0.0;
};

}  // namespace demcal::dem
