#include "config/models/apparatus_models.hpp"

#include "config/run_sanity.hpp"

#include <stdexcept>
#include <string>

namespace demcal::config {

// The apparatus, in the order messages list them: one declaration and one
// call each (the function is in the apparatus' own apparatus_<name>.cpp).
void register_sandglass(ApparatusRegistry& r);
void register_conical_pile(ApparatusRegistry& r);
void register_rectangular_container(ApparatusRegistry& r);

const ApparatusRegistry& apparatus_models() {
  static const ApparatusRegistry registry = [] {
    ApparatusRegistry r({"apparatus", "",
                         "[apparatus.<name>], or [apparatus.<setup>] with type = \"<name>\""});
    register_sandglass(r);
    register_conical_pile(r);
    register_rectangular_container(r);
    return r;
  }();
  return registry;
}

namespace apparatus_reading {

using reader::Table;
using reader::above;
using reader::at_least;

const reader::Plausible kMaxLength{kMaxApparatusExtent_m, "no laboratory test is larger"};

dem::ModelReduction read_reduction(Table& t, bool slice_applies) {
  dem::ModelReduction r;
  if (slice_applies) {
    r.slice = t.boolean_or("slice", false);
    // Left alone without slice so that toggling slice with --set needs no second override.
    if (t.has("slice_thickness_diameters") || r.slice)
      r.slice_thickness_diameters =
          t.number_or("slice_thickness_diameters", r.slice_thickness_diameters, at_least(2));
  } else {
    for (const char* k : {"slice", "slice_thickness_diameters"})
      if (t.contains(k))
        t.fail(k,
               "does not apply here: the container's thickness is thickness_m or "
               "thickness_diameters, its front and rear are `boundary`");
  }
  r.coarse_graining_factor = t.number_or("coarse_graining_factor", 1.0, above(0));
  r.shear_modulus_pa = t.number_or("shear_modulus_pa", 0.0, at_least(0));
  return r;
}

std::vector<ModelKey> reduction_keys(bool slice_applies) {
  const dem::ModelReduction d;
  std::vector<ModelKey> keys;
  if (slice_applies) {
    keys.push_back({"slice", "", "false", "true | false",
                    "simulate a periodic slice through the axis instead of the whole apparatus"});
    keys.push_back({"slice_thickness_diameters", "1",
                    reader::format_number(d.slice_thickness_diameters) + " (written in with slice)",
                    ">= 2", "the slice's thickness in mean grain diameters"});
  }
  keys.push_back({"coarse_graining_factor", "1", "1", "> 0",
                  "parcel diameter over grain diameter (1: the grains themselves)"});
  keys.push_back({"shear_modulus_pa", "Pa", "0 (the material's)", ">= 0",
                  "a softened shear modulus for a longer time step; 0 keeps the material's"});
  return keys;
}

namespace {

// Where `key` occurs in `text` as a whole identifier (so that "height_m"
// does not match inside "upper_height_m").
std::size_t find_identifier(const std::string& text, const std::string& key) {
  auto ident = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  };
  for (std::size_t pos = text.find(key); pos != std::string::npos; pos = text.find(key, pos + 1)) {
    const bool before_ok = pos == 0 || !ident(text[pos - 1]);
    const std::size_t end = pos + key.size();
    const bool after_ok = end >= text.size() || !ident(text[end]);
    if (before_ok && after_ok) return pos;
  }
  return std::string::npos;
}

}  // namespace

// Constructing an apparatus checks its geometry against the fill; what it
// refuses is an input error. It is reported at the key its message names
// first (keys with an underscore: one-word keys are also plain words) (the one
// the message is about: "fill_mass_kg = ... needs more than ..."; keys named
// later are suggested remedies), else at the table.
std::unique_ptr<dem::Apparatus> build_guarded(
    const Table& t, const std::function<std::unique_ptr<dem::Apparatus>()>& make) {
  try {
    return make();
  } catch (const ConfigError&) {
    throw;
  } catch (const std::logic_error& e) {
    const std::string message = e.what();
    std::size_t best = std::string::npos;
    const std::string* key = nullptr;
    for (const std::string& k : t.known_keys()) {
      // One-word keys ("boundary", "slice") are also English words in messages.
      if (k.find('_') == std::string::npos) continue;
      const std::size_t pos = find_identifier(message, k);
      if (pos < best) {
        best = pos;
        key = &k;
      }
    }
    if (key != nullptr) t.fail(*key, message);
    t.fail_here(message);
  }
}

}  // namespace apparatus_reading
}  // namespace demcal::config
