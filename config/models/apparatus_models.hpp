#pragma once
// The apparatus a study can define ([apparatus.<name>]), registered by name
// (config/model_registry.hpp). Each apparatus has one file here,
// apparatus_<name>.cpp, holding its reader and its registration function
// register_<name>(ApparatusRegistry&); the list of registrations is
// apparatus_models.cpp (one line per apparatus). The helpers below are what
// every apparatus reader shares.

#include "config/model_registry.hpp"
#include "config/toml_reader.hpp"
#include "dem/apparatus/apparatus.hpp"
#include "dem/apparatus/granular_material.hpp"
#include <functional>

#include <memory>
#include <string>
#include <vector>

namespace demcal::config {

// Reads an apparatus table (its `type` already read by the study reader) and
// builds the apparatus; calls finish(). `max_steps` is the protocol's step cap.
using ApparatusReader = std::unique_ptr<dem::Apparatus> (*)(reader::Table& t,
                                                           const dem::GranularMaterial& material,
                                                           double max_steps,
                                                           const dem::RunProtocol& protocol);

struct ApparatusModel {
  ApparatusReader read = nullptr;
  // The names its walls are grouped under ([interaction.particle_wall.<group>]).
  std::vector<std::string> (*wall_group_names)() = nullptr;
};

using ApparatusRegistry = ModelRegistry<ApparatusModel>;
const ApparatusRegistry& apparatus_models();

namespace apparatus_reading {

// The model-reduction keys (slice only where `slice_applies`), as every
// apparatus reads them, and their declarations for the schema.
dem::ModelReduction read_reduction(reader::Table& t, bool slice_applies);
std::vector<ModelKey> reduction_keys(bool slice_applies);

// Runs an apparatus constructor; what it refuses (std::logic_error) is an
// input error, reported at the key its message names first, else at the table.
std::unique_ptr<dem::Apparatus> build_guarded(
    const reader::Table& t, const std::function<std::unique_ptr<dem::Apparatus>()>& make);

inline const reader::Range kPositive = reader::above(0);
inline const reader::Range kHalfAngle = reader::between(0, true, 80, true);
// A dimension of a laboratory test: positive, and at most kMaxApparatusExtent_m
// (a 1e6 m chamber is a slip, and its fill lattice alone would not fit in memory).
extern const reader::Plausible kMaxLength;

}  // namespace apparatus_reading
}  // namespace demcal::config
