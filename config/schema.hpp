#pragma once
// What `demcal schema [NAME]` prints: every key a registered model declares,
// with its unit, default and range, generated from the declarations the readers
// themselves use (so the listing cannot drift from what is accepted):
//   - contact parts by role (dem/contact/contact_law.hpp's registry) and the
//     parameters each part declares (dem/contact/part_parameter.hpp), which
//     read_interaction reads;
//   - the physics candidates of `demcal diagnose` (config/physics_candidates.hpp);
//   - the models of every run-time selection table (config/model_registry.hpp):
//     apparatus, wall types, insertion regions, inserters, size distributions
//     and surrogate models, whose readers look their names up there.
// The command line only prints the text.

#include <string>
#include <vector>

namespace demcal::config {

// One registered key, as the schema shows it.
struct SchemaKey {
  std::string key;
  std::string unit;
  std::string default_text;  // "0 (absent: not written in)"
  std::string range_text;    // "[0, 90)"
  std::string summary;
};

// One registered model: an apparatus, a wall type, ..., a contact part, a
// physics candidate.
struct SchemaEntry {
  std::string kind;     // "apparatus", "size distribution", "contact.adhesion", "diagnosis candidate"
  std::string alias;    // a short name for the kind ("size"); "" for none
  std::string name;     // "liquid_bridge"
  std::string where;    // where its keys go
  std::vector<SchemaKey> keys;
};

// Every entry, kinds in a fixed order and names in registration order.
std::vector<SchemaEntry> schema_entries();

// The schema as text: all entries when `name` is empty, else the entries whose
// name, kind or kind's alias is `name` (a model: "sandglass", "plane",
// "log_normal", ...; a family: "apparatus", "wall", "region", "insertion",
// "size distribution" or "size", "surrogate"; a part, "contact",
// "contact.adhesion", "candidates" or a candidate's name), or "observables": the observable
// registry's table (io/observable_registry.hpp), which the full listing ends with. An unknown
// name throws ConfigError listing the names known.
std::string schema_text(const std::string& name);

}  // namespace demcal::config
