#include "config/toml_reader.hpp"

#include "config/models/size_models.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace demcal::config {
namespace reader {

std::string format_number(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

std::string quoted_list(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "\"" : ", \"") + n + "\"";
  return s;
}

// How a value is shown after "got": numbers bare (the user recognises their
// own input), everything else with its type since the type is usually the problem.
std::string describe_value(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::integer:
      return std::to_string(*n.value<std::int64_t>());
    case toml::node_type::floating_point:
      return format_number(*n.value<double>());
    case toml::node_type::boolean:
      return std::string(*n.value<bool>() ? "true" : "false") + " (a boolean)";
    case toml::node_type::string:
      return "\"" + *n.value<std::string>() + "\" (a string)";
    case toml::node_type::array: {
      std::ostringstream s;
      s << *n.as_array();
      std::string text = s.str();
      if (text.size() > 80) text = text.substr(0, 77) + "...";
      return text + " (an array)";
    }
    case toml::node_type::table:
      return "a table";
    default:
      return "a date or time";
  }
}

// "[i]"; built by appending because GCC 12 gives a false -Wrestrict on "[" + std::string&&.
std::string bracket(std::size_t i) {
  std::string s(1, '[');
  s += std::to_string(i);
  s += ']';
  return s;
}

bool is_path_prefix(const std::string& prefix, const std::string& path) {
  return path.size() > prefix.size() && path.compare(0, prefix.size(), prefix) == 0 &&
         (path[prefix.size()] == '.' || path[prefix.size()] == '[');
}

std::size_t node_line(const toml::node& n, std::size_t fallback) {
  return n.source().begin.line > 0 ? n.source().begin.line : fallback;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// Built by appending, like bracket(), for the same false -Wrestrict.
std::string vec_text(const Vec3& v) {
  std::string s(1, '[');
  s += format_number(v.x);
  s += ", ";
  s += format_number(v.y);
  s += ", ";
  s += format_number(v.z);
  s += ']';
  return s;
}

// Each component of `upper_key` must exceed the same one of `lower`.
void require_above(Table& t, std::string_view upper_key, const Vec3& lower, const Vec3& upper,
                   std::string_view lower_key) {
  for (int k = 0; k < 3; ++k)
    if (!(upper[k] > lower[k]))
      t.fail(upper_key, "expected every component above " + std::string(lower_key) + " " +
                            vec_text(lower) + ", got " + vec_text(upper));
}

std::unique_ptr<dem::SizeDistribution> read_size(Table& s) {
  const std::string dist = s.choice("distribution", size_models().names());
  return size_models().at(dist).model(s);
}

std::string file_name_problem(std::string_view name) {
  if (name.empty()) return "it is empty";
  if (name == "." || name == "..")
    return name == "." ? "\".\" names a directory" : "\"..\" names a directory";
  for (const char c : name) {
    if (c == '/' || c == '\\') return "it holds a path separator";
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return "it holds a control character";
  }
  if (name.find("..") != std::string::npos) return "it holds \"..\"";
  // A file system takes 255 bytes per name; demcal adds to a name (<setup>.<observable>.json,
  // <study>-<candidate> of a diagnosis), so a name alone keeps well under that.
  if (name.size() > kMaxFileNameBytes)
    return "it is " + std::to_string(name.size()) + " bytes long, more than " +
           std::to_string(kMaxFileNameBytes) + " (file names take at most 255 bytes)";
  return "";
}

std::string read_run_name(Table& t, std::string_view key) {
  std::string name = t.string(key);
  if (const std::string why = file_name_problem(name); !why.empty())
    t.fail(key, "expected a non-empty name without '/' (it names the output directory), got \"" +
                    name + "\": " + why);
  return name;
}

void read_material_properties(Table& t, dem::Material& m) {
  m.density_kg_m3 = t.number_at_most("density_kg_m3", above(0), kMaxDensity);
  const bool has_e = t.has("youngs_modulus_pa");
  const bool has_g = t.has("shear_modulus_pa");
  if (!has_e && !has_g)
    t.fail("youngs_modulus_pa",
           "missing required key; expected a number > 0 (or give shear_modulus_pa)");
  if (has_e) m.youngs_modulus_pa = t.number_at_most("youngs_modulus_pa", above(0), kMaxModulus);
  if (has_g) m.shear_modulus_pa = t.number_at_most("shear_modulus_pa", above(0), kMaxModulus);
  m.poisson_ratio = t.number("poisson_ratio", between(-1, true, 0.5, true));
}

dem::InteractionParameters read_interaction(Table& t) {
  dem::InteractionParameters p;
  p.restitution = t.number("restitution", between(0, true, 1, false));
  p.sliding_friction = t.number_at_most("sliding_friction", at_least(0), kMaxFriction);
  p.rolling_friction = t.number_at_most("rolling_friction", at_least(0), kMaxFriction);
  p.rolling_stiffness_factor = t.number_or("rolling_stiffness_factor", 2.25, above(0));
  p.rolling_damping_ratio = t.number_or("rolling_damping_ratio", 0.3, at_least(0));
  read_part_parameters(t, p);
  return p;
}

Range declared_range(const dem::PartParameter& d) { return {d.lo, d.hi, d.lo_open, d.hi_open}; }

void read_part_parameters(Table& t, dem::InteractionParameters& p) {
  // Declared "not written when absent" (all so far): configs without the part
  // resolve, and hash, as before it existed.
  for (const dem::RegisteredPartParameter& r : dem::registered_part_parameters()) {
    const dem::PartParameter& d = r.parameter;
    if (d.written_when_absent)
      d.value_in(p) = t.number_or(d.key, d.default_value, declared_range(d));
    else if (t.has(d.key))
      d.value_in(p) = t.number(d.key, declared_range(d));
  }
}

dem::InteractionParameters read_interaction_over(Table& t, const dem::InteractionParameters& base) {
  dem::InteractionParameters p = base;
  if (t.has("restitution")) p.restitution = t.number("restitution", between(0, true, 1, false));
  if (t.has("sliding_friction"))
    p.sliding_friction = t.number_at_most("sliding_friction", at_least(0), kMaxFriction);
  if (t.has("rolling_friction"))
    p.rolling_friction = t.number_at_most("rolling_friction", at_least(0), kMaxFriction);
  if (t.has("rolling_stiffness_factor"))
    p.rolling_stiffness_factor = t.number("rolling_stiffness_factor", above(0));
  if (t.has("rolling_damping_ratio"))
    p.rolling_damping_ratio = t.number("rolling_damping_ratio", at_least(0));
  for (const dem::RegisteredPartParameter& r : dem::registered_part_parameters())
    if (t.has(r.parameter.key))
      r.parameter.value_in(p) = t.number(r.parameter.key, declared_range(r.parameter));
  return p;
}

std::optional<dem::AirProperties> read_air(Table& t) {
  const std::string drag = t.choice_or("drag", {"none", "schiller_naumann"}, "none");
  // Read (and checked) either way, so that --set air.drag=... toggles the drag alone.
  dem::AirProperties air;
  air.density_kg_m3 = t.number_or("density_kg_m3", air.density_kg_m3, above(0));
  air.dynamic_viscosity_pa_s =
      t.number_or("dynamic_viscosity_pa_s", air.dynamic_viscosity_pa_s, above(0));
  // The strength the diagnosis varies (1 = Schiller–Naumann's still air, 0 =
  // off, between: a partial effect such as drag screened in a dense stream).
  // Not written in when absent: configs without it resolve (and hash) as before.
  if (t.has("drag_scale")) air.drag_scale = t.number("drag_scale", at_least(0));
  t.finish();
  if (drag == "none") return std::nullopt;
  return air;
}

const std::string& part_in_role(const dem::ContactLawSpec& law, const std::string& role) {
  if (role == "normal") return law.normal;
  if (role == "adhesion") return law.adhesion;
  if (role == "tangential") return law.tangential;
  return law.rolling;
}

void check_part_parameters(Table& contact, const dem::ContactLawSpec& law,
                           const std::vector<InteractionKeys>& given) {
  for (const dem::RegisteredPartParameter& r : dem::registered_part_parameters()) {
    const dem::PartParameter& d = r.parameter;
    const std::string& selected = part_in_role(law, r.role);
    if (selected != r.part) {
      // A value the part would act on, with the part not in the law: refused
      // (it would be ignored); its default (0 for a strength) is accepted, so
      // that a design can reach the "off" end.
      for (const InteractionKeys& g : given)
        if (g.table->contains(d.key) && d.value_in(g.values) != d.default_value)
          g.table->fail(d.key, "is " + format_number(d.value_in(g.values)) + " " + d.unit +
                                   " but contact." + r.role + " is \"" + selected + "\": " +
                                   d.what + " acts only through the " + r.role + " part \"" +
                                   r.part + "\"; set contact." + r.role + " = \"" + r.part +
                                   "\" or remove this key");
      continue;
    }
    if (!d.required) continue;
    const bool found = std::any_of(given.begin(), given.end(),
                                   [&](const InteractionKeys& g) { return g.table->contains(d.key); });
    if (!found)
      contact.fail(r.role, "\"" + r.part + "\" needs " + d.what + " it acts with: give " + d.key +
                               " (" + d.unit + ", " + dem::part_parameter_range_text(d) +
                               ") in the particle-particle and/or the particle-wall interaction");
  }
}

dem::ContactLawSpec read_contact(Table& t) {
  auto part = [&](const char* role, const std::string* fallback) {
    const std::string name = fallback ? t.string_or(role, *fallback) : t.string(role);
    const auto known = dem::known_part_names(role);
    if (std::find(known.begin(), known.end(), name) == known.end())
      t.fail(role, "unknown " + std::string(role) + " part \"" + name +
                       "\"; known: " + quoted_list(known));
    return name;
  };
  const std::string no_adhesion = "none";
  dem::ContactLawSpec c;
  c.normal = part("normal", nullptr);
  c.adhesion = part("adhesion", &no_adhesion);
  c.tangential = part("tangential", nullptr);
  c.rolling = part("rolling", nullptr);
  c.cdt_own_angular_velocity = t.boolean_or("cdt_own_angular_velocity", false);
  if (c.cdt_own_angular_velocity && c.rolling != "cdt")
    t.fail("cdt_own_angular_velocity",
           "applies only to rolling = \"cdt\" (rolling is \"" + c.rolling + "\")");
  return c;
}

dem::RestitutionModel read_restitution_model(Table& t) {
  return t.choice_or("restitution_model", {"exact", "linear_spring_formula"}, "exact") == "exact"
             ? dem::RestitutionModel::kExact
             : dem::RestitutionModel::kLinearSpringFormula;
}

}  // namespace reader

using demcal::config::reader::Vec3;
using demcal::config::reader::InteractionKeys;
using demcal::config::reader::Range;
using demcal::config::reader::Table;
using demcal::config::reader::above;
using demcal::config::reader::at_least;
using demcal::config::reader::between;
using demcal::config::reader::bracket;
using demcal::config::reader::check_part_parameters;
using demcal::config::reader::describe_value;
using demcal::config::reader::edit_distance;
using demcal::config::reader::file_name_problem;
using demcal::config::reader::format_number;
using demcal::config::reader::guarded;
using demcal::config::reader::is_path_prefix;
using demcal::config::reader::kMaxDensity;
using demcal::config::reader::kMaxFriction;
using demcal::config::reader::kMaxModulus;
using demcal::config::reader::node_line;
using demcal::config::reader::quoted_list;
using demcal::config::reader::read_air;
using demcal::config::reader::read_contact;
using demcal::config::reader::read_interaction;
using demcal::config::reader::read_interaction_over;
using demcal::config::reader::read_material_properties;
using demcal::config::reader::read_part_parameters;
using demcal::config::reader::read_restitution_model;
using demcal::config::reader::read_run_name;
using demcal::config::reader::read_size;
using demcal::config::reader::require_above;
using demcal::config::reader::vec_text;

// ---------------------------------------------------------------- documents

ConfigDocument parse_config_string(std::string_view text, const std::string& file_name) {
  ConfigDocument doc;
  doc.file = file_name;
  try {
    doc.table = toml::parse(text, std::string_view(file_name));
  } catch (const toml::parse_error& e) {
    throw ConfigError(file_name + ":" + std::to_string(e.source().begin.line) + ":" +
                      std::to_string(e.source().begin.column) +
                      ": TOML syntax error: " + std::string(e.description()));
  }
  if (doc.table.empty())
    throw ConfigError(file_name +
                      ":1: the config is empty (no keys, no tables); expected a study config "
                      "([study], [material], [wall_material], [contact], [interaction], "
                      "[apparatus.<name>]) or a simulation config ([simulation], ...)");
  return doc;
}

ConfigDocument read_config_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw ConfigError(path.string() + ": is a directory; expected a TOML config file (e.g. " +
                      (path / "study.toml").string() + ")");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ConfigError(path.string() + ": cannot open the config file (" + std::strerror(errno) +
                      ")");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_config_string(text.str(), path.string());
}

namespace {

struct PathStep {
  std::string name;
  std::vector<std::size_t> indices;
};

std::vector<PathStep> split_path(std::string_view path, const std::string& file,
                                 const std::string& origin) {
  auto bad = [&](const std::string& why) -> ConfigError {
    return ConfigError(file + ": " + origin + ": bad key path \"" + std::string(path) +
                       "\": " + why);
  };
  std::vector<PathStep> steps;
  std::size_t pos = 0;
  while (pos <= path.size()) {
    const std::size_t dot = std::min(path.find('.', pos), path.size());
    std::string_view seg = path.substr(pos, dot - pos);
    PathStep step;
    const std::size_t br = std::min(seg.find('['), seg.size());
    step.name = std::string(seg.substr(0, br));
    if (step.name.empty()) throw bad("empty key");
    std::string_view rest = seg.substr(br);
    while (!rest.empty()) {
      const std::size_t close = rest.find(']');
      if (rest[0] != '[' || close == std::string_view::npos || close == 1)
        throw bad("expected [index] after \"" + step.name + "\"");
      const std::string_view digits = rest.substr(1, close - 1);
      if (!std::all_of(digits.begin(), digits.end(),
                       [](char ch) { return ch >= '0' && ch <= '9'; }))
        throw bad("index \"" + std::string(digits) + "\" is not a non-negative integer");
      step.indices.push_back(static_cast<std::size_t>(std::stoull(std::string(digits))));
      rest = rest.substr(close + 1);
    }
    steps.push_back(std::move(step));
    pos = dot + 1;
  }
  return steps;
}

// Picks the element of an array of tables named by `selector`: by its `name`
// key (for walls without one, the default "<type>-<index>"), or, for
// interactions, by the pair "a-b" in either order.
std::optional<std::size_t> select_element(const toml::array& arr, const std::string& array_key,
                                          const std::string& selector,
                                          std::vector<std::string>& candidates) {
  std::vector<std::size_t> hits;
  for (std::size_t i = 0; i < arr.size(); ++i) {
    const toml::table* t = arr[i].as_table();
    if (t == nullptr) continue;
    std::optional<std::string> name = (*t)["name"].value<std::string>();
    if (!name && array_key == "wall")
      if (auto type = (*t)["type"].value<std::string>()) name = *type + "-" + std::to_string(i);
    if (name) {
      candidates.push_back(*name);
      if (*name == selector) hits.push_back(i);
    } else if (const toml::array* m = (*t)["materials"].as_array();
               m != nullptr && m->size() == 2 && (*m)[0].is_string() && (*m)[1].is_string()) {
      const std::string a = *(*m)[0].value<std::string>(), b = *(*m)[1].value<std::string>();
      candidates.push_back(a + "-" + b);
      // Material names may contain '-', so try every split point.
      for (std::size_t cut = selector.find('-'); cut != std::string::npos;
           cut = selector.find('-', cut + 1)) {
        const std::string x = selector.substr(0, cut), y = selector.substr(cut + 1);
        if ((x == a && y == b) || (x == b && y == a)) {
          hits.push_back(i);
          break;
        }
      }
    }
  }
  if (hits.size() == 1) return hits[0];
  return std::nullopt;
}

}  // namespace

void set_config_value(ConfigDocument& doc, std::string_view path, toml::node&& value,
                      const std::string& origin) {
  const std::vector<PathStep> steps = split_path(path, doc.file, origin);
  auto fail = [&](std::size_t line, const std::string& at, const std::string& why) {
    throw ConfigError(doc.file + ":" + std::to_string(line) + ": " + at + ": " + why + " (" +
                      origin + ")");
  };
  auto record = [&](const std::string& canon, std::size_t line) {
    if (auto it = doc.overrides.find(canon); it != doc.overrides.end()) {
      // Two --set of one key (perhaps one by its alias) would let the later win unseen:
      // which value the user meant is not ours to guess.
      const auto from_command_line = [](const std::string& o) { return o.rfind("--set ", 0) == 0; };
      if (from_command_line(origin) && from_command_line(it->second.text))
        throw ConfigError(doc.file + ": " + origin + ": sets " + canon + ", which " +
                          it->second.text + " already sets; give each key once");
      // A path set twice keeps the line of the original key.
      line = it->second.line;
    }
    doc.overrides[canon] = {origin, line};
  };

  toml::node* cur = &doc.table;
  std::string canon;
  std::string array_key;  // the key of the array `cur` is, for selecting by name
  std::size_t line = node_line(doc.table, 1);
  for (std::size_t s = 0; s < steps.size(); ++s) {
    const PathStep& step = steps[s];
    const bool last_step = s + 1 == steps.size();
    if (toml::table* t = cur->as_table()) {
      const std::string next_canon = canon.empty() ? step.name : canon + "." + step.name;
      toml::node* next = t->get(step.name);
      if (last_step && step.indices.empty()) {
        // An absent key is added; the strict build rejects it if the schema does not know it.
        record(next_canon, next != nullptr ? node_line(*next, line) : line);
        t->insert_or_assign(step.name, std::move(value));
        return;
      }
      if (next == nullptr) {
        if (!step.indices.empty()) fail(line, next_canon, "no such key to index");
        // Optional tables such as [output] may be absent from the file.
        t->insert_or_assign(step.name, toml::table{});
        next = t->get(step.name);
      }
      cur = next;
      canon = next_canon;
      array_key = step.name;
      line = node_line(*cur, line);
    } else if (toml::array* a = cur->as_array(); a != nullptr && a->is_array_of_tables()) {
      std::vector<std::string> candidates;
      const auto i = select_element(*a, array_key, step.name, candidates);
      if (!i)
        fail(line, canon + "." + step.name,
             "selects no single [[" + canon + "]] table; " +
                 (candidates.empty() ? std::string("these tables have no names")
                                     : "selectors here are " + quoted_list(candidates)) +
                 "; or use " + canon + "[index]");
      if (last_step && step.indices.empty())
        fail(line, canon + "." + step.name, "names a whole table; give a key inside it");
      cur = &(*a)[*i];
      canon += bracket(*i);
      line = node_line(*cur, line);
    } else {
      fail(line, canon,
           std::string("is a ") + (cur->is_array() ? "value array" : "value") +
               " and has no key \"" + step.name + "\"" +
               (cur->is_array() ? "; index it as " + canon + "[0]" : ""));
    }
    for (std::size_t k = 0; k < step.indices.size(); ++k) {
      const std::size_t idx = step.indices[k];
      toml::array* arr = cur->as_array();
      if (arr == nullptr) fail(line, canon, "is not an array; it cannot be indexed");
      if (idx >= arr->size())
        fail(line, canon + bracket(idx),
             "index out of range; there " + std::string(arr->size() == 1 ? "is " : "are ") +
                 std::to_string(arr->size()));
      canon += bracket(idx);
      toml::node& elem = (*arr)[idx];
      if (last_step && k + 1 == step.indices.size()) {
        record(canon, node_line(elem, line));
        arr->replace(arr->cbegin() + static_cast<std::ptrdiff_t>(idx), std::move(value));
        return;
      }
      cur = &elem;
      line = node_line(*cur, line);
    }
  }
}

void apply_override(ConfigDocument& doc, std::string_view assignment,
                    const OverrideAliases& aliases) {
  const std::string origin = "--set " + std::string(assignment);
  const std::size_t eq = assignment.find('=');
  auto trim = [](std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
  };
  if (eq == std::string_view::npos)
    throw ConfigError(doc.file + ": " + origin + ": expected key=value");
  std::string_view path = trim(assignment.substr(0, eq));
  if (auto a = aliases.find(path); a != aliases.end()) path = a->second;
  const std::string text(trim(assignment.substr(eq + 1)));
  toml::table parsed;
  try {
    parsed = toml::parse(std::string_view("v = " + text), std::string_view("--set"));
  } catch (const toml::parse_error& e) {
    // Bare words (paths, names) are strings; anything with TOML punctuation was meant as TOML.
    if (text.empty() || text.find_first_of("\"'[]{}=,#\n") != std::string::npos)
      throw ConfigError(doc.file + ": " + origin + ": the value is not valid TOML (" +
                        std::string(e.description()) + "); quote strings, e.g. name=\"pile\"");
    parsed.insert_or_assign("v", text);
  }
  set_config_value(doc, path, std::move(*parsed.get("v")), origin);
}

}  // namespace demcal::config
