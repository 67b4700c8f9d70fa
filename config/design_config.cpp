#include "config/design_config.hpp"

#include "config/adaptive_design_keys.hpp"
#include "config/study_config.hpp"
#include "surrogate/sobol_design.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

namespace demcal::config {

using reader::any_number;
using reader::Context;
using reader::describe_value;
using reader::format_number;
using reader::node_line;
using reader::Table;

namespace {

constexpr std::int64_t kMaxPoints = 100000;
constexpr std::int64_t kMaxLevels = 1000;
constexpr double kMaxFactorialPoints = 1e6;
// Points x replicates (each apparatus runs them all). Planning builds the study
// at every point (about 0.1 s each for a sandglass), so 5000 is minutes of
// planning before anything runs; the largest design in studies/ has 208.
constexpr double kMaxDesignRuns = 5000;

std::string first_segment(const std::string& path) {
  return path.substr(0, std::min(path.find_first_of(".["), path.size()));
}

}  // namespace

std::string without_file_prefix(const std::string& message, const std::string& file) {
  if (message.compare(0, file.size() + 1, file + ":") != 0) return message;
  std::size_t pos = file.size() + 1;
  while (pos < message.size() && message[pos] >= '0' && message[pos] <= '9') ++pos;
  if (pos < message.size() && message[pos] == ':') ++pos;
  while (pos < message.size() && message[pos] == ' ') ++pos;
  return message.substr(pos);
}

std::string toml_key_text(const std::string& key) {
  const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
  return bare ? key : "\"" + key + "\"";
}

std::string shortest_decimal(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::uint64_t replicate_seed(std::uint64_t study_seed, int replicate) {
  return study_seed + static_cast<std::uint64_t>(replicate);
}

std::optional<DesignConfig> read_design(const Context& ctx, Table& root, toml::table& top) {
  if (!root.has("design")) return std::nullopt;
  Table d = root.table("design");
  toml::table& dt = *top.get("design")->as_table();
  DesignConfig out;
  out.line = d.line();
  surrogate::DesignSpec& spec = out.spec;

  std::vector<std::string> kinds = surrogate::design_kind_names();
  kinds.push_back("adaptive");
  const std::string kind = d.choice("kind", kinds);
  const bool adaptive = kind == "adaptive";
  // An adaptive design's points are a list the campaign grows batch by batch
  // (study/adaptive_campaign.hpp); none is known before it runs.
  spec.kind = adaptive ? surrogate::DesignKind::kList : *surrogate::design_kind_from_name(kind);
  const bool factorial = spec.kind == surrogate::DesignKind::kFullFactorial;
  const bool sobol = spec.kind == surrogate::DesignKind::kSobol;
  const bool list = spec.kind == surrogate::DesignKind::kList;

  if (adaptive) {
    out.adaptive = read_adaptive_design_keys(d);
  } else if (list) {
    if (d.contains("points"))
      d.fail("points",
             "applies only to kind = \"latin_hypercube\" or \"sobol\"; a list design "
             "runs the points of design.values");
  } else if (factorial) {
    if (d.contains("points"))
      d.fail("points",
             "applies only to kind = \"latin_hypercube\" or \"sobol\"; a full factorial design "
             "has the product of its parameters' levels");
  } else {
    spec.points = static_cast<std::size_t>(d.integer("points", 1, kMaxPoints));
  }
  if (!adaptive) {
    out.replicates = static_cast<int>(d.integer_or("replicates", 1, 1, 1000));
    spec.seed = static_cast<std::uint64_t>(
        d.integer_or("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  }
  if (sobol)
    spec.skip = static_cast<std::size_t>(d.integer_or("skip", 0, 0, 1000000000));
  else if (d.contains("skip"))
    d.fail("skip", "applies only to kind = \"sobol\"");

  Table p = d.table("parameters");
  toml::table& pt = *dt.get("parameters")->as_table();
  // In the order written (a TOML table is kept sorted by key).
  std::vector<std::pair<std::string, toml::node*>> entries;
  for (auto& [k, v] : pt) entries.emplace_back(std::string(k.str()), &v);
  std::stable_sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    const auto& sa = a.second->source().begin;
    const auto& sb = b.second->source().begin;
    return sa.line != sb.line ? sa.line < sb.line : sa.column < sb.column;
  });
  if (entries.empty())
    d.fail("parameters",
           "expected at least one parameter, e.g. parameters = { mu_r = { lower = 0.05, upper = "
           "0.6" +
               std::string(factorial ? ", levels = 5" : "") + " } }");

  double factorial_points = 1.0;
  const OverrideAliases& aliases = study_override_aliases();
  std::map<std::string, std::string> set_by;  // each key the design sets -> its parameter
  for (auto& [name, node] : entries) {
    p.has(name);  // part of the schema: every entry is a parameter
    const std::size_t line = node_line(*node, p.line());
    const std::string path_text = p.path() + "." + toml_key_text(name);
    if (!node->is_table())
      ctx.raise(line, path_text,
                "expected a table { lower = ..., upper = ..." +
                    std::string(factorial ? ", levels = ..." : "") + " }, got " +
                    describe_value(*node));
    Table t(ctx, *node->as_table(), path_text, line);

    std::string target = name;
    if (auto a = aliases.find(name); a != aliases.end()) target = a->second;
    const std::string head = first_segment(target);
    if (target.empty() || head.empty())
      ctx.raise(line, path_text,
                "expected a key of the study, e.g. mu_r or apparatus.<name>.<key>");
    if (head == "study")
      ctx.raise(line, path_text,
                "cannot vary [study] keys: each replicate's seed is study.seed + replicate, and "
                "the threads per run are `demcal doe --threads-per-run`");
    if (head == "output")
      ctx.raise(line, path_text, "cannot vary [output] keys: they do not change a run");
    if (head == "design") ctx.raise(line, path_text, "cannot vary the design itself");
    // Every key the design sets (a parameter's own and its also_sets) is set by one
    // parameter only: two would overwrite each other and collapse the design's points.
    if (const auto it = set_by.find(target); it != set_by.end())
      ctx.raise(line, path_text,
                "sets " + target + ", as parameter \"" + it->second + "\" does already");
    set_by.emplace(target, name);

    surrogate::ParameterRange r;
    r.name = name;
    r.lower = t.number("lower", any_number());
    r.upper = t.number("upper", any_number());
    if (!(r.upper > r.lower))
      t.fail("upper", "expected a number > lower (" + format_number(r.lower) + "), got " +
                          format_number(r.upper));
    std::vector<std::string> tied;
    if (t.contains("also_sets")) {
      for (const std::string& key : t.strings_or("also_sets", {}, {})) {
        std::string k = key;
        if (auto a = aliases.find(key); a != aliases.end()) k = a->second;
        const std::string h = first_segment(k);
        if (k.empty() || h == "study" || h == "output" || h == "design" || k == target)
          t.fail("also_sets",
                 "expected keys of the study other than the parameter's own, got \"" + key + "\"");
        if (const auto it = set_by.find(k); it != set_by.end() && it->second != name)
          t.fail("also_sets", "\"" + key + "\" is set by parameter \"" + it->second +
                                  "\" already; a key follows one parameter only");
        tied.push_back(k);
        set_by.emplace(k, name);
      }
    }
    if (factorial) {
      r.levels = static_cast<int>(t.integer("levels", 2, kMaxLevels));
      factorial_points *= r.levels;
    } else if (t.contains("levels")) {
      t.fail("levels", "applies only to kind = \"full_factorial\"; " +
                           (adaptive ? std::string("an adaptive design chooses its points itself")
                                     : kind + " designs take the number of points from design.points"));
    }
    t.finish();
    spec.parameters.push_back(r);
    out.parameter_paths.push_back(target);
    out.tied_paths.push_back(std::move(tied));
    out.parameter_lines.push_back(line);
  }
  if (list && !adaptive) {
    const toml::node* vn = dt.get("values");
    const std::size_t vline = vn ? node_line(*vn, d.line()) : d.line();
    const toml::array* rows = vn ? vn->as_array() : nullptr;
    const std::string expected =
        "an array of points [[" + spec.parameters.front().name +
        (spec.parameters.size() > 1 ? ", " + spec.parameters[1].name : std::string()) +
        (spec.parameters.size() > 2 ? ", ..." : "") + "], ...]";
    if (rows == nullptr || rows->empty())
      ctx.raise(vline, d.path() + ".values",
                "expected " + expected + (vn ? ", got " + describe_value(*vn) : ""));
    if (rows->size() > static_cast<std::size_t>(kMaxPoints))
      ctx.raise(vline, d.path() + ".values",
                "expected at most " + std::to_string(kMaxPoints) + " points");
    for (std::size_t i = 0; i < rows->size(); ++i) {
      const toml::array* row = (*rows)[i].as_array();
      const std::string where = d.path() + ".values[" + std::to_string(i) + "]";
      if (row == nullptr || row->size() != spec.parameters.size())
        ctx.raise(vline, where,
                  "expected " + std::to_string(spec.parameters.size()) +
                      " numbers (one per parameter: " + expected + "), got " +
                      describe_value((*rows)[i]));
      std::vector<double> v;
      for (std::size_t k = 0; k < row->size(); ++k) {
        const auto x = (*row)[k].value<double>();
        const auto& r = spec.parameters[k];
        if (!x || !std::isfinite(*x))
          ctx.raise(vline, where,
                    r.name + ": expected a finite number, got " + describe_value((*row)[k]));
        if (*x < r.lower || *x > r.upper)
          ctx.raise(vline, where,
                    r.name + " = " + format_number(*x) + " is outside its bounds [" +
                        format_number(r.lower) + ", " + format_number(r.upper) + "]");
        v.push_back(*x);
      }
      spec.values.push_back(std::move(v));
    }
    d.has("values");
  } else if (d.contains("values")) {
    d.fail("values", "applies only to kind = \"list\"");
  }
  if (factorial && factorial_points > kMaxFactorialPoints)
    d.fail("parameters", "the full factorial design has " + format_number(factorial_points) +
                             " points, more than " + format_number(kMaxFactorialPoints) +
                             "; use fewer levels or a latin_hypercube or sobol design");
  // Every run is planned (its study built, its key hashed) before any runs: a
  // design of 10^6 runs would take hours and gigabytes just to list.
  if (!adaptive) {
    const double points = factorial ? factorial_points
                          : list    ? static_cast<double>(spec.values.size())
                                    : static_cast<double>(spec.points);
    const double runs = points * out.replicates;
    if (runs > kMaxDesignRuns)
      d.fail(factorial ? "parameters"
             : list    ? "values"
                       : "points",
             "the design has " + format_number(points) + " points x " +
                 std::to_string(out.replicates) + " replicates = " + format_number(runs) +
                 " runs per apparatus, more than " + format_number(kMaxDesignRuns) +
                 "; split it into several studies or use fewer points");
  }
  if (sobol && spec.parameters.size() > surrogate::kSobolMaxDimensions)
    d.fail("parameters", "a sobol design takes at most " +
                             std::to_string(surrogate::kSobolMaxDimensions) + " parameters");
  p.finish();
  d.finish();
  return out;
}

void apply_design_values(ConfigDocument& doc, const DesignConfig& design,
                         const std::vector<double>& values, const std::string& origin) {
  const auto& params = design.spec.parameters;
  for (std::size_t i = 0; i < params.size() && i < values.size(); ++i)
    set_parameter(doc, design, i, values[i],
                  origin + ": " + params[i].name + " = " + shortest_decimal(values[i]));
}

void set_parameter(ConfigDocument& doc, const DesignConfig& design, std::size_t i, double value,
                   const std::string& origin) {
  set_config_value(doc, design.parameter_paths[i], toml::value<double>(value), origin);
  if (i < design.tied_paths.size())
    for (const auto& key : design.tied_paths[i])
      set_config_value(doc, key, toml::value<double>(value), origin);
}

StudySource StudySource::read(const std::filesystem::path& path,
                              std::vector<std::string> overrides) {
  StudySource s;
  s.file = path.string();
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  // read_config_file throws its ConfigError ("cannot open ...", "is a directory").
  if (!in || std::filesystem::is_directory(path, ec)) read_config_file(path);
  std::ostringstream text;
  text << in.rdbuf();
  s.text = text.str();
  s.overrides = std::move(overrides);
  return s;
}

ConfigDocument StudySource::document() const {
  ConfigDocument doc = parse_config_string(text, file);
  for (const auto& o : overrides) apply_override(doc, o, study_override_aliases());
  return doc;
}

void check_design_bounds(const StudySource& source, const DesignConfig& design) {
  const auto& params = design.spec.parameters;
  for (std::size_t i = 0; i < params.size(); ++i) {
    for (const bool upper : {false, true}) {
      const double v = upper ? params[i].upper : params[i].lower;
      const std::string what = std::string(upper ? "upper" : "lower") + " = " + shortest_decimal(v);
      try {
        ConfigDocument doc = source.document();
        set_parameter(doc, design, i, v, "the design");
        build_study(std::move(doc));
      } catch (const ConfigError& e) {
        throw ConfigError(source.file + ":" + std::to_string(design.parameter_lines[i]) +
                          ": design.parameters." + toml_key_text(params[i].name) + ": " + what +
                          " is refused: " + without_file_prefix(e.what(), source.file));
      }
    }
  }
}

}  // namespace demcal::config
