// Every registered family, for `demcal schema` (config/schema.cpp).

#include "config/model_registry.hpp"
#include "config/models/apparatus_models.hpp"
#include "config/models/insertion_models.hpp"
#include "config/models/size_models.hpp"
#include "config/models/surrogate_models.hpp"
#include "config/models/wall_models.hpp"

namespace demcal::config {

std::vector<ModelFamilyListing> model_families() {
  return {listing_of(apparatus_models()), listing_of(wall_models()),
          listing_of(region_models()),    listing_of(inserter_models()),
          listing_of(size_models()),      listing_of(surrogate_models())};
}

}  // namespace demcal::config
