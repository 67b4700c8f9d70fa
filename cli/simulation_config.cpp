#include "cli/simulation_config.hpp"

#include "dem/contact/contact_law.hpp"
#include "dem/insertion/inserter.hpp"
#include "dem/insertion/region.hpp"
#include "dem/size_distribution.hpp"
#include "dem/wall/bounded_plane_wall.hpp"
#include "dem/wall/cone_wall.hpp"
#include "dem/wall/cylinder_wall.hpp"
#include "dem/wall/orifice_plate_wall.hpp"
#include "dem/wall/plane_wall.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <utility>

namespace demcal::cli {
namespace {

using dem::Vec3;

constexpr double kInf = std::numeric_limits<double>::infinity();

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

Range any_number() { return {}; }
Range at_least(double lo) { return {lo, kInf, false, false}; }
Range above(double lo) { return {lo, kInf, true, false}; }
Range between(double lo, bool lo_open, double hi, bool hi_open) {
  return {lo, hi, lo_open, hi_open};
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

  double number(std::string_view key, Range r) { return as_number(require(key, r.text()), key, r); }
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

std::string vec_text(const Vec3& v) {
  return "[" + format_number(v.x) + ", " + format_number(v.y) + ", " + format_number(v.z) + "]";
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
  const std::string dist = s.choice(
      "distribution", {"monodisperse", "uniform", "truncated_normal", "log_normal", "sieve"});
  auto bounds = [&] {
    const double lo = s.number("min_diameter_m", above(0));
    const double hi = s.number("max_diameter_m", above(0));
    if (hi < lo)
      s.fail("max_diameter_m", "expected a number >= min_diameter_m (" + format_number(lo) +
                                   "), got " + format_number(hi));
    return std::pair{lo, hi};
  };
  std::unique_ptr<dem::SizeDistribution> out;
  if (dist == "monodisperse") {
    const double d = s.number("diameter_m", above(0));
    s.finish();
    out = guarded(s, [&] { return dem::make_monodisperse(d); });
  } else if (dist == "uniform") {
    const auto [lo, hi] = bounds();
    s.finish();
    out = guarded(s, [&] { return dem::make_uniform(lo, hi); });
  } else if (dist == "truncated_normal") {
    const double mean = s.number("mean_diameter_m", above(0));
    const double sd = s.number("std_dev_m", at_least(0));
    const auto [lo, hi] = bounds();
    s.finish();
    out = guarded(s, [&] { return dem::make_truncated_normal(mean, sd, lo, hi); });
  } else if (dist == "log_normal") {
    const double median = s.number("median_diameter_m", above(0));
    const double sigma = s.number("sigma_ln", at_least(0));
    const auto [lo, hi] = bounds();
    s.finish();
    out = guarded(s, [&] { return dem::make_log_normal(median, sigma, lo, hi); });
  } else {
    auto curve = s.number_pairs("sieve", "opening_m, cumulative_fraction_passing");
    s.finish();
    out = guarded(s, [&] { return dem::make_sieve_curve(std::move(curve)); });
  }
  return out;
}

std::unique_ptr<dem::Region> read_region(Table& r, const dem::Domain& domain) {
  const std::string shape = r.choice("shape", {"box", "cylinder"});
  std::unique_ptr<dem::Region> out;
  if (shape == "box") {
    const Vec3 lo = r.vec3("lower_m");
    const Vec3 hi = r.vec3("upper_m");
    require_above(r, "upper_m", lo, hi, "lower_m");
    r.finish();
    out = guarded(r, [&] { return dem::make_box_region(lo, hi); });
  } else {
    const Vec3 base = r.vec3("base_centre_m");
    const double radius = r.number("radius_m", above(0));
    const double height = r.number("height_m", above(0));
    r.finish();
    out = guarded(r, [&] { return dem::make_cylinder_region(base, radius, height); });
  }
  // A particle placed outside the box along a bounded axis would stop the run
  // on its first step with a message about escaping walls; say it here instead.
  static const char* const kAxis[] = {"x", "y", "z"};
  const Vec3 lo = out->lower_m(), hi = out->upper_m();
  for (int k = 0; k < 3; ++k)
    if (!domain.periodic[k] && (lo[k] < domain.lower_m[k] || hi[k] > domain.upper_m[k]))
      r.fail_here("the region " + vec_text(lo) + " - " + vec_text(hi) +
                  " reaches outside the domain along " + kAxis[k] + " ([" +
                  format_number(domain.lower_m[k]) + ", " + format_number(domain.upper_m[k]) +
                  "])");
  return out;
}

std::unique_ptr<dem::Wall> read_wall_geometry(Table& w, const std::string& type) {
  if (type == "plane") {
    const Vec3 p = w.vec3("point_m");
    const Vec3 n = w.direction("normal");
    return guarded(w, [&] { return std::make_unique<dem::PlaneWall>(p, n); });
  }
  if (type == "rectangle") {
    const Vec3 c = w.vec3("centre_m");
    const Vec3 n = w.direction("normal");
    const Vec3 u = w.direction("axis_u");
    const double hu = w.number("half_length_u_m", above(0));
    const double hv = w.number("half_length_v_m", above(0));
    return guarded(w, [&] { return std::make_unique<dem::RectangleWall>(c, n, u, hu, hv); });
  }
  if (type == "disk") {
    const Vec3 c = w.vec3("centre_m");
    const Vec3 n = w.direction("normal");
    const double r = w.number("radius_m", above(0));
    return guarded(w, [&] { return std::make_unique<dem::DiskWall>(c, n, r); });
  }
  if (type == "cylinder") {
    const Vec3 b = w.vec3("base_m");
    const Vec3 a = w.direction("axis");
    const double len = w.number("length_m", above(0));
    const double r = w.number("radius_m", above(0));
    return guarded(w, [&] { return std::make_unique<dem::CylinderWall>(b, a, len, r); });
  }
  if (type == "cone") {
    const Vec3 b = w.vec3("base_m");
    const Vec3 a = w.direction("axis");
    const double len = w.number("length_m", above(0));
    const double r0 = w.number("radius_base_m", at_least(0));
    const double r1 = w.number("radius_end_m", at_least(0));
    if (r0 == 0.0 && r1 == 0.0)
      w.fail("radius_end_m", "radius_base_m and radius_end_m cannot both be 0");
    return guarded(w, [&] { return std::make_unique<dem::ConeWall>(b, a, len, r0, r1); });
  }
  // orifice_plate
  const Vec3 c = w.vec3("centre_m");
  const Vec3 n = w.direction("normal");
  const double open_s = w.number("open_time_s", any_number());
  const bool circle = w.has("diameter_m");
  const bool slot = w.has("width_m");
  if (circle && slot)
    w.fail("width_m", "give diameter_m (a circular hole) or width_m (a slot), not both");
  if (!circle && !slot)
    w.fail(
        "diameter_m",
        "missing required key; expected diameter_m (a circular hole) or width_m + axis_u (a slot)");
  const double opening = w.number(circle ? "diameter_m" : "width_m", above(0));
  const Vec3 u = slot ? w.direction("axis_u") : w.vec3_or("axis_u", Vec3{});
  const double outer = w.number_or("outer_radius_m", 0.0, at_least(0));
  const auto shape = circle ? dem::OrificeShape::circle : dem::OrificeShape::slot;
  return guarded(w, [&] {
    return std::make_unique<dem::OrificePlateWall>(c, n, u, shape, opening, open_s, outer);
  });
}

}  // namespace

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
  return doc;
}

ConfigDocument read_config_file(const std::filesystem::path& path) {
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

std::size_t node_line(const toml::node& n, std::size_t fallback) {
  return n.source().begin.line > 0 ? n.source().begin.line : fallback;
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
    // A path set twice keeps the line of the original key.
    if (auto it = doc.overrides.find(canon); it != doc.overrides.end()) line = it->second.line;
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

void apply_override(ConfigDocument& doc, std::string_view assignment) {
  const std::string origin = "--set " + std::string(assignment);
  const std::size_t eq = assignment.find('=');
  auto trim = [](std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
  };
  if (eq == std::string_view::npos)
    throw ConfigError(doc.file + ": " + origin + ": expected key=value");
  const std::string_view path = trim(assignment.substr(0, eq));
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

// ---------------------------------------------------------------- building

SimulationConfig build_simulation(ConfigDocument&& doc) {
  const Context ctx{doc};
  Table root(ctx, doc.table, "", node_line(doc.table, 1));
  // Unknown top-level tables first: a misspelt [simulation] would otherwise be
  // reported as a missing one.
  for (const char* k : {"simulation", "domain", "contact", "material", "interaction", "wall",
                        "insertion", "run", "output"})
    root.has(k);
  root.finish();

  SimulationConfig out;
  out.file = doc.file;

  // [simulation]
  Table sim_t = root.table("simulation");
  out.name = sim_t.string("name");
  if (out.name.empty() || out.name == "." || out.name == ".." ||
      out.name.find_first_of("/\\") != std::string::npos)
    sim_t.fail("name",
               "expected a non-empty name without '/' (it names the output directory), got \"" +
                   out.name + "\"");
  dem::SimulationOptions opt;
  opt.seed = static_cast<std::uint64_t>(
      sim_t.integer_or("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  opt.threads = static_cast<int>(sim_t.integer_or("threads", 1, 1, 4096));
  opt.gravity_m_s2 = sim_t.vec3_or("gravity_m_s2", Vec3{0, 0, -9.81});
  opt.time_step_s = sim_t.number_or("time_step_s", 0.0, at_least(0));
  opt.time_step_fraction_of_rayleigh =
      sim_t.number_or("time_step_fraction_of_rayleigh", 0.2, between(0, true, 1, false));
  opt.skin_fraction_of_diameter = sim_t.number_or("skin_fraction_of_diameter", 0.3, above(0));
  opt.restitution_model =
      sim_t.choice_or("restitution_model", {"exact", "linear_spring_formula"}, "exact") == "exact"
          ? dem::RestitutionModel::kExact
          : dem::RestitutionModel::kLinearSpringFormula;
  opt.max_speed_m_s = sim_t.number_or("max_speed_m_s", 0.0, at_least(0));
  sim_t.finish();

  // [domain]
  Table dom_t = root.table("domain");
  opt.domain.lower_m = dom_t.vec3("lower_m");
  opt.domain.upper_m = dom_t.vec3("upper_m");
  require_above(dom_t, "upper_m", opt.domain.lower_m, opt.domain.upper_m, "lower_m");
  opt.domain.periodic = dom_t.bools3_or("periodic", {false, false, false});
  dom_t.finish();

  // [contact]
  Table con_t = root.table("contact");
  auto part = [&](const char* role, const std::string* fallback) {
    const std::string name = fallback ? con_t.string_or(role, *fallback) : con_t.string(role);
    const auto known = dem::known_part_names(role);
    if (std::find(known.begin(), known.end(), name) == known.end())
      con_t.fail(role, "unknown " + std::string(role) + " part \"" + name +
                           "\"; known: " + quoted_list(known));
    return name;
  };
  const std::string no_adhesion = "none";
  opt.contact.normal = part("normal", nullptr);
  opt.contact.adhesion = part("adhesion", &no_adhesion);
  opt.contact.tangential = part("tangential", nullptr);
  opt.contact.rolling = part("rolling", nullptr);
  opt.contact.cdt_own_angular_velocity = con_t.boolean_or("cdt_own_angular_velocity", false);
  if (opt.contact.cdt_own_angular_velocity && opt.contact.rolling != "cdt")
    con_t.fail("cdt_own_angular_velocity",
               "applies only to rolling = \"cdt\" (rolling is \"" + opt.contact.rolling + "\")");
  con_t.finish();

  const dem::Domain domain = opt.domain;
  const Vec3 gravity = opt.gravity_m_s2;
  auto sim = guarded(sim_t, [&] { return std::make_unique<dem::Simulation>(std::move(opt)); });

  // [[material]]
  std::vector<Table> mat_ts = root.tables("material", true);
  std::vector<std::string> material_names;
  for (Table& m : mat_ts) {
    dem::Material mat;
    mat.name = m.string("name");
    if (mat.name.empty()) m.fail("name", "expected a non-empty string");
    for (std::size_t j = 0; j < material_names.size(); ++j)
      if (material_names[j] == mat.name)
        m.fail("name", "material \"" + mat.name + "\" is already defined at line " +
                           std::to_string(mat_ts[j].line()));
    mat.density_kg_m3 = m.number("density_kg_m3", above(0));
    const bool has_e = m.has("youngs_modulus_pa");
    const bool has_g = m.has("shear_modulus_pa");
    if (!has_e && !has_g)
      m.fail("youngs_modulus_pa",
             "missing required key; expected a number > 0 (or give shear_modulus_pa)");
    if (has_e) mat.youngs_modulus_pa = m.number("youngs_modulus_pa", above(0));
    if (has_g) mat.shear_modulus_pa = m.number("shear_modulus_pa", above(0));
    mat.poisson_ratio = m.number("poisson_ratio", between(-1, true, 0.5, true));
    m.finish();
    guarded(m, [&] { return sim->add_material(mat); });
    material_names.push_back(mat.name);
  }
  auto material = [&](Table& t, std::string_view key, const std::string& name) {
    for (std::size_t i = 0; i < material_names.size(); ++i)
      if (material_names[i] == name) return static_cast<int>(i);
    t.fail(key, "unknown material \"" + name + "\"; defined: " + quoted_list(material_names));
  };

  // [[interaction]]
  std::vector<Table> int_ts = root.tables("interaction", true);
  std::map<std::pair<int, int>, std::size_t> given;  // pair -> line
  for (Table& t : int_ts) {
    const auto [na, nb] = t.string_pair("materials");
    const int a = material(t, "materials", na);
    const int b = material(t, "materials", nb);
    const auto key = std::minmax(a, b);
    if (auto it = given.find(key); it != given.end())
      t.fail("materials", "the pair \"" + na + "\"-\"" + nb + "\" is already given at line " +
                              std::to_string(it->second));
    given[key] = t.line();
    dem::InteractionParameters p;
    p.restitution = t.number("restitution", between(0, true, 1, false));
    p.sliding_friction = t.number("sliding_friction", at_least(0));
    p.rolling_friction = t.number("rolling_friction", at_least(0));
    p.rolling_stiffness_factor = t.number_or("rolling_stiffness_factor", 2.25, above(0));
    p.rolling_damping_ratio = t.number_or("rolling_damping_ratio", 0.3, at_least(0));
    t.finish();
    guarded(t, [&] { sim->set_interaction(a, b, p); });
  }

  // [[wall]]
  std::vector<Table> wall_ts = root.tables("wall", false);
  std::vector<int> wall_material;
  for (std::size_t i = 0; i < wall_ts.size(); ++i) {
    Table& w = wall_ts[i];
    const std::string type =
        w.choice("type", {"plane", "rectangle", "disk", "cylinder", "cone", "orifice_plate"});
    const int mat = material(w, "material", w.string("material"));
    const std::string name = w.string_or("name", type + "-" + std::to_string(i));
    if (name.empty()) w.fail("name", "expected a non-empty string");
    for (std::size_t j = 0; j < out.wall_names.size(); ++j)
      if (out.wall_names[j] == name)
        w.fail("name", "wall \"" + name + "\" is already defined at line " +
                           std::to_string(wall_ts[j].line()));
    std::unique_ptr<dem::Wall> wall = read_wall_geometry(w, type);
    dem::WallMotion motion;
    motion.velocity_m_s = w.vec3_or("velocity_m_s", Vec3{});
    motion.start_s = w.number_or("moves_from_s", 0.0, any_number());
    if (w.has("moves_until_s")) {
      motion.stop_s = w.number("moves_until_s", above(motion.start_s));
    }
    w.finish();
    wall->set_motion(motion);
    guarded(w, [&] { return sim->add_wall(std::move(wall), mat); });
    out.wall_names.push_back(name);
    wall_material.push_back(mat);
  }

  // [[insertion]]
  std::vector<Table> ins_ts = root.tables("insertion", true);
  std::vector<int> particle_material;
  for (Table& t : ins_ts) {
    const std::string type = t.choice("type", {"pour", "fill"});
    const int mat = material(t, "material", t.string("material"));
    dem::InsertionAmount amount;
    const bool has_count = t.has("count");
    const bool has_mass = t.has("mass_kg");
    if (!has_count && !has_mass)
      t.fail(
          "count",
          "missing required key; expected count (an integer >= 1) and/or mass_kg (a number > 0)");
    if (has_count)
      amount.count =
          static_cast<std::size_t>(t.integer("count", 1, std::numeric_limits<std::int64_t>::max()));
    if (has_mass) amount.mass_kg = t.number("mass_kg", above(0));
    Table size_t_ = t.table("size");
    auto sizes = read_size(size_t_);
    Table region_t = t.table("region");
    auto region = read_region(region_t, domain);
    const double density = sim->materials()[static_cast<std::size_t>(mat)].density_kg_m3;
    std::unique_ptr<dem::Inserter> inserter;
    if (type == "pour") {
      dem::PourOptions o;
      o.material = mat;
      o.density_kg_m3 = density;
      o.amount = amount;
      o.gravity_m_s2 = gravity;
      o.velocity_m_s = t.vec3_or("velocity_m_s", Vec3{});
      o.start_s = t.number_or("start_s", 0.0, at_least(0));
      const bool has_rate = t.has("rate_particles_per_s");
      if (has_rate && t.has("batch_volume_fraction"))
        t.fail("batch_volume_fraction",
               "give rate_particles_per_s (a steady rate) or batch_volume_fraction (batches), not "
               "both");
      if (has_rate) {
        o.rate_particles_per_s = t.number("rate_particles_per_s", above(0));
      } else {
        o.batch_volume_fraction =
            t.number_or("batch_volume_fraction", 0.3, between(0, true, 0.6, true));
      }
      o.attempts_per_particle =
          static_cast<int>(t.integer_or("attempts_per_particle", 200, 1, 1000000));
      t.finish();
      inserter = guarded(
          t, [&] { return dem::make_pour_inserter(std::move(region), std::move(sizes), o); });
    } else {
      dem::FillOptions o;
      o.material = mat;
      o.density_kg_m3 = density;
      o.amount = amount;
      o.time_s = t.number_or("time_s", 0.0, at_least(0));
      o.method = t.choice_or("method", {"random", "lattice"}, "random");
      o.lattice_gap = t.number_or("lattice_gap", 0.05, at_least(0));
      o.attempts_per_particle =
          static_cast<int>(t.integer_or("attempts_per_particle", 400, 1, 1000000));
      t.finish();
      inserter = guarded(
          t, [&] { return dem::make_fill_inserter(std::move(region), std::move(sizes), o); });
    }
    guarded(t, [&] { sim->add_inserter(std::move(inserter)); });
    out.insertion_types.push_back(type);
    particle_material.push_back(mat);
  }

  // Every pair that can touch needs coefficients. The engine checks this on
  // its first step; checking here points at the table that needs the pair.
  for (std::size_t i = 0; i < ins_ts.size(); ++i) {
    const int a = particle_material[i];
    auto require = [&](int b, Table& t) {
      if (!given.contains(std::minmax(a, b)))
        t.fail("material", "no [[interaction]] for materials \"" +
                               material_names[static_cast<std::size_t>(a)] + "\" and \"" +
                               material_names[static_cast<std::size_t>(b)] +
                               "\"; every pair that can touch needs one");
    };
    for (std::size_t j = 0; j <= i; ++j) require(particle_material[j], ins_ts[i]);
    for (std::size_t w = 0; w < wall_ts.size(); ++w) require(wall_material[w], wall_ts[w]);
  }

  // [run]
  Table run_t = root.table("run");
  out.run.end_time_s = run_t.number("end_time_s", above(0));
  out.run.stop_at_rest = run_t.boolean_or("stop_at_rest", true);
  out.run.rest_speed_m_s = run_t.number_or("rest_speed_m_s", 2e-3, above(0));
  out.run.check_interval_s = run_t.number_or("check_interval_s", 0.01, above(0));
  run_t.finish();

  // [output]
  Table out_t = root.table_or_empty("output");
  const std::string dir = out_t.string_or("directory", "out/" + out.name);
  if (dir.empty()) out_t.fail("directory", "expected a non-empty path");
  out.output.directory = dir;
  out.output.vtk = out_t.boolean_or("vtk", true);
  out.output.snapshot_interval_s = out_t.number_or("snapshot_interval_s", 0.0, at_least(0));
  out_t.finish();

  root.finish();
  out.simulation = std::move(sim);
  out.resolved = std::move(doc.table);
  return out;
}

SimulationConfig load_simulation_config(const std::filesystem::path& path,
                                        const std::vector<std::string>& overrides) {
  ConfigDocument doc = read_config_file(path);
  for (const auto& o : overrides) apply_override(doc, o);
  return build_simulation(std::move(doc));
}

}  // namespace demcal::cli
