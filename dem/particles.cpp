#include "dem/particles.hpp"

#include <numbers>

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

}  // namespace demcal::dem
