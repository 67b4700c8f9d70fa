#pragma once
// What an inserter sees of the simulation while it places particles: a test
// for free space (other particles, also those placed a moment ago, and walls)
// and a way to add a particle there.

#include "dem/domain.hpp"
#include "dem/particles.hpp"
#include "dem/random.hpp"
#include "dem/wall/wall.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <unordered_map>
#include <vector>

namespace demcal::dem {

class InsertionContext {
 public:
  using AddFn = std::function<void(const Vec3& centre_m, double radius_m, int material,
                                   const Vec3& velocity_m_s)>;

  // Indexes the particles near the box [lower, upper] (grown by the largest
  // radius that can occur) so that is_free costs O(1).
  InsertionContext(double time_s, const Domain& domain, const Particles& particles,
                   const std::vector<const Wall*>& walls, Random& rng, const Vec3& lower_m,
                   const Vec3& upper_m, double max_radius_m, AddFn add);

  double time_s() const { return time_s_; }
  Random& rng() { return rng_; }
  const Domain& domain() const { return domain_; }

  // True when a sphere here would touch no particle and no wall.
  bool is_free(const Vec3& centre_m, double radius_m) const;
  // Adds the particle (the caller checked is_free) and indexes it.
  void add(const Vec3& centre_m, double radius_m, int material, const Vec3& velocity_m_s);

 private:
  std::int64_t key(const Vec3& p) const;
  std::array<int, 3> coords(const Vec3& p) const;

  double time_s_;
  const Domain& domain_;
  const std::vector<const Wall*>& walls_;
  Random& rng_;
  AddFn add_;
  double cell_m_;
  std::array<int, 3> wrap_{};  // cells along periodic axes (0 = not periodic)
  struct Entry {
    Vec3 centre;
    double radius;
  };
  std::unordered_map<std::int64_t, std::vector<Entry>> grid_;
};

}  // namespace demcal::dem
