#pragma once
// Particle storage, structure of arrays: the force loop streams positions and
// velocities and touches the rest rarely.

#include "dem/vec3.hpp"

#include <cstdint>
#include <vector>

namespace demcal::dem {

struct Particles {
  std::vector<Vec3> position_m;
  std::vector<Vec3> velocity_m_s;
  std::vector<Vec3> omega_rad_s;
  std::vector<Vec3> force_n;
  std::vector<Vec3> torque_nm;
  std::vector<double> radius_m;
  std::vector<double> mass_kg;
  std::vector<double> inv_mass_kg;
  std::vector<double> inv_inertia_kg_m2;
  std::vector<int> material;
  std::vector<std::int64_t> id;

  std::size_t size() const { return radius_m.size(); }
  bool empty() const { return radius_m.empty(); }

  // Appends a solid sphere; returns its index.
  std::size_t add(const Vec3& position, double radius, double density_kg_m3, int material_index,
                  std::int64_t identifier, const Vec3& velocity = {}, const Vec3& omega = {});

  // Reorders every per-particle array: the particle at old index order[k]
  // moves to index k. `order` must be a permutation of 0 .. size()-1. A
  // particle keeps its id, so whatever follows particles across a reorder
  // (outputs, latches) must key them by id, not by index. Any array added to
  // this struct must be added here too.
  void permute(const std::vector<std::uint32_t>& order);
};

}  // namespace demcal::dem
