#pragma once
// The empty adhesion part: dry, cohesionless grains.

#include "dem/contact/contact_state.hpp"
#include "dem/contact/pair_coefficients.hpp"

namespace demcal::dem {

struct NoAdhesion {
  static constexpr const char* kName = "none";
  void apply(const ContactKinematics&, const PairCoefficients&, ContactHistory&,
             ContactForce&) const {}
};

}  // namespace demcal::dem
