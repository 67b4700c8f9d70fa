#pragma once
// Inserters add particles during a run. Each is asked every step whether it is
// due; placement never creates an overlap (with particles or walls).

#include "dem/insertion/insertion_context.hpp"
#include "dem/insertion/region.hpp"
#include "dem/size_distribution.hpp"
#include "dem/domain.hpp"

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace demcal::dem {

class Inserter {
 public:
  virtual ~Inserter() = default;
  virtual bool due(double time_s) const = 0;
  // Places what is due; throws std::runtime_error when it cannot and never will.
  virtual void insert(InsertionContext& ctx) = 0;
  virtual bool finished() const = 0;
  virtual std::size_t inserted() const = 0;
  virtual double inserted_mass_kg() const = 0;
  virtual int material() const = 0;
  virtual const SizeDistribution& sizes() const = 0;
  virtual const Region& region() const = 0;
  virtual std::string describe() const = 0;
};

// What and how much: a count, a mass, or both (whichever is reached first).
struct InsertionAmount {
  std::size_t count = 0;   // 0: no limit by count
  double mass_kg = 0.0;    // 0: no limit by mass
};

struct PourOptions {
  int material = 0;
  double density_kg_m3 = 2650.0;
  InsertionAmount amount;
  Vec3 velocity_m_s;           // initial velocity of each particle
  double start_s = 0.0;
  // Either a steady rate (particles per second; used when > 0) ...
  double rate_particles_per_s = 0.0;
  // ... or batches filling the region to this solid volume fraction, one batch
  // each time the previous one has fallen clear of the region (LAMMPS's fix pour).
  double batch_volume_fraction = 0.3;
  Vec3 gravity_m_s2{0, 0, -9.81};  // to time the batches
  int attempts_per_particle = 200;
};

// Pours particles from a region.
std::unique_ptr<Inserter> make_pour_inserter(std::unique_ptr<Region> region,
                                             std::unique_ptr<SizeDistribution> sizes,
                                             const PourOptions& options);

struct FillOptions {
  int material = 0;
  double density_kg_m3 = 2650.0;
  InsertionAmount amount;
  double time_s = 0.0;   // when to fill
  // "random": random sequential addition (loose, ~30-35 % solid); "lattice": a
  // cubic lattice of the largest diameter (times 1 + gap) jittered in all three
  // directions (denser, and the jitter avoids crystalline layers).
  std::string method = "random";
  double lattice_gap = 0.05;
  int attempts_per_particle = 400;
};

// The nominal centres a lattice fill uses (before jitter), bottom up: how many
// particles a region can take that way, known before anything runs. At most
// max_sites of them (the first, in the same order): a capacity check or a fill
// needs no more sites than grains, however large the region.
std::vector<Vec3> lattice_sites(const Region& region, double max_diameter_m, double lattice_gap,
                                const Domain& domain,
                                std::size_t max_sites = std::numeric_limits<std::size_t>::max());

// The same sites in the same order, handed to `visit` one by one until it
// returns false: a fill takes sites until it has its amount, without a list
// of every site of a large region.
void for_each_lattice_site(const Region& region, double max_diameter_m, double lattice_gap,
                           const Domain& domain, const std::function<bool(const Vec3&)>& visit);

// Fills a region at one instant; throws when the region cannot hold the amount.
std::unique_ptr<Inserter> make_fill_inserter(std::unique_ptr<Region> region,
                                             std::unique_ptr<SizeDistribution> sizes,
                                             const FillOptions& options);

}  // namespace demcal::dem
