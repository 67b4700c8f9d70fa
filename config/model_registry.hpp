#pragma once
// A run-time selection table (OpenFOAM's, LAMMPS's styles): the models of one
// family — apparatus, wall types, inserters, insertion regions, size
// distributions, surrogate models — each registered by name with its reader
// and the keys that reader reads. A config reader turns a name into a model by
// looking it up here, never by an if/else chain on the name; the list of names
// a `choice` error offers is the registry's, in registration order; and
// `demcal schema` prints the declarations (config/schema.cpp), which a unit
// test (tests/unit/test_model_registry.cpp) holds to what each reader actually
// reads (reader::Table::known_keys()), so the listing cannot drift.
//
// A family's registry is built on first use by a function that calls one
// registration function per model (config/models/*_models.cpp): explicit calls
// rather than static registrar objects, which a static library's linker would
// drop with the object file that holds them. A duplicate name is refused.

#include "config/toml_reader.hpp"

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace demcal::config {

// One key a model reads, as the schema shows it.
struct ModelKey {
  std::string key;           // "orifice_diameter_m"
  std::string unit;          // "m"; "" for a name, a flag or a count
  std::string default_text;  // "required", "0.5", "absent: not written in"
  std::string range_text;    // "> 0", "\"flat\" | \"conical\""
  std::string summary;       // one line
};

// A Range as the schema shows it: "> 0", "[0, 1)" (the text of the same Range
// the reader checks the key with, so the two cannot differ).
inline std::string range_of(const reader::Range& r) {
  std::string s = r.text();
  for (const char* prefix : {"a number in ", "a number "})
    if (s.rfind(prefix, 0) == 0) return s.substr(std::string(prefix).size());
  return s == "a number" ? "any number" : s;
}

// What a family knows of a model besides its reader.
struct ModelInfo {
  std::string name;     // "sandglass"
  std::string summary;  // one line
  std::vector<ModelKey> keys;
};

// A family's description, shared by its models.
struct ModelFamily {
  std::string kind;    // "apparatus", "size distribution"
  std::string alias;   // a short name for `demcal schema` ("size"); "" for none
  std::string where;   // where a model's keys go; "<name>" stands for the model's name
};

// The registry of one family. Model is what the family keeps of a model: its
// reader (a plain function pointer: a reader is a free function in its model's
// file), and for apparatus also its wall groups.
template <class Model>
class ModelRegistry {
 public:
  struct Entry {
    ModelInfo info;
    Model model;
  };

  explicit ModelRegistry(ModelFamily family) : family_(std::move(family)) {}

  const ModelFamily& family() const { return family_; }

  // Refuses a second model of the same name (std::logic_error: a programming
  // error, found by the first use of the family).
  void add(ModelInfo info, Model model) {
    if (info.name.empty()) throw std::logic_error(family_.kind + ": a model needs a name");
    if (find(info.name) != nullptr)
      throw std::logic_error(family_.kind + " \"" + info.name + "\" is registered twice");
    entries_.push_back({std::move(info), model});
  }

  // The model called `name`, or nullptr.
  const Entry* find(const std::string& name) const {
    for (const Entry& e : entries_)
      if (e.info.name == name) return &e;
    return nullptr;
  }
  // The model called `name`; an unknown name is a ConfigError listing the known
  // ones (readers normally get the name through Table::choice(key, names()),
  // which refuses it first, at the key).
  const Entry& at(const std::string& name) const {
    if (const Entry* e = find(name)) return *e;
    throw ConfigError(family_.kind + ": unknown name \"" + name + "\"; expected one of " +
                      reader::quoted_list(names()));
  }

  // The names in registration order: the order error messages list them in.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    out.reserve(entries_.size());
    for (const Entry& e : entries_) out.push_back(e.info.name);
    return out;
  }
  const std::vector<Entry>& entries() const { return entries_; }

 private:
  ModelFamily family_;
  std::vector<Entry> entries_;
};

// One family's declarations without its reader type, for `demcal schema`.
struct ModelFamilyListing {
  ModelFamily family;
  std::vector<ModelInfo> models;
};

template <class Model>
ModelFamilyListing listing_of(const ModelRegistry<Model>& r) {
  ModelFamilyListing l{r.family(), {}};
  for (const auto& e : r.entries()) l.models.push_back(e.info);
  return l;
}

// Every registered family (apparatus, wall, region, insertion, size
// distribution, surrogate), in that order (config/models/model_families.cpp).
std::vector<ModelFamilyListing> model_families();

}  // namespace demcal::config
