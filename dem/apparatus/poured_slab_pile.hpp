#pragma once
// The poured quasi-2D pile of the peer cases (../shared/peers/lammps/pile.in):
// monodisperse spheres poured from a narrow inlet onto a frictional floor
// between two side walls, in a slab periodic across its thickness. It is the
// engine's benchmark case and the sanity check that friction steepens a pile.

#include "dem/simulation.hpp"

#include <memory>

namespace demcal::dem {

struct PouredSlabPileOptions {
  // Grains poured from the inlet. 0 builds the empty box with its walls and
  // materials ("grain", "wall"), for a caller that places its own grains (the
  // benchmark's tiled pile).
  std::size_t particles = 6000;
  double diameter_m = 1e-3;
  double density_kg_m3 = 2650.0;
  double youngs_modulus_pa = 1e7;
  double poisson_ratio = 0.3;
  double restitution = 0.6;
  double sliding_friction = 0.5;
  double rolling_friction = 0.1;
  double wall_sliding_friction = 0.9;
  double wall_rolling_friction = 0.3;
  std::string rolling_model = "epsd";
  double slab_thickness_diameters = 5.0;
  double box_length_m = 0.12;   // x extent, side walls at +-box_length/2
  double box_height_m = 0.045;
  double inlet_half_width_diameters = 4.0;
  double inlet_bottom_m = 0.030;
  double inlet_top_m = 0.035;
  double inlet_speed_m_s = 0.5;  // downwards
  double batch_volume_fraction = 0.3;
  double time_step_s = 5e-6;
  std::uint64_t seed = 4767;
  int threads = 1;
  ParticleOrder particle_order = ParticleOrder::kInsertion;  // dem/particle_order.hpp
  WorkerParking worker_parking = WorkerParking::kAdaptive;   // dem/worker_parking.hpp
  WorkerParkingOptions worker_parking_options;
};

std::unique_ptr<Simulation> make_poured_slab_pile(const PouredSlabPileOptions& options);

// The grains copied `copies` times across the periodic slab thickness into the
// empty box of `options` made `copies` times as thick, positions and
// velocities only (no spin, no contact history), as LAMMPS's `replicate`
// builds it: the benchmark's larger case. The copies meet as the images did.
std::unique_ptr<Simulation> copy_across_slab(const PouredSlabPileOptions& options,
                                             const Particles& grains, int copies);

// Runs until everything is poured and the rms speed falls below rest_speed_m_s,
// or until max_time_s. Returns true when it came to rest.
bool run_until_at_rest(Simulation& sim, double rest_speed_m_s, double max_time_s,
                       double check_interval_s = 5e-3);

}  // namespace demcal::dem
