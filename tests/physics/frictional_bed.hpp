#pragma once
// A frictional bed of 6 x 6 x 8 spheres dropped onto a frictional floor in a
// box periodic in x and y, and the comparisons of two runs of it: per particle
// id, and bit for bit. Shared by the tests of the particle order and of the
// thread team's chunks, which both change only the order of summation.
#include "physics_fixtures.hpp"

#include "dem/particle_order.hpp"
#include "dem/random.hpp"
#include "dem/wall/plane_wall.hpp"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

namespace demcal::dem::testing {

inline constexpr double kRadius = 0.5e-3;

// Positions of a lattice of nx x ny x nz spheres, listed in a shuffled order so
// that insertion order and spatial order differ everywhere.
inline std::vector<Vec3> shuffled_lattice(int nx, int ny, int nz, double spacing, double z0,
                                   std::uint64_t seed) {
  std::vector<Vec3> sites;
  for (int iz = 0; iz < nz; ++iz)
    for (int iy = 0; iy < ny; ++iy)
      for (int ix = 0; ix < nx; ++ix)
        sites.push_back({(ix + 0.5) * spacing, (iy + 0.5) * spacing, z0 + (iz + 0.5) * spacing});
  Random rng(seed);
  for (std::size_t i = sites.size(); i > 1; --i) {
    const auto j = static_cast<std::size_t>(rng.uniform(0.0, static_cast<double>(i)));
    std::swap(sites[i - 1], sites[std::min(j, i - 1)]);
  }
  return sites;
}

// A frictional bed of 6 x 6 x 8 spheres with random velocities, dropped onto a
// frictional floor in a box periodic in x and y: tangential and rolling springs
// between particles and against the floor, pairs through the periodic images.
inline std::unique_ptr<Simulation> frictional_bed(ParticleOrder order, int threads,
                                                  int chunks_per_thread = 1) {
  const double spacing = 2.05 * kRadius;
  const double side = 6 * spacing;
  auto o = options_in_box({0, 0, -0.001}, {side, side, 0.03}, {0, 0, -9.81});
  o.domain.periodic = {true, true, false};
  o.contact.rolling = "epsd";
  o.threads = threads;
  o.chunks_per_thread = chunks_per_thread;
  o.particle_order = order;
  auto s = make_scene(o, interaction(0.6, 0.5, 0.1));
  s.sim->add_wall(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), s.material);
  Random rng(11);
  for (const Vec3& x : shuffled_lattice(6, 6, 8, spacing, 0.0, 5)) {
    const Vec3 v{rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05)};
    s.sim->add_particle(x, kRadius, s.material, v);
  }
  return std::move(s.sim);
}

// State by particle id.
struct ById {
  std::vector<Vec3> position, velocity, omega;
};
inline ById by_id(const Particles& p) {
  ById out;
  out.position.resize(p.size());
  out.velocity.resize(p.size());
  out.omega.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto id = static_cast<std::size_t>(p.id.at(i));
    out.position.at(id) = p.position_m[i];
    out.velocity.at(id) = p.velocity_m_s[i];
    out.omega.at(id) = p.omega_rad_s[i];
  }
  return out;
}

inline bool bitwise_equal(const Particles& a, const Particles& b) {
  if (a.size() != b.size() || a.id != b.id) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (a.position_m[i][k] != b.position_m[i][k] || a.velocity_m_s[i][k] != b.velocity_m_s[i][k] ||
          a.omega_rad_s[i][k] != b.omega_rad_s[i][k])
        return false;
  return true;
}

inline std::size_t moved_particles(const Particles& p) {
  std::size_t moved = 0;
  for (std::size_t i = 0; i < p.size(); ++i) moved += p.id[i] != static_cast<std::int64_t>(i);
  return moved;
}

}  // namespace demcal::dem::testing
