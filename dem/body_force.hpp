#pragma once
// Forces on each particle that do not come from contacts: gravity now, air
// drag and other fields later, each its own part.

#include "dem/particles.hpp"

#include <memory>
#include <string>

namespace demcal::dem {

class BodyForce {
 public:
  virtual ~BodyForce() = default;
  virtual std::string name() const = 0;
  // Adds this field's force (and torque) on particles [begin, end) to the arrays.
  virtual void add(const Particles& particles, std::size_t begin, std::size_t end,
                   std::vector<Vec3>& force_n, std::vector<Vec3>& torque_nm) const = 0;
  // Potential energy of the field, for energy balances (0 if not conservative).
  virtual double potential_energy_j(const Particles& /*particles*/) const { return 0.0; }
};

class Gravity final : public BodyForce {
 public:
  explicit Gravity(const Vec3& acceleration_m_s2) : g_(acceleration_m_s2) {}
  std::string name() const override { return "gravity"; }
  void add(const Particles& p, std::size_t begin, std::size_t end, std::vector<Vec3>& force_n,
           std::vector<Vec3>& /*torque_nm*/) const override {
    for (std::size_t i = begin; i < end; ++i) force_n[i] += p.mass_kg[i] * g_;
  }
  double potential_energy_j(const Particles& p) const override {
    double e = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) e -= p.mass_kg[i] * dot(g_, p.position_m[i]);
    return e;
  }
  const Vec3& acceleration_m_s2() const { return g_; }

 private:
  Vec3 g_;
};

}  // namespace demcal::dem
