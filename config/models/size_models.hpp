#pragma once
// The particle size distributions of a size table ({ distribution = "<name>",
// <its keys> }: a study's [material.size], a simulation's [insertion.size]),
// registered by name (config/model_registry.hpp); reader::read_size looks the
// name up here.

#include "config/model_registry.hpp"
#include "config/toml_reader.hpp"
#include "dem/size_distribution.hpp"

#include <memory>

namespace demcal::config {

// Reads a distribution's keys (its name already read), calls finish() and builds it.
using SizeReader = std::unique_ptr<dem::SizeDistribution> (*)(reader::Table& s);
using SizeRegistry = ModelRegistry<SizeReader>;
const SizeRegistry& size_models();

}  // namespace demcal::config
