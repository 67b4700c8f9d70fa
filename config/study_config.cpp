#include "config/study_config.hpp"

#include "config/calibration_config.hpp"
#include "config/models/apparatus_models.hpp"
#include "config/run_sanity.hpp"
#include "config/surrogate_config.hpp"

#include "dem/contact/restitution_damping.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>

namespace demcal::config {

using demcal::config::reader::Context;
using demcal::config::reader::InteractionKeys;
using demcal::config::reader::Range;
using demcal::config::reader::Table;
using demcal::config::reader::above;
using demcal::config::reader::at_least;
using demcal::config::reader::between;
using demcal::config::reader::check_part_parameters;
using demcal::config::reader::guarded;
using demcal::config::reader::node_line;
using demcal::config::reader::quoted_list;
using demcal::config::reader::read_air;
using demcal::config::reader::read_contact;
using demcal::config::reader::read_interaction;
using demcal::config::reader::read_interaction_over;
using demcal::config::reader::read_material_properties;
using demcal::config::reader::read_restitution_model;
using demcal::config::reader::read_run_name;
using demcal::config::reader::read_size;

namespace {

// The wall groups of an apparatus kind (the names its walls are grouped under).
std::vector<std::string> wall_group_names(const std::string& kind) {
  return apparatus_models().at(kind).model.wall_group_names();
}

// Every group name any apparatus has, each once, in a stable order.
std::vector<std::string> all_wall_group_names() {
  std::vector<std::string> all;
  for (const auto& e : apparatus_models().entries())
    for (const std::string& g : e.model.wall_group_names())
      if (std::find(all.begin(), all.end(), g) == all.end()) all.push_back(g);
  return all;
}

const Range kPositive = above(0);

dem::Material read_named_material(Table& t) {
  dem::Material m;
  m.name = t.string("name");
  if (m.name.empty()) t.fail("name", "expected a non-empty string");
  read_material_properties(t, m);
  return m;
}

}  // namespace

const std::vector<std::string>& known_apparatus_names() {
  static const std::vector<std::string> names = apparatus_models().names();
  return names;
}

const OverrideAliases& study_override_aliases() {
  static const OverrideAliases aliases = {
      {"mu_s", "interaction.particle_particle.sliding_friction"},
      {"mu_r", "interaction.particle_particle.rolling_friction"},
      {"mu_s_wall", "interaction.particle_wall.sliding_friction"},
      {"mu_r_wall", "interaction.particle_wall.rolling_friction"},
      {"surface_energy", "interaction.particle_particle.surface_energy_j_m2"},
      {"surface_energy_wall", "interaction.particle_wall.surface_energy_j_m2"},
      {"size_spread", "material.size.relative_half_width"},
      {"drag_scale", "air.drag_scale"},
  };
  return aliases;
}

bool is_study_config(const ConfigDocument& doc) { return doc.table.contains("apparatus"); }

StudyConfig build_study(ConfigDocument&& doc) {
  const Context ctx{doc};
  Table root(ctx, doc.table, "", node_line(doc.table, 1));
  // Unknown top-level tables first: a misspelt [material] would otherwise be
  // reported as a missing one.
  for (const char* k :
       {"study", "material", "wall_material", "contact", "interaction", "air", "protocol",
        "apparatus", "output", "design", "surrogate", "calibration", "diagnosis", "engine",
        "raw_recordings"})
    root.has(k);
  root.finish();

  StudyConfig out;
  out.file = doc.file;
  dem::RunProtocol& protocol = out.protocol;
  const dem::RunProtocol defaults;

  // [study]
  Table study_t = root.table("study");
  out.name = read_run_name(study_t, "name");
  protocol.seed = static_cast<std::uint64_t>(
      study_t.integer_or("seed", static_cast<std::int64_t>(defaults.seed), 0,
                         std::numeric_limits<std::int64_t>::max()));
  protocol.threads = static_cast<int>(study_t.integer_or("threads", defaults.threads, 1, 4096));
  study_t.finish();

  // [material], [wall_material]
  dem::GranularMaterial& material = out.material;
  Table mat_t = root.table("material");
  material.particle = read_named_material(mat_t);
  Table size_t_ = mat_t.table("size");
  material.sizes = read_size(size_t_);
  mat_t.finish();
  guarded(mat_t, [&] { material.particle.validate(); });

  Table wall_t = root.table("wall_material");
  material.wall = read_named_material(wall_t);
  wall_t.finish();
  guarded(wall_t, [&] { material.wall.validate(); });

  // [contact]
  Table con_t = root.table("contact");
  material.contact = read_contact(con_t);
  material.restitution_model = read_restitution_model(con_t);
  con_t.finish();

  // [interaction.particle_particle], [interaction.particle_wall]
  Table int_t = root.table("interaction");
  std::vector<Table> pair_ts;
  std::vector<InteractionKeys> part_keys;
  std::vector<std::pair<std::string, Table>>
      wall_group_tables;  // checked once the apparatus are known
  pair_ts.reserve(2);     // part_keys points into it
  for (const char* pair : {"particle_particle", "particle_wall"}) {
    Table& t = pair_ts.emplace_back(int_t.table(pair));
    const dem::InteractionParameters p = read_interaction(t);
    // The exact model's damping is found by a root search that resolves
    // restitutions down to smallest_resolved_restitution() only.
    const auto check = [&](Table& table, const dem::InteractionParameters& q) {
      guarded(table, [&] { q.validate(table.path() + ": "); });
      if (material.restitution_model == dem::RestitutionModel::kExact) try {
          (void)dem::damping_beta_for_restitution(q.restitution);
        } catch (const std::invalid_argument& e) {
          table.fail("restitution", e.what());
        }
    };
    // [interaction.particle_wall.<group>]: the walls of an apparatus' group
    // (a bare floor under a lined hopper) with their own values over
    // particle_wall's. Absent groups are not written in (hashes unchanged).
    if (std::string(pair) == "particle_wall")
      for (const std::string& group : all_wall_group_names())
        if (t.has(group)) {
          Table gt = t.table(group);
          const dem::InteractionParameters q = read_interaction_over(gt, p);
          gt.finish();
          check(gt, q);
          material.particle_wall_by_group[group] = q;
          wall_group_tables.emplace_back(group, gt);
        }
    t.finish();
    check(t, p);
    (std::string(pair) == "particle_particle" ? material.particle_particle
                                              : material.particle_wall) = p;
    part_keys.push_back({&t, p});
  }
  int_t.finish();
  check_part_parameters(con_t, material.contact, part_keys);

  // [air]: absent means no drag, and is not written in (the runs of studies
  // without it resolve, and hash, as before it existed).
  if (root.has("air")) {
    Table air_t = root.table("air");
    material.air_drag = read_air(air_t);
  }

  // [protocol]
  Table prot_t = root.table_or_empty("protocol");
  protocol.rest_speed_m_s = prot_t.number_or("rest_speed_m_s", defaults.rest_speed_m_s, kPositive);
  protocol.check_interval_s =
      prot_t.number_or("check_interval_s", defaults.check_interval_s, kPositive);
  protocol.max_settle_s = prot_t.number_or("max_settle_s", defaults.max_settle_s, kPositive);
  protocol.max_flow_s = prot_t.number_or("max_flow_s", defaults.max_flow_s, kPositive);
  protocol.sample_interval_s =
      prot_t.number_or("sample_interval_s", defaults.sample_interval_s, kPositive);
  protocol.stall_time_s = prot_t.number_or("stall_time_s", defaults.stall_time_s, kPositive);
  protocol.time_step_fraction_of_rayleigh =
      prot_t.number_or("time_step_fraction_of_rayleigh", defaults.time_step_fraction_of_rayleigh,
                       between(0, true, 1, false));
  // Not written in when absent: the runs of studies without it keep their hashes.
  const double max_steps =
      prot_t.has("max_steps") ? prot_t.number("max_steps", at_least(1)) : kDefaultMaxSteps;
  // Not written in when absent either; the apparatus refuse a fill of more grains.
  if (prot_t.has("max_particles"))
    protocol.max_particles = prot_t.number("max_particles", at_least(1));
  // Absent means "spatial", the default since run keys of version 2 (issue 13: the same
  // statistics for less CPU, BENCHMARKS.md). Not written in when absent, nor when the
  // default is given: the runs are the same, so their keys must be too. "insertion" is
  // written in, so its runs (bit-wise different) get keys of their own.
  protocol.particle_order = dem::ParticleOrder::kSpatial;
  const bool order_given = prot_t.has("particle_order");
  if (order_given)
    protocol.particle_order =
        dem::parse_particle_order(prot_t.choice("particle_order", dem::particle_order_names()));
  check_rest_protocol(prot_t, protocol, material);
  prot_t.finish();
  if (order_given && protocol.particle_order == dem::ParticleOrder::kSpatial)
    doc.table.get("protocol")->as_table()->erase("particle_order");

  // [apparatus.*]: a table named after its kind ([apparatus.sandglass]), or
  // any name with the kind given (type = "sandglass"), so that one study can
  // hold several setups of one kind — the sandglass at three orifices.
  Table app_t = root.table("apparatus");
  toml::table& app_toml = *doc.table.get("apparatus")->as_table();
  std::vector<std::string> defined;
  for (auto& [k, v] : app_toml) {
    defined.emplace_back(k.str());
    app_t.has(k.str());
  }
  app_t.finish();
  if (defined.empty()) {
    std::string expected;
    for (const std::string& n : known_apparatus_names())
      expected += (expected.empty() ? "[apparatus." : ", [apparatus.") + n + "]";
    app_t.fail_here("defines no apparatus; expected one or more of " + expected);
  }
  for (const std::string& name : defined) {
    Table t = app_t.table(name);
    const auto& kinds = known_apparatus_names();
    const bool named_by_kind = std::find(kinds.begin(), kinds.end(), name) != kinds.end();
    if (!named_by_kind && !t.contains("type"))
      t.fail_here("unknown key; expected one of " + quoted_list(kinds) +
                  ", or a setup name of your own with type = \"<kind>\"");
    // Not written in when absent: a run's hash is its resolved inputs, and the
    // runs of studies written before setups had names must keep theirs.
    const std::string kind = !named_by_kind  ? t.choice("type", kinds)
                             : t.has("type") ? t.choice("type", {name})
                                             : name;
    if (!named_by_kind && !std::all_of(name.begin(), name.end(), [](char c) {
          return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
        }))
      t.fail_here("a setup name takes letters, digits, _ and - only (it names files)");
    if (const std::string why = reader::file_name_problem(name); !why.empty())
      t.fail_here("a setup name names files: " + why);
    StudyApparatus a;
    a.name = name;
    a.kind = kind;
    a.line = t.line();
    a.apparatus = apparatus_models().at(kind).model.read(t, material, max_steps, protocol);
    check_apparatus_extent(t, *a.apparatus);
    out.apparatus.push_back(std::move(a));
  }
  // A wall group no apparatus of the study has would silently change nothing.
  for (auto& [group, gt] : wall_group_tables) {
    bool used = false;
    std::string groups_here;
    for (const StudyApparatus& a : out.apparatus) {
      const std::vector<std::string> names = wall_group_names(a.kind);
      used = used || std::find(names.begin(), names.end(), group) != names.end();
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      groups_here += (groups_here.empty() ? "" : "; ") + a.name + ": " + list;
    }
    if (!used)
      gt.fail_here("no apparatus of this study has a wall group \"" + group + "\" (" + groups_here +
                   ")");
  }
  std::stable_sort(
      out.apparatus.begin(), out.apparatus.end(),
      [](const StudyApparatus& a, const StudyApparatus& b) { return a.line < b.line; });

  // [output]
  Table out_t = root.table_or_empty("output");
  if (out_t.has("directory")) {
    const std::string dir = out_t.string("directory");
    if (dir.empty()) out_t.fail("directory", "expected a non-empty path");
    out.output.directory = dir;
  }
  out.output.vtk = out_t.boolean_or("vtk", false);
  out.output.snapshot_interval_s = out_t.number_or("snapshot_interval_s", 0.0, at_least(0));
  out_t.finish();

  // [design]
  out.design = read_design(ctx, root, doc.table);
  // [surrogate]
  out.surrogate = read_surrogate(root);
  // [calibration]
  out.calibration = read_calibration(root, doc.file, out.design, root.has("raw_recordings"));
  // [diagnosis]
  {
    std::vector<std::string> setups;
    for (const auto& a : out.apparatus) setups.push_back(a.name);
    out.diagnosis = read_diagnosis(
        root, setups,
        out.design ? out.design->spec.parameters : std::vector<surrogate::ParameterRange>{});
    out.raw_recordings = read_raw_recordings(root, setups, doc.file);
  }

  // [engine]
  out.engine = read_engine(root, doc.file);

  root.finish();
  out.resolved = std::move(doc.table);
  return out;
}

StudyConfig load_study_config(const std::filesystem::path& path,
                              const std::vector<std::string>& overrides) {
  ConfigDocument doc = read_config_file(path);
  for (const auto& o : overrides) apply_override(doc, o, study_override_aliases());
  return build_study(std::move(doc));
}

StudyApparatus& select_apparatus(StudyConfig& study, const std::optional<std::string>& requested) {
  std::vector<std::string> names;
  for (const StudyApparatus& a : study.apparatus) names.push_back(a.name);
  if (requested) {
    for (StudyApparatus& a : study.apparatus)
      if (a.name == *requested) return a;
    throw ConfigError(study.file + ": --apparatus " + *requested +
                      ": the study defines no apparatus \"" + *requested +
                      "\"; defined: " + quoted_list(names));
  }
  if (study.apparatus.size() != 1)
    throw ConfigError(study.file + ":" + std::to_string(study.apparatus.front().line) +
                      ": apparatus: the study defines " + std::to_string(names.size()) +
                      " apparatus (" + quoted_list(names) + "); choose one with --apparatus NAME");
  return study.apparatus.front();
}

std::filesystem::path output_directory(const StudyConfig& study, const std::string& apparatus) {
  if (!study.output.directory.empty()) return study.output.directory;
  return std::filesystem::path("out") / study.name / apparatus;
}

toml::table resolved_for(const StudyConfig& study, const std::string& apparatus) {
  toml::table t = study.resolved;
  t.erase("design");
  t.erase("surrogate");
  t.erase("calibration");
  t.erase("diagnosis");  // like the three above: it does not change a run, so not its hash
  t.erase("raw_recordings");  // the same
  if (toml::table* apps = t["apparatus"].as_table()) {
    toml::table only;
    if (const toml::node* a = apps->get(apparatus)) only.insert(apparatus, *a);
    *apps = std::move(only);
  }
  if (toml::table* o = t["output"].as_table())
    o->insert_or_assign("directory", output_directory(study, apparatus).string());
  return t;
}

}  // namespace demcal::config
