#pragma once
// The calibrated material card: every contact parameter a target engine needs,
// from demcal's calibrated material through the parameter mapping
// (parameter_mapping.hpp), with the calibrated values and their 95 %
// intervals as comments (each interval also carried through the mapping to the
// engine's parameters it moves), the engine and contact model the calibration
// ran on, the reductions it used, and a warning when the target engine is not
// the engine the calibration ran on. Formats: a LAMMPS or LIGGGHTS input
// fragment, EDEM's parameters as CSV, and demcal's own JSON.

#include "dem/apparatus/granular_material.hpp"
#include "engines/parameter_mapping.hpp"

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace demcal::engines {

enum class CardFormat { kLammps, kLiggghts, kEdemCsv, kJson };

// "lammps" | "liggghts" | "edem-csv" | "json"; throws std::invalid_argument listing them.
CardFormat card_format_from_name(const std::string& name);
std::string card_format_name(CardFormat format);

struct CalibratedParameter {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  // A field of the material: "particle_particle.<field>" or "particle_wall.<field>"
  // (restitution, sliding_friction, rolling_friction, rolling_stiffness_factor,
  // rolling_damping_ratio, surface_energy_j_m2), or "particle.<field>"
  // (density_kg_m3, youngs_modulus_pa, shear_modulus_pa, poisson_ratio).
  std::string name;
  double value = kNaN;
  double lower_95 = kNaN;  // NaN: no interval (a fixed parameter)
  double upper_95 = kNaN;
};

struct CardProvenance {
  std::string study;
  Engine calibrated_engine = Engine::kDemcal;
  std::string calibrated_engine_version;  // e.g. demcal's DEMCAL_VERSION
  std::string contact_model;              // empty: described from the material
};

struct MaterialCardInput {
  dem::GranularMaterial material;  // the calibrated values already set in it
  dem::ModelReduction reduction;   // the coarse graining and modulus the calibration ran with
  std::vector<CalibratedParameter> calibrated;
  CardProvenance provenance;
};

struct CardResult {
  std::optional<std::string> text;
  std::string refusal;
  bool ok() const { return text.has_value(); }
};

// Sets the named field (see CalibratedParameter::name); throws
// std::invalid_argument naming the known fields for an unknown name.
void set_material_parameter(dem::GranularMaterial& material, const std::string& name, double value);
double material_parameter(const dem::GranularMaterial& material, const std::string& name);

// Refuses what the target cannot express (the mapping's refusal). The card is
// deterministic: the same input gives the same bytes.
CardResult write_material_card(const MaterialCardInput& input, CardFormat format,
                               const MappingOptions& mapping = {});

}  // namespace demcal::engines
