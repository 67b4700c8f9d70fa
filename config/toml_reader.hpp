#pragma once
// The strict TOML reading that every config schema shares (plain simulation
// configs, study configs): the parsed document, the --set override machinery,
// and Table, a view of one TOML table that turns every unknown key, missing
// required key, wrong type or out-of-range value into a ConfigError naming
// file, line, dotted key and what was expected. A schema is the code that
// reads it; see simulation_config.hpp and study_config.hpp.

#include "dem/air_drag.hpp"
#include "dem/contact/contact_law.hpp"
#include "dem/contact/pair_coefficients.hpp"
#include "dem/material.hpp"
#include "dem/size_distribution.hpp"
#include "dem/vec3.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace demcal::config {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A parsed config file with the overrides applied so far.
struct ConfigDocument {
  std::string file;  // as given by the user; prefixes every message
  toml::table table;
  struct Override {
    std::string text;  // e.g. "--set interaction[0].sliding_friction=0.4"
    std::size_t line;  // line reported for errors in the overridden value
  };
  // Canonical dotted path (arrays of tables by index) -> where its value came from.
  std::map<std::string, Override> overrides;
};

ConfigDocument read_config_file(const std::filesystem::path& path);
// For tests and for configs assembled in memory; `file_name` is used in messages.
ConfigDocument parse_config_string(std::string_view text, const std::string& file_name);

// Short names a schema accepts on the command line for a full dotted path
// (study configs: mu_s -> interaction.particle_particle.sliding_friction).
using OverrideAliases = std::map<std::string, std::string, std::less<>>;

// Applies one "dotted.key=value"; a key found in `aliases` stands for its path.
void apply_override(ConfigDocument& doc, std::string_view assignment,
                    const OverrideAliases& aliases = {});
// Sets one value programmatically (command-line options such as --output);
// `origin` names the option in error messages.
void set_config_value(ConfigDocument& doc, std::string_view path, toml::node&& value,
                      const std::string& origin);

// The pieces a schema reader is built from.
namespace reader {

using dem::Vec3;

inline constexpr double kInf = std::numeric_limits<double>::infinity();

std::string format_number(double v);
std::string quoted_list(const std::vector<std::string>& names);
// How a value is shown after "got": numbers bare (the user recognises their
// own input), everything else with its type since the type is usually the problem.
std::string describe_value(const toml::node& n);
std::string bracket(std::size_t i);
bool is_path_prefix(const std::string& prefix, const std::string& path);
std::size_t node_line(const toml::node& n, std::size_t fallback);
std::string vec_text(const Vec3& v);
// Levenshtein distance, for spotting misspelt keys.
std::size_t edit_distance(std::string_view a, std::string_view b);

// Numeric bounds with the wording used in messages.
struct Range {
  double lo = -kInf;
  double hi = kInf;
  bool lo_open = false;
  bool hi_open = false;

  bool contains(double v) const {
    if (!std::isfinite(v)) return false;
    if (lo_open ? !(v > lo) : !(v >= lo)) return false;
    if (hi_open ? !(v < hi) : !(v <= hi)) return false;
    return true;
  }
  std::string text() const {
    const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
    if (has_lo && has_hi)
      return "a number in " + std::string(lo_open ? "(" : "[") + format_number(lo) + ", " +
             format_number(hi) + (hi_open ? ")" : "]");
    if (has_lo) return "a number " + std::string(lo_open ? "> " : ">= ") + format_number(lo);
    if (has_hi) return "a number " + std::string(hi_open ? "< " : "<= ") + format_number(hi);
    return "a number";
  }
};

// Physical bounds of material and contact inputs: beyond them a value is a
// slip (1e6 for a friction coefficient, 1e308 kg/m3), not a material. They are
// checked after the key's own range (whose messages stay as they were), with
// the reason: Table::number_at_most.
struct Plausible {
  double max;
  const char* why;
};
inline constexpr Plausible kMaxDensity{3e4, "no material is denser; osmium: 22 590 kg/m3"};
inline constexpr Plausible kMaxModulus{1e13, "no material is stiffer; diamond: 1.2e12 Pa"};
inline constexpr Plausible kMaxFriction{10, "a friction coefficient above 10 is a slip"};

inline Range any_number() { return {}; }
inline Range at_least(double lo) { return {lo, kInf, false, false}; }
inline Range above(double lo) { return {lo, kInf, true, false}; }
inline Range between(double lo, bool lo_open, double hi, bool hi_open) {
  return {lo, hi, lo_open, hi_open};
}

struct Context {
  const ConfigDocument& doc;

  // The override that set this path or one of its ancestors (the longest).
  const ConfigDocument::Override* covering(const std::string& path) const {
    const ConfigDocument::Override* best = nullptr;
    std::size_t best_len = 0;
    for (const auto& [p, o] : doc.overrides)
      if ((p == path || is_path_prefix(p, path)) && (best == nullptr || p.size() > best_len)) {
        best = &o;
        best_len = p.size();
      }
    return best;
  }
  // An override that created something below this path.
  const ConfigDocument::Override* below(const std::string& path) const {
    for (const auto& [p, o] : doc.overrides)
      if (is_path_prefix(path, p)) return &o;
    return nullptr;
  }

  [[noreturn]] void raise(std::size_t line, const std::string& path,
                          const std::string& what) const {
    std::string note;
    if (const auto* o = covering(path)) {
      line = o->line;
      note = " (from " + o->text + ")";
    } else if (const auto* b = path.empty() ? nullptr : below(path)) {
      note = " (from " + b->text + ")";
    }
    throw ConfigError(doc.file + ":" + std::to_string(line) + ": " +
                      (path.empty() ? std::string("(top level)") : path) + ": " + what + note);
  }
};

// A view of one TOML table that remembers which keys were asked for, so that
// finish() can report every other key as unknown: the schema is whatever the
// builder reads, with no second list to keep in step.
class Table {
 public:
  Table(const Context& ctx, toml::table& t, std::string path, std::size_t line)
      : ctx_(&ctx), t_(&t), path_(std::move(path)), line_(line) {}

  const std::string& path() const { return path_; }
  std::size_t line() const { return line_; }
  std::string key_path(std::string_view key) const {
    return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  }

  [[noreturn]] void fail(std::string_view key, const std::string& what) const {
    ctx_->raise(line_of(t_->get(key)), key_path(key), what);
  }
  [[noreturn]] void fail_here(const std::string& what) const { ctx_->raise(line_, path_, what); }

  bool has(std::string_view key) { return lookup(key) != nullptr; }
  // Whether the key is present, without making it part of the schema: for a
  // key that is refused with its own message rather than as unknown.
  bool contains(std::string_view key) const { return t_->contains(key); }
  // The keys asked for so far, in order.
  const std::vector<std::string>& known_keys() const { return known_; }

  double number(std::string_view key, Range r) { return as_number(require(key, r.text()), key, r); }
  // number(), then at most `p.max` (a physical bound, refused with its reason).
  double number_at_most(std::string_view key, Range r, Plausible p) {
    const double v = number(key, r);
    if (v > p.max)
      fail(key, "expected at most " + format_number(p.max) + " (" + p.why + "), got " +
                    format_number(v));
    return v;
  }
  double number_or(std::string_view key, double fallback, Range r) {
    if (const toml::node* n = lookup(key)) return as_number(*n, key, r);
    if (std::isfinite(fallback)) t_->insert_or_assign(key, fallback);
    return fallback;
  }

  std::int64_t integer(std::string_view key, std::int64_t lo, std::int64_t hi) {
    return as_integer(require(key, integer_text(lo, hi)), key, lo, hi);
  }
  std::int64_t integer_or(std::string_view key, std::int64_t fallback, std::int64_t lo,
                          std::int64_t hi) {
    if (const toml::node* n = lookup(key)) return as_integer(*n, key, lo, hi);
    t_->insert_or_assign(key, fallback);
    return fallback;
  }

  bool boolean_or(std::string_view key, bool fallback) {
    if (const toml::node* n = lookup(key)) {
      if (!n->is_boolean()) fail(key, "expected true or false, got " + describe_value(*n));
      return *n->value<bool>();
    }
    t_->insert_or_assign(key, fallback);
    return fallback;
  }

  std::string string(std::string_view key) { return as_string(require(key, "a string"), key); }
  std::string string_or(std::string_view key, const std::string& fallback) {
    if (const toml::node* n = lookup(key)) return as_string(*n, key);
    t_->insert_or_assign(key, fallback);
    return fallback;
  }
  std::string choice(std::string_view key, const std::vector<std::string>& options) {
    return as_choice(require(key, "one of " + quoted_list(options)), key, options);
  }
  std::string choice_or(std::string_view key, const std::vector<std::string>& options,
                        const std::string& fallback) {
    if (const toml::node* n = lookup(key)) return as_choice(*n, key, options);
    t_->insert_or_assign(key, fallback);
    return fallback;
  }

  // An array of finite numbers; empty when the key is absent (nothing is written in).
  std::vector<double> numbers_or_empty(std::string_view key) {
    const toml::node* n = lookup(key);
    if (n == nullptr) return {};
    const toml::array* a = n->as_array();
    if (a == nullptr) fail(key, "expected an array of numbers, got " + describe_value(*n));
    std::vector<double> out;
    for (std::size_t i = 0; i < a->size(); ++i) {
      const auto v = (*a)[i].value<double>();
      if (!v || !std::isfinite(*v))
        fail(key, "entry " + std::to_string(i) + ": expected a finite number");
      out.push_back(*v);
    }
    return out;
  }

  // An array of strings, each one of `options` (any string when options is
  // empty), without repeats; `fallback` when the key is absent.
  std::vector<std::string> strings_or(std::string_view key, const std::vector<std::string>& options,
                                      const std::vector<std::string>& fallback) {
    const toml::node* n = lookup(key);
    const std::string expected =
        "an array of strings" +
        (options.empty() ? std::string() : ", each one of " + quoted_list(options));
    if (n == nullptr) {
      toml::array a;
      for (const auto& f : fallback) a.push_back(f);
      t_->insert_or_assign(key, std::move(a));
      return fallback;
    }
    const toml::array* a = n->as_array();
    if (a == nullptr) fail(key, "expected " + expected + ", got " + describe_value(*n));
    std::vector<std::string> out;
    for (std::size_t i = 0; i < a->size(); ++i) {
      const auto v = (*a)[i].value<std::string>();
      if (!v) fail(key, "entry " + std::to_string(i) + ": expected " + expected);
      if (!options.empty() && std::find(options.begin(), options.end(), *v) == options.end())
        fail(key, "entry " + std::to_string(i) + " is \"" + *v + "\"; expected one of " +
                      quoted_list(options));
      if (std::find(out.begin(), out.end(), *v) != out.end())
        fail(key, "\"" + *v + "\" is listed twice");
      out.push_back(*v);
    }
    return out;
  }

  Vec3 vec3(std::string_view key) { return as_vec3(require(key, kVec3Text), key); }
  Vec3 vec3_or(std::string_view key, const Vec3& fallback) {
    if (const toml::node* n = lookup(key)) return as_vec3(*n, key);
    t_->insert_or_assign(key, toml::array{fallback.x, fallback.y, fallback.z});
    return fallback;
  }
  // A direction: any non-zero length (the walls normalize).
  Vec3 direction(std::string_view key) {
    const Vec3 v = as_vec3(require(key, "a non-zero direction [x, y, z]"), key);
    if (!(dem::norm2(v) > 0.0)) fail(key, "expected a non-zero direction [x, y, z], got [0, 0, 0]");
    return v;
  }

  std::array<bool, 3> bools3_or(std::string_view key, std::array<bool, 3> fallback) {
    if (const toml::node* n = lookup(key)) {
      const toml::array* a = n->as_array();
      bool ok = a != nullptr && a->size() == 3;
      for (std::size_t k = 0; ok && k < 3; ++k) ok = (*a)[k].is_boolean();
      if (!ok) fail(key, "expected an array of 3 booleans [x, y, z], got " + describe_value(*n));
      return {*(*a)[0].value<bool>(), *(*a)[1].value<bool>(), *(*a)[2].value<bool>()};
    }
    t_->insert_or_assign(key, toml::array{fallback[0], fallback[1], fallback[2]});
    return fallback;
  }

  std::pair<std::string, std::string> string_pair(std::string_view key) {
    const std::string expected = "an array of two names [\"a\", \"b\"]";
    const toml::node& n = require(key, expected);
    const toml::array* a = n.as_array();
    if (a == nullptr || a->size() != 2 || !(*a)[0].is_string() || !(*a)[1].is_string())
      fail(key, "expected " + expected + ", got " + describe_value(n));
    return {*(*a)[0].value<std::string>(), *(*a)[1].value<std::string>()};
  }

  std::vector<std::pair<double, double>> number_pairs(std::string_view key,
                                                      const std::string& what) {
    const std::string expected = "an array of [" + what + "] pairs";
    const toml::node& n = require(key, expected);
    const toml::array* a = n.as_array();
    if (a == nullptr || a->empty())
      fail(key, "expected " + expected + ", got " + describe_value(n));
    std::vector<std::pair<double, double>> out;
    for (std::size_t i = 0; i < a->size(); ++i) {
      const toml::array* p = (*a)[i].as_array();
      if (p == nullptr || p->size() != 2 || !(*p)[0].is_number() || !(*p)[1].is_number())
        fail(key, "expected " + expected + "; entry " + std::to_string(i) + " is " +
                      describe_value((*a)[i]));
      const double first = *(*p)[0].value<double>(), second = *(*p)[1].value<double>();
      if (!std::isfinite(first) || !std::isfinite(second))
        fail(key, "entry " + std::to_string(i) + " is not finite");
      out.emplace_back(first, second);
    }
    return out;
  }

  Table table(std::string_view key) {
    const toml::node& n = require(key, "a table [" + key_path(key) + "]");
    return as_table(n, key);
  }
  // An optional table: created empty when absent so its defaults are written in.
  Table table_or_empty(std::string_view key) {
    if (const toml::node* n = lookup(key)) return as_table(*n, key);
    t_->insert_or_assign(key, toml::table{});
    return Table(*ctx_, *t_->get(key)->as_table(), key_path(key), line_);
  }
  std::vector<Table> tables(std::string_view key, bool required) {
    const toml::node* n = lookup(key);
    if (n == nullptr) {
      if (required) fail(key, "missing; expected one or more [[" + key_path(key) + "]] tables");
      return {};
    }
    toml::array* a = t_->get(key)->as_array();
    if (a == nullptr || !a->is_array_of_tables())
      fail(key, "expected an array of tables [[" + key_path(key) + "]], got " + describe_value(*n));
    if (required && a->empty()) fail(key, "expected one or more [[" + key_path(key) + "]] tables");
    std::vector<Table> out;
    for (std::size_t i = 0; i < a->size(); ++i) {
      toml::node& e = (*a)[i];
      out.emplace_back(*ctx_, *e.as_table(), key_path(key) + bracket(i), line_of(&e));
    }
    return out;
  }

  // Rejects every key that was never asked for.
  void finish() const {
    for (const auto& [k, v] : *t_) {
      const std::string_view key = k.str();
      if (std::find(known_.begin(), known_.end(), key) != known_.end()) continue;
      fail(key,
           known_.empty() ? "unknown key" : "unknown key; expected one of " + quoted_list(known_));
    }
  }

 private:
  static constexpr const char* kVec3Text = "an array of 3 numbers [x, y, z]";

  std::size_t line_of(const toml::node* n) const {
    if (n != nullptr && n->source().begin.line > 0) return n->source().begin.line;
    return line_;
  }
  const toml::node* lookup(std::string_view key) {
    if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.emplace_back(key);
    return t_->get(key);
  }
  const toml::node& require(std::string_view key, const std::string& expected) {
    if (const toml::node* n = lookup(key)) return *n;
    // A misspelt key is both unknown and leaves this one missing; "missing"
    // alone would hide the actual mistake, so point at the misspelling.
    for (const auto& [k, v] : *t_) {
      const std::string_view other = k.str();
      if (std::find(known_.begin(), known_.end(), other) == known_.end() &&
          edit_distance(other, key) <= 2)
        ctx_->raise(line_of(&v), key_path(key),
                    "missing required key; expected " + expected + "; is \"" + std::string(other) +
                        "\" a misspelling of it?");
    }
    fail(key, "missing required key; expected " + expected);
  }
  static std::string integer_text(std::int64_t lo, std::int64_t hi) {
    std::string s = "an integer";
    if (lo > std::numeric_limits<std::int64_t>::min()) s += " >= " + std::to_string(lo);
    if (hi < std::numeric_limits<std::int64_t>::max()) s += " and <= " + std::to_string(hi);
    return s;
  }
  double as_number(const toml::node& n, std::string_view key, const Range& r) const {
    std::optional<double> v;
    // 0x10, 0o20 and 0b10000 are TOML integers, but a physical quantity written
    // so is a slip (0x10 reads as 16): numbers are taken in decimal only.
    if (n.is_integer() && n.as_integer()->flags() != toml::value_flags::none)
      fail(key, "expected " + r.text() + " written in decimal, got " + describe_value(n) +
                    " written in hexadecimal, octal or binary");
    if (n.is_integer())
      v = static_cast<double>(*n.value<std::int64_t>());
    else if (n.is_floating_point())
      v = *n.value<double>();
    if (!v || !r.contains(*v)) fail(key, "expected " + r.text() + ", got " + describe_value(n));
    return *v;
  }
  std::int64_t as_integer(const toml::node& n, std::string_view key, std::int64_t lo,
                          std::int64_t hi) const {
    if (!n.is_integer() || *n.value<std::int64_t>() < lo || *n.value<std::int64_t>() > hi)
      fail(key, "expected " + integer_text(lo, hi) + ", got " + describe_value(n));
    return *n.value<std::int64_t>();
  }
  std::string as_string(const toml::node& n, std::string_view key) const {
    if (!n.is_string()) fail(key, "expected a string, got " + describe_value(n));
    return *n.value<std::string>();
  }
  std::string as_choice(const toml::node& n, std::string_view key,
                        const std::vector<std::string>& options) const {
    const std::string expected = "one of " + quoted_list(options);
    if (!n.is_string()) fail(key, "expected " + expected + ", got " + describe_value(n));
    std::string s = *n.value<std::string>();
    if (std::find(options.begin(), options.end(), s) == options.end())
      fail(key, "expected " + expected + ", got \"" + s + "\"");
    return s;
  }
  Vec3 as_vec3(const toml::node& n, std::string_view key) const {
    const toml::array* a = n.as_array();
    bool ok = a != nullptr && a->size() == 3;
    for (std::size_t k = 0; ok && k < 3; ++k) ok = (*a)[k].is_number();
    Vec3 v;
    for (int k = 0; ok && k < 3; ++k) {
      v[k] = *(*a)[static_cast<std::size_t>(k)].value<double>();
      ok = std::isfinite(v[k]);
    }
    if (!ok)
      fail(key, std::string("expected ") + kVec3Text + " (finite), got " + describe_value(n));
    return v;
  }
  Table as_table(const toml::node& n, std::string_view key) const {
    toml::node* m = t_->get(key);
    if (!n.is_table()) fail(key, "expected a table, got " + describe_value(n));
    return Table(*ctx_, *m->as_table(), key_path(key), line_of(m));
  }

  const Context* ctx_;
  toml::table* t_;
  std::string path_;
  std::size_t line_;
  std::vector<std::string> known_;  // in the order asked, for messages
};

// Runs an engine constructor and turns its std::invalid_argument (or
// out_of_range) into a ConfigError at the table the arguments came from.
template <class F>
auto guarded(const Table& t, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const ConfigError&) {
    throw;
  } catch (const std::logic_error& e) {
    t.fail_here(e.what());
  }
}

// Each component of `upper_key` must exceed the same one of `lower`.
void require_above(Table& t, std::string_view upper_key, const Vec3& lower, const Vec3& upper,
                   std::string_view lower_key);

// A size table: { distribution = "...", <that distribution's keys> }.
std::unique_ptr<dem::SizeDistribution> read_size(Table& s);

// Why `name` cannot be one component of a file name (empty, "." or "..", a
// path separator, "..", a NUL or other control character, longer than
// kMaxFileNameBytes), or "" when it can.
// Every name that becomes part of a file name is checked with it.
inline constexpr std::size_t kMaxFileNameBytes = 100;
std::string file_name_problem(std::string_view name);

// A name that also names an output directory: non-empty, no '/'.
std::string read_run_name(Table& t, std::string_view key);

// The schema pieces both config kinds share. Each reads its keys (the caller
// reads any others, e.g. a material's name, and calls finish()) and checks
// them the way the engine would, so its errors point at the key.
//   material:     density_kg_m3, youngs_modulus_pa | shear_modulus_pa, poisson_ratio
//   interaction:  restitution, sliding_friction, rolling_friction,
//                 rolling_stiffness_factor (opt), rolling_damping_ratio (opt),
//                 and every key a contact part declares (dem/contact/part_parameter.hpp;
//                 `demcal schema contact` lists them: JKR's surface_energy_j_m2, ...),
//                 each with its declared range, not written in when absent
//   contact:      normal, adhesion (opt), tangential, rolling, cdt_own_angular_velocity (opt)
//   air:          drag (opt, "none" | "schiller_naumann"), density_kg_m3 (opt, > 0),
//                 dynamic_viscosity_pa_s (opt, > 0), drag_scale (opt, >= 0; not written
//                 in when absent); calls finish(); the air when drag is on
void read_material_properties(Table& t, dem::Material& m);
dem::InteractionParameters read_interaction(Table& t);
// The keys of an interaction table given in `t` (an [interaction.particle_wall.<group>]
// table), each over the value in `base`; keys not given keep the base's. The
// same ranges as read_interaction; nothing is written in.
dem::InteractionParameters read_interaction_over(Table& t, const dem::InteractionParameters& base);
dem::ContactLawSpec read_contact(Table& t);
dem::RestitutionModel read_restitution_model(Table& t);
std::optional<dem::AirProperties> read_air(Table& t);

// The declared part parameters of an interaction table, read into `p`.
void read_part_parameters(Table& t, dem::InteractionParameters& p);

// An interaction table and what was read from it.
struct InteractionKeys {
  Table* table;
  dem::InteractionParameters values;
};
// The declared part parameters and the contact law must agree: a key whose part
// is not in the law, at a value other than its default, is refused at the key
// (it would be ignored); a part in the law needs each of its required keys in
// at least one interaction (an explicit 0 is accepted, so that a design can
// reach the "off" end), else it is refused at contact.<role>.
void check_part_parameters(Table& contact, const dem::ContactLawSpec& law,
                           const std::vector<InteractionKeys>& given);

}  // namespace reader
}  // namespace demcal::config
