#pragma once
// The wall types of a simulation config's [[wall]] tables, registered by name
// (config/model_registry.hpp); each reads its geometry keys (the [[wall]]
// reader reads type, material, name and the motion keys around it).

#include "config/model_registry.hpp"
#include "config/toml_reader.hpp"
#include "dem/wall/wall.hpp"

#include <memory>

namespace demcal::config {

// Reads a wall's geometry keys and builds it (no finish(): the caller reads
// the motion keys after it).
using WallReader = std::unique_ptr<dem::Wall> (*)(reader::Table& w);

using WallRegistry = ModelRegistry<WallReader>;
const WallRegistry& wall_models();

}  // namespace demcal::config
