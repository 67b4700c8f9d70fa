// Every contact law the parts can make: each adhesion ("none", "jkr") with
// each registered tangential and rolling part, and cdt in both of its
// angular-velocity forms. The batch tests (test_contact_batch.cpp,
// test_wall_contact_batch.cpp) run each against the law applied one contact
// at a time; a part added to the registry is then checked without a change
// here.
#pragma once

#include "dem/contact/contact_law.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/material.hpp"

#include <string>
#include <vector>

namespace demcal::dem::testing {

// Calls visit(law, name) for each law; returns how many there were.
template <class Visit>
int for_every_contact_law(Visit&& visit) {
  int laws = 0;
  for (const char* adhesion : {"none", "jkr"})
    for (const std::string& tangential : known_part_names("tangential"))
      for (const std::string& rolling : known_part_names("rolling"))
        for (const bool own : {false, true}) {
          if (own && rolling != "cdt") continue;
          ContactLawSpec spec;
          spec.adhesion = adhesion;
          spec.tangential = tangential;
          spec.rolling = rolling;
          spec.cdt_own_angular_velocity = own;
          const ContactLaw law = make_contact_law(spec);
          visit(law, law.describe() + (own ? " (own angular velocity)" : ""));
          ++laws;
        }
  return laws;
}

// The pair coefficients of two materials (sand and glass, so that the table
// is looked up per pair), with rolling friction, sliding friction and surface
// energy; the pair (0, 1) has no rolling friction (the parts' former early
// return). Indexed a * materials + b.
struct CoefficientTable {
  int materials = 0;
  std::vector<PairCoefficients> table;
};

inline CoefficientTable two_material_coefficients() {
  const std::vector<Material> materials = {{"sand", 2650.0, 5e7, 0.0, 0.25},
                                           {"glass", 2500.0, 6e7, 0.0, 0.22}};
  InteractionParameters p;
  p.restitution = 0.6;
  p.sliding_friction = 0.5;
  p.rolling_friction = 0.3;
  p.surface_energy_j_m2 = 0.05;
  CoefficientTable c;
  c.materials = static_cast<int>(materials.size());
  for (const Material& a : materials)
    for (const Material& b : materials)
      c.table.push_back(resolve_pair(a, b, p, RestitutionModel::kExact));
  InteractionParameters q = p;
  q.rolling_friction = 0.0;
  c.table[1] = resolve_pair(materials[0], materials[1], q, RestitutionModel::kExact);
  return c;
}

}  // namespace demcal::dem::testing
