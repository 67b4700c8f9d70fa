#include "config/simulation_config.hpp"

#include "config/models/insertion_models.hpp"
#include "config/models/wall_models.hpp"

#include "dem/air_drag.hpp"
#include "dem/contact/contact_law.hpp"
#include "dem/insertion/inserter.hpp"
#include "dem/insertion/region.hpp"
#include "dem/size_distribution.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>

namespace demcal::config {

using demcal::config::reader::Context;
using demcal::config::reader::InteractionKeys;
using demcal::config::reader::Table;
using demcal::config::reader::Vec3;
using demcal::config::reader::above;
using demcal::config::reader::any_number;
using demcal::config::reader::at_least;
using demcal::config::reader::between;
using demcal::config::reader::check_part_parameters;
using demcal::config::reader::format_number;
using demcal::config::reader::guarded;
using demcal::config::reader::node_line;
using demcal::config::reader::quoted_list;
using demcal::config::reader::read_air;
using demcal::config::reader::read_contact;
using demcal::config::reader::read_interaction;
using demcal::config::reader::read_material_properties;
using demcal::config::reader::read_restitution_model;
using demcal::config::reader::read_run_name;
using demcal::config::reader::read_size;
using demcal::config::reader::require_above;
using demcal::config::reader::vec_text;

namespace {

std::unique_ptr<dem::Region> read_region(Table& r, const dem::Domain& domain) {
  const std::string shape = r.choice("shape", region_models().names());
  std::unique_ptr<dem::Region> out = region_models().at(shape).model(r);
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

}  // namespace

// ---------------------------------------------------------------- building

SimulationConfig build_simulation(ConfigDocument&& doc) {
  const Context ctx{doc};
  Table root(ctx, doc.table, "", node_line(doc.table, 1));
  // Unknown top-level tables first: a misspelt [simulation] would otherwise be
  // reported as a missing one.
  for (const char* k : {"simulation", "domain", "contact", "material", "interaction", "air", "wall",
                        "insertion", "run", "output"})
    root.has(k);
  root.finish();

  SimulationConfig out;
  out.file = doc.file;

  // [simulation]
  Table sim_t = root.table("simulation");
  out.name = read_run_name(sim_t, "name");
  dem::SimulationOptions opt;
  opt.seed = static_cast<std::uint64_t>(
      sim_t.integer_or("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  opt.threads = static_cast<int>(sim_t.integer_or("threads", 1, 1, 4096));
  opt.gravity_m_s2 = sim_t.vec3_or("gravity_m_s2", Vec3{0, 0, -9.81});
  opt.time_step_s = sim_t.number_or("time_step_s", 0.0, at_least(0));
  opt.time_step_fraction_of_rayleigh =
      sim_t.number_or("time_step_fraction_of_rayleigh", 0.2, between(0, true, 1, false));
  opt.skin_fraction_of_diameter = sim_t.number_or("skin_fraction_of_diameter", 0.3, above(0));
  opt.restitution_model = read_restitution_model(sim_t);
  opt.max_speed_m_s = sim_t.number_or("max_speed_m_s", 0.0, at_least(0));
  // Absent means "spatial" (as in a study's [protocol]); not written in when absent, nor when
  // the default is given (same run, same hash). "insertion" is written in.
  opt.particle_order = dem::ParticleOrder::kSpatial;
  const bool order_given = sim_t.has("particle_order");
  if (order_given)
    opt.particle_order =
        dem::parse_particle_order(sim_t.choice("particle_order", dem::particle_order_names()));
  sim_t.finish();
  if (order_given && opt.particle_order == dem::ParticleOrder::kSpatial)
    doc.table.get("simulation")->as_table()->erase("particle_order");

  // [domain]
  Table dom_t = root.table("domain");
  opt.domain.lower_m = dom_t.vec3("lower_m");
  opt.domain.upper_m = dom_t.vec3("upper_m");
  require_above(dom_t, "upper_m", opt.domain.lower_m, opt.domain.upper_m, "lower_m");
  opt.domain.periodic = dom_t.bools3_or("periodic", {false, false, false});
  dom_t.finish();

  // [contact]
  Table con_t = root.table("contact");
  opt.contact = read_contact(con_t);
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
    read_material_properties(m, mat);
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
  std::vector<InteractionKeys> part_keys;
  for (Table& t : int_ts) {
    const auto [na, nb] = t.string_pair("materials");
    const int a = material(t, "materials", na);
    const int b = material(t, "materials", nb);
    const auto key = std::minmax(a, b);
    if (auto it = given.find(key); it != given.end())
      t.fail("materials", "the pair \"" + na + "\"-\"" + nb + "\" is already given at line " +
                              std::to_string(it->second));
    given[key] = t.line();
    const dem::InteractionParameters p = read_interaction(t);
    t.finish();
    guarded(t, [&] { sim->set_interaction(a, b, p); });
    part_keys.push_back({&t, p});
  }
  check_part_parameters(con_t, sim->options().contact, part_keys);

  // [air]: absent means no drag, and is not written in.
  if (root.has("air")) {
    Table air_t = root.table("air");
    if (const auto air = read_air(air_t))
      guarded(air_t, [&] { sim->add_body_force(std::make_unique<dem::AirDrag>(*air)); });
  }

  // [[wall]]
  std::vector<Table> wall_ts = root.tables("wall", false);
  std::vector<int> wall_material;
  for (std::size_t i = 0; i < wall_ts.size(); ++i) {
    Table& w = wall_ts[i];
    const std::string type = w.choice("type", wall_models().names());
    const int mat = material(w, "material", w.string("material"));
    const std::string name = w.string_or("name", type + "-" + std::to_string(i));
    if (name.empty()) w.fail("name", "expected a non-empty string");
    for (std::size_t j = 0; j < out.wall_names.size(); ++j)
      if (out.wall_names[j] == name)
        w.fail("name", "wall \"" + name + "\" is already defined at line " +
                           std::to_string(wall_ts[j].line()));
    std::unique_ptr<dem::Wall> wall = wall_models().at(type).model(w);
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
    const std::string type = t.choice("type", inserter_models().names());
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
    const InsertionCommon common{mat, density, amount, gravity};
    std::unique_ptr<dem::Inserter> inserter =
        inserter_models().at(type).model(t, common, std::move(region), std::move(sizes));
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
  // As for a study's protocol (config/run_sanity.hpp): a grain released from rest
  // reaches rest_speed_m_s only after rest_speed_m_s / g; a finer check declares
  // a falling fill at rest.
  if (const double g = dem::norm(gravity);
      out.run.stop_at_rest && g > 0.0 && out.run.check_interval_s < out.run.rest_speed_m_s / g)
    run_t.fail(
        "check_interval_s",
        "expected at least rest_speed_m_s / g = " + format_number(out.run.rest_speed_m_s / g) +
            " s, got " + format_number(out.run.check_interval_s) +
            ": a check finer than the dynamics declares a fill at rest while it is still "
            "falling (a grain released from rest needs that long to reach rest_speed_m_s)");
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

}  // namespace demcal::config
