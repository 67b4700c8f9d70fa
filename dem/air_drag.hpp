#pragma once
// Air drag on particles moving through still air: a body force (BodyForce), on
// with `[air] drag = "schiller_naumann"` in a config.
//
// Each sphere of diameter d moving at v feels
//   F = -(1/2) rho_air C_d (pi d^2 / 4) |v| v,  Re = rho_air |v| d / mu_air,
//   C_d = 24 / Re (1 + 0.15 Re^0.687) for Re < 1000, 0.44 above (Schiller & Naumann 1933),
// written as F = -3 pi mu_air d v (C_d Re / 24) so that the Stokes limit
// F = -3 pi mu_air d v at small Re is exact and v = 0 gives exactly 0.
// The air is at rest and unbounded: no buoyancy (rho_air / rho_grain ~ 5e-4 for
// quartz), no torque, no drag on the walls' account, no air flow through a bed
// (a grain in a packing feels the drag of an isolated sphere: fine for free
// fall and thin streams, an overestimate in dense flow).
//
// AirDrag multiplies this force by AirProperties::drag_scale: the strength
// parameter the missing-physics diagnosis (`demcal diagnose`) varies, since
// drag = "none" | "schiller_naumann" alone has no value that switches it off.
//
// Coarse graining: a parcel of factor f stands for f^3 grains. Its drag is
// computed for the original grain, diameter d / f, at the parcel's velocity,
// and multiplied by f^3, so drag per unit mass, and with it the terminal
// velocity, are the grain's; drag on a parcel of diameter d would give it the
// terminal velocity of a grain f times larger.

#include "dem/body_force.hpp"
#include "dem/vec3.hpp"

#include <string>

namespace demcal::dem {

struct AirProperties {
  double density_kg_m3 = 1.2;  // dry air near 20 C, sea level
  double dynamic_viscosity_pa_s = 1.8e-5;
  // Dimensionless, >= 0: 1 = still air as Schiller–Naumann gives it, 0 = no
  // drag at all; values between stand for a partial effect (e.g. drag screened
  // in a dense stream), above for more drag than an isolated sphere feels.
  double drag_scale = 1.0;

  // Throws std::invalid_argument naming the field.
  void validate() const;
};

// Schiller–Naumann's C_d Re / 24: 1 + 0.15 Re^0.687 below Re = 1000, 0.44 Re / 24 above.
double schiller_naumann_drag_factor(double reynolds);

// The drag on one sphere of `diameter_m` moving at `velocity_m_s` through still air,
// Schiller–Naumann's unscaled (AirDrag applies air.drag_scale).
Vec3 sphere_drag_force_n(const AirProperties& air, double diameter_m, const Vec3& velocity_m_s);

class AirDrag final : public BodyForce {
 public:
  // coarse_graining_factor f: each particle is a parcel of f^3 grains of diameter d / f.
  explicit AirDrag(const AirProperties& air, double coarse_graining_factor = 1.0);
  std::string name() const override { return "air_drag"; }
  void add(const Particles& particles, std::size_t begin, std::size_t end,
           std::vector<Vec3>& force_n, std::vector<Vec3>& torque_nm) const override;
  const AirProperties& air() const { return air_; }
  double coarse_graining_factor() const { return factor_; }

 private:
  AirProperties air_;
  double factor_;
};

}  // namespace demcal::dem
