#pragma once
// What a simulation config's [[insertion]] tables name, registered by name
// (config/model_registry.hpp): the inserters (type = "pour" | "fill") and the
// shapes of their [insertion.region] (shape = "box" | "cylinder").

#include "config/model_registry.hpp"
#include "config/toml_reader.hpp"
#include "dem/insertion/inserter.hpp"
#include "dem/insertion/region.hpp"
#include "dem/size_distribution.hpp"

#include <memory>

namespace demcal::config {

// Reads a region's keys (its shape already read), calls finish() and builds it.
using RegionReader = std::unique_ptr<dem::Region> (*)(reader::Table& r);
using RegionRegistry = ModelRegistry<RegionReader>;
const RegionRegistry& region_models();

// What the [[insertion]] reader has read before an inserter's own keys.
struct InsertionCommon {
  int material = 0;
  double density_kg_m3 = 0.0;
  dem::InsertionAmount amount;
  dem::Vec3 gravity_m_s2;
};

// Reads an inserter's own keys, calls finish() and builds it.
using InserterReader = std::unique_ptr<dem::Inserter> (*)(
    reader::Table& t, const InsertionCommon& common, std::unique_ptr<dem::Region> region,
    std::unique_ptr<dem::SizeDistribution> sizes);
using InserterRegistry = ModelRegistry<InserterReader>;
const InserterRegistry& inserter_models();

}  // namespace demcal::config
