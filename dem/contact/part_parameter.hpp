#pragma once
// A contact part's own parameters, declared by the part (MercuryDPM-style): a
// part lists them in `static constexpr std::array<PartParameter, N> kParameters`
// and everything else — the TOML readers of both config kinds, the range check
// of InteractionParameters::validate, coarse graining, `demcal schema contact`
// and the check that a key is given only with its part — reads that list
// (registered_part_parameters() in contact_law.hpp). Adding a physics with its
// own numbers is then one file plus one line in a role's variant list.
//
// Where a value lives: per pair of materials, in InteractionParameters::
// part_values (what the user gave) and PairCoefficients::part_values (what the
// force loop reads), at the slot the declaration names. Slots are unique across
// every registered part (registered_part_parameters() refuses a clash, as
// OpenFOAM's selection tables refuse a duplicate name). The JKR surface energy
// predates the slots and keeps its named field (`legacy_field`), so code and
// tests that name it are unchanged.

#include "dem/contact/pair_coefficients.hpp"

#include <cmath>
#include <limits>
#include <string>

namespace demcal::dem {

struct PartParameter {
  const char* key;      // TOML key in an interaction table, with its unit: "surface_tension_n_m"
  const char* unit;     // "N/m", "deg", "1"
  const char* summary;  // one line for the schema
  const char* what;     // how messages name it: "a surface tension"
  double default_value = 0.0;  // the value when the key is absent
  // Accepted values: [lo, hi], each end open when the flag says so.
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;
  // false: an absent key is not written into the resolved config, so the run
  // keys (content hashes) of configs without it stay byte-identical. Every
  // part parameter so far is declared so.
  bool written_when_absent = false;
  // The part needs this key in at least one interaction table (its strength:
  // a part switched on without it would silently do nothing).
  bool required = false;
  // A parcel f times a grain's size carries value * f^exponent, chosen so that
  // the parcel keeps the grain's dimensionless group (a Bond number: a force
  // scaling as value * R over a weight scaling as R^3 gives exponent 2).
  double coarse_graining_exponent = 0.0;
  int slot = -1;  // index into part_values; -1 with a legacy_field
  double InteractionParameters::*legacy_field = nullptr;

  bool accepts(double v) const {
    if (!std::isfinite(v)) return false;
    if (lo_open ? !(v > lo) : !(v >= lo)) return false;
    if (hi_open ? !(v < hi) : !(v <= hi)) return false;
    return true;
  }
  double value_in(const InteractionParameters& p) const {
    return legacy_field != nullptr ? p.*legacy_field : p.part_values[static_cast<std::size_t>(slot)];
  }
  double& value_in(InteractionParameters& p) const {
    return legacy_field != nullptr ? p.*legacy_field : p.part_values[static_cast<std::size_t>(slot)];
  }
  // The value scaled for a parcel of coarse-graining factor f; an integer
  // exponent multiplies (bit-identical to the f * f it replaced).
  double coarse_grained(double value, double f) const {
    const double e = coarse_graining_exponent;
    if (e == std::floor(e) && std::abs(e) <= 8.0) {
      double scale = 1.0;
      for (int i = 0; i < static_cast<int>(std::abs(e)); ++i) scale *= f;
      return e >= 0.0 ? value * scale : value / scale;
    }
    return value * std::pow(f, e);
  }
};

// One declared parameter with the part and role that own it.
struct RegisteredPartParameter {
  std::string role;  // "adhesion"
  std::string part;  // "liquid_bridge"
  PartParameter parameter;
};

}  // namespace demcal::dem
