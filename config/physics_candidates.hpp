#pragma once
// The physics a base model may have left out, as `demcal diagnose` knows them:
// one entry per candidate, each naming the engine part it switches on
// (dem/contact/jkr_adhesion.hpp, dem/air_drag.hpp, ...) by the study keys that
// do so, and the one parameter that sets its strength. A new candidate is one
// entry in physics_candidates() — the diagnosis itself names none of them.
//
// The parameter's "off" value is where the candidate adds nothing: 0 for
// cohesion and air drag; for the particle–wall friction and the size spread,
// the study's own value (the base model's assumption, which the candidate
// frees).

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace demcal::config {

struct PhysicsCandidate {
  std::string name;       // "cohesion"
  std::string summary;    // "cohesion (JKR surface energy between grains and with the walls)"
  std::string parameter;  // the design parameter's name, e.g. "surface_energy_j_m2"
  std::vector<std::string> keys;  // study keys the parameter sets, all to its value
  // key = value (strings) that switch the part on, e.g. contact.adhesion = "jkr".
  std::vector<std::pair<std::string, std::string>> switches;
  std::optional<double> off_value;  // nullopt: the study's value of keys[0]
  double lower = 0.0, upper = 1.0;  // the range the design extends into
  // The sensitivity runs' value: far enough from "off" that the effect stands
  // out of the DEM's scatter, close enough to stay near-linear.
  double probe = 0.0;
};

// Every candidate demcal knows, in a fixed order.
const std::vector<PhysicsCandidate>& physics_candidates();

// The candidate of that name; ConfigError-free: nullptr when unknown.
const PhysicsCandidate* find_physics_candidate(const std::string& name);

std::vector<std::string> physics_candidate_names();

}  // namespace demcal::config
