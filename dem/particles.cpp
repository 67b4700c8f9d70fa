#include "dem/particles.hpp"

#include <numbers>
#include <string>
#include <stdexcept>

namespace demcal::dem {

std::size_t Particles::add(const Vec3& position, double radius, double density_kg_m3,
                           int material_index, std::int64_t identifier, const Vec3& velocity,
                           const Vec3& omega) {
  const double mass = density_kg_m3 * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  const double inertia = 0.4 * mass * radius * radius;
  position_m.push_back(position);
  velocity_m_s.push_back(velocity);
  omega_rad_s.push_back(omega);
  force_n.push_back({});
  torque_nm.push_back({});
  radius_m.push_back(radius);
  mass_kg.push_back(mass);
  inv_mass_kg.push_back(1.0 / mass);
  inv_inertia_kg_m2.push_back(1.0 / inertia);
  material.push_back(material_index);
  id.push_back(identifier);
  return size() - 1;
}

namespace {

template <class T>
void gather(std::vector<T>& values, const std::vector<std::uint32_t>& order, std::vector<T>& scratch) {
  scratch.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) scratch[k] = values[order[k]];
  values.swap(scratch);
}

}  // namespace

void Particles::permute(const std::vector<std::uint32_t>& order) {
  if (order.size() != size())
    throw std::invalid_argument("Particles::permute: the order has " + std::to_string(order.size()) +
                                " entries for " + std::to_string(size()) + " particles");
  std::vector<Vec3> v3;
  gather(position_m, order, v3);
  gather(velocity_m_s, order, v3);
  gather(omega_rad_s, order, v3);
  gather(force_n, order, v3);
  gather(torque_nm, order, v3);
  std::vector<double> d;
  gather(radius_m, order, d);
  gather(mass_kg, order, d);
  gather(inv_mass_kg, order, d);
  gather(inv_inertia_kg_m2, order, d);
  std::vector<int> i32;
  gather(material, order, i32);
  std::vector<std::int64_t> i64;
  gather(id, order, i64);
}

}  // namespace demcal::dem
