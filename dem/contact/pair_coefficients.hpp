#pragma once
// The numbers one pair of materials needs at every contact, resolved once from
// the user's input (materials + interaction) so the force loop does no setup work.

#include "dem/material.hpp"

#include <array>
#include <cstddef>
#include <string>

namespace demcal::dem {

// The values of the parameters contact parts declare for themselves
// (dem/contact/part_parameter.hpp), by slot.
inline constexpr std::size_t kPartValueSlots = 8;
using PartValues = std::array<double, kPartValueSlots>;
// Every slot at its declared default (0 where no part declares it); defined
// in contact_law.cpp, where the parts are registered.
const PartValues& default_part_values();

// What a user states about a pair of materials (particle–particle or particle–wall).
struct InteractionParameters {
  double restitution = 0.5;        // coefficient of restitution in (0, 1]
  double sliding_friction = 0.5;   // mu_s, Coulomb coefficient
  double rolling_friction = 0.0;   // mu_r, dimensionless (see the rolling parts for the lever arm)
  // Elastic–plastic spring–dashpot rolling: k_r = factor * k_n * (mu_r R*)^2 (Iwashita & Oda: 2.25)
  double rolling_stiffness_factor = 2.25;
  // Elastic–plastic spring–dashpot rolling: fraction of critical rolling damping (Ai et al. 2011)
  double rolling_damping_ratio = 0.3;
  // Surface energy gamma of each surface (J/m^2) for an adhesion part (JKR:
  // pull-off force 3 pi gamma R*); 0 = no adhesion between this pair.
  double surface_energy_j_m2 = 0.0;
  // The parameters contact parts declare themselves, at their defaults until read.
  PartValues part_values = default_part_values();

  // Throws std::invalid_argument naming the field (prefixed by `where`); the
  // declared part parameters against their declared ranges.
  void validate(const std::string& where) const;
};

// How the damping coefficient is derived from the restitution.
enum class RestitutionModel {
  // beta chosen so that a Hertzian collision with this damping rebounds with
  // exactly the stated restitution (solved once per pair). Default.
  kExact,
  // beta = ln e / sqrt(ln^2 e + pi^2), the linear-spring formula that
  // commercial codes use with Hertz contacts; the realised restitution differs
  // from the stated one, markedly below e ~ 0.5.
  kLinearSpringFormula,
};

struct PairCoefficients {
  double youngs_modulus_eff_pa = 0.0;  // E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)
  double shear_modulus_eff_pa = 0.0;   // G* = 1 / ((2 - nu1)/G1 + (2 - nu2)/G2)
  double damping_beta = 0.0;           // |beta| in C = 2 sqrt(5/6) beta sqrt(S m*)
  double sliding_friction = 0.0;
  double rolling_friction = 0.0;
  double rolling_stiffness_factor = 0.0;
  double rolling_damping_ratio = 0.0;
  double surface_energy_j_m2 = 0.0;
  PartValues part_values{};  // as given, by the slot each part declares
};

PairCoefficients resolve_pair(const Material& a, const Material& b,
                              const InteractionParameters& p, RestitutionModel model);

}  // namespace demcal::dem
