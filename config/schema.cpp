#include "config/schema.hpp"

#include "io/observable_registry.hpp"

#include "config/model_registry.hpp"
#include "config/physics_candidates.hpp"
#include "config/toml_reader.hpp"
#include "dem/contact/contact_law.hpp"

#include <algorithm>
#include <cstddef>
#include <set>
#include <sstream>

namespace demcal::config {

namespace {

std::string exponent_text(double e) {
  if (e == 0.0) return "";
  return "; coarse grained as f^" + reader::format_number(e);
}

void add_contact_parts(std::vector<SchemaEntry>& out) {
  const auto& declared = dem::registered_part_parameters();
  for (const std::string& role : dem::contact_roles())
    for (const std::string& part : dem::known_part_names(role)) {
      SchemaEntry e;
      e.kind = "contact." + role;
      e.name = part;
      e.where = "[contact] " + role + " = \"" + part +
                "\"; its keys in each interaction table ([interaction.particle_particle], "
                "[interaction.particle_wall], [[interaction]])";
      for (const dem::RegisteredPartParameter& r : declared) {
        if (r.role != role || r.part != part) continue;
        const dem::PartParameter& d = r.parameter;
        SchemaKey k;
        k.key = d.key;
        k.unit = d.unit;
        k.default_text = reader::format_number(d.default_value) +
                         (d.written_when_absent ? "" : " (absent: not written in)") +
                         (d.required ? "; required in at least one interaction" : "");
        k.range_text = dem::part_parameter_range_text(d);
        k.summary = std::string(d.summary) + exponent_text(d.coarse_graining_exponent);
        e.keys.push_back(std::move(k));
      }
      out.push_back(std::move(e));
    }
}

void add_candidates(std::vector<SchemaEntry>& out) {
  for (const PhysicsCandidate& c : physics_candidates()) {
    SchemaEntry e;
    e.kind = "diagnosis candidate";
    e.name = c.name;
    e.where = "[diagnosis] candidates = [\"" + c.name + "\", ...]; range and probe in [diagnosis." +
              c.name + "]";
    SchemaKey k;
    k.key = c.parameter;
    std::string sets;
    for (const std::string& key : c.keys) sets += (sets.empty() ? "" : ", ") + key;
    for (const auto& [key, value] : c.switches) sets += "; switches " + key + " = \"" + value + "\"";
    k.unit = "";
    k.default_text = c.off_value ? "off at " + reader::format_number(*c.off_value)
                                 : std::string("off at the study's value");
    k.range_text = "[" + reader::format_number(c.lower) + ", " + reader::format_number(c.upper) + "]";
    k.summary = c.summary + "; sets " + sets;
    e.keys.push_back(std::move(k));
    out.push_back(std::move(e));
  }
}

// The run-time selection tables (config/model_registry.hpp): apparatus, walls,
// insertion regions and inserters, size distributions, surrogate models.
void add_models(std::vector<SchemaEntry>& out) {
  for (const ModelFamilyListing& f : model_families())
    for (const ModelInfo& m : f.models) {
      SchemaEntry e;
      e.kind = f.family.kind;
      e.alias = f.family.alias;
      e.name = m.name;
      e.where = f.family.where;
      for (std::size_t p = e.where.find("<name>"); p != std::string::npos;
           p = e.where.find("<name>", p + m.name.size()))
        e.where.replace(p, 6, m.name);
      e.where += "; " + m.summary;
      for (const ModelKey& k : m.keys)
        e.keys.push_back({k.key, k.unit, k.default_text, k.range_text, k.summary});
      out.push_back(std::move(e));
    }
}

}  // namespace

std::vector<SchemaEntry> schema_entries() {
  std::vector<SchemaEntry> out;
  add_models(out);
  add_contact_parts(out);
  add_candidates(out);
  return out;
}

std::string schema_text(const std::string& name) {
  // The observables are a table of their own (name, unit, range, the apparatus that measure
  // them: io/observable_registry.hpp), not keys of a model.
  const std::string observables =
      "observables (what a recording, a design table or a surrogate may name)\n" +
      io::observable_registry_table();
  if (name == "observables") return observables;
  const std::vector<SchemaEntry> all = schema_entries();
  const auto wanted = [&](const SchemaEntry& e) {
    return name.empty() || e.name == name || e.kind == name || (!e.alias.empty() && e.alias == name) ||
           (name == "contact" && e.kind.rfind("contact.", 0) == 0) ||
           (name == "candidates" && e.kind == "diagnosis candidate");
  };
  if (std::none_of(all.begin(), all.end(), wanted)) {
    std::set<std::string> known = {"contact", "candidates", "observables"};
    for (const SchemaEntry& e : all) {
      known.insert(e.name);
      known.insert(e.kind);
      if (!e.alias.empty()) known.insert(e.alias);
    }
    known.erase("diagnosis candidate");
    throw ConfigError("schema: unknown name \"" + name + "\"; known: " +
                      reader::quoted_list(std::vector<std::string>(known.begin(), known.end())));
  }
  std::ostringstream s;
  for (const SchemaEntry& e : all) {
    if (!wanted(e)) continue;
    s << e.kind << " \"" << e.name << "\"\n  " << e.where << "\n";
    if (e.keys.empty()) s << "  (no keys of its own)\n";
    for (const SchemaKey& k : e.keys) {
      s << "  " << k.key;
      if (!k.unit.empty()) s << " [" << k.unit << "]";
      s << "  range " << k.range_text << "  default " << k.default_text << "\n      " << k.summary
        << "\n";
    }
  }
  if (name.empty()) s << "\n" << observables;
  return s.str();
}

}  // namespace demcal::config
