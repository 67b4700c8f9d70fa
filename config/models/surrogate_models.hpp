#pragma once
// The surrogate models of a study's [surrogate] table (model = "<name>"),
// registered by name (config/model_registry.hpp). A model's keys given with
// another model are refused at the key ("applies only to model = ...").

#include "config/model_registry.hpp"
#include "config/toml_reader.hpp"
#include "surrogate/surrogate_fit.hpp"

namespace demcal::config {

// Reads a model's own keys into `spec` (the [surrogate] reader reads model and
// observables, and calls finish()).
using SurrogateReader = void (*)(reader::Table& t, surrogate::SurrogateSpec& spec);
using SurrogateRegistry = ModelRegistry<SurrogateReader>;
const SurrogateRegistry& surrogate_models();

}  // namespace demcal::config
