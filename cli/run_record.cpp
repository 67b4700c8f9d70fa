#include "cli/run_record.hpp"

#include "dem/output/atomic_file.hpp"
#include "dem/simulation.hpp"

#include <chrono>
#include <cmath>
#include <ctime>
#include <sstream>

namespace demcal::cli {
namespace {

nlohmann::json vec_json(const dem::Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace

std::string engine_version() {
#ifdef DEMCAL_VERSION
  return DEMCAL_VERSION;
#else
  return "unknown";
#endif
}

nlohmann::json toml_to_json(const toml::node& node) {
  if (const toml::table* t = node.as_table()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [k, v] : *t) out[std::string(k.str())] = toml_to_json(v);
    return out;
  }
  if (const toml::array* a = node.as_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& v : *a) out.push_back(toml_to_json(v));
    return out;
  }
  if (auto s = node.value_exact<std::string>()) return *s;
  if (auto i = node.value_exact<std::int64_t>()) return *i;
  if (auto b = node.value_exact<bool>()) return *b;
  if (auto d = node.value_exact<double>()) {
    if (std::isnan(*d)) return "nan";
    if (std::isinf(*d)) return *d > 0 ? "inf" : "-inf";
    return *d;
  }
  std::ostringstream text;  // date, time or date-time
  node.visit([&](const auto& n) { text << n; });
  return text.str();
}

nlohmann::json make_run_record(const SimulationConfig& config, const RunResults& results) {
  const dem::Simulation& sim = *config.simulation;
  nlohmann::json r;
  r["engine"] = {{"name", "demcal"}, {"version", engine_version()}};
  r["config_file"] = config.file;
  r["written_utc"] = utc_now();
  r["inputs"] = toml_to_json(config.resolved);
  r["seed"] = sim.options().seed;
  r["threads"] = sim.options().threads;
  r["time_step_s"] = results.time_step_s;
  r["contact_law"] = sim.contact_law().describe();

  nlohmann::json res;
  res["time_s"] = sim.time_s();
  res["steps"] = sim.step_count();
  res["particles"] = sim.particles().size();
  res["particle_steps"] = sim.particle_steps();
  res["wall_time_s"] = results.wall_time_s;
  res["particle_steps_per_s"] =
      results.wall_time_s > 0.0 ? sim.particle_steps() / results.wall_time_s : 0.0;
  res["stopped_because"] = results.stopped_because;
  if (!results.error.empty()) res["error"] = results.error;
  res["rms_speed_m_s"] = sim.rms_speed_m_s();
  res["kinetic_energy_j"] = sim.kinetic_energy_j();
  res["insertion"] = nlohmann::json::array();
  for (std::size_t i = 0; i < sim.inserters().size(); ++i) {
    const auto& ins = *sim.inserters()[i];
    res["insertion"].push_back(
        {{"type", i < config.insertion_types.size() ? config.insertion_types[i] : ""},
         {"material", sim.materials()[static_cast<std::size_t>(ins.material())].name},
         {"inserted", ins.inserted()},
         {"mass_kg", ins.inserted_mass_kg()},
         {"finished", ins.finished()}});
  }
  res["walls"] = nlohmann::json::array();
  const auto& loads = sim.wall_loads();
  for (std::size_t w = 0; w < sim.walls().size(); ++w) {
    // Loads exist once the engine has evaluated forces (it may not have, after an early error).
    const dem::WallLoad load = w < loads.size() ? loads[w] : dem::WallLoad{};
    res["walls"].push_back({{"name", w < config.wall_names.size() ? config.wall_names[w] : ""},
                            {"type", sim.walls()[w]->type_name()},
                            {"force_n", vec_json(load.force_n)},
                            {"torque_nm", vec_json(load.torque_nm)},
                            {"contacts", load.contacts}});
  }
  r["results"] = res;

  nlohmann::json outputs;
  outputs["vtk_series"] = results.vtk_series.empty() ? nlohmann::json(nullptr)
                                                     : nlohmann::json(results.vtk_series.string());
  outputs["vtk_walls_series"] = results.vtk_walls_series.empty()
                                    ? nlohmann::json(nullptr)
                                    : nlohmann::json(results.vtk_walls_series.string());
  outputs["snapshots"] = results.snapshots;
  r["outputs"] = outputs;
  return r;
}

std::filesystem::path run_record_path(const std::filesystem::path& output_dir) {
  return output_dir / "run.json";
}

void check_no_previous_run(const std::filesystem::path& output_dir, bool overwrite) {
  const auto path = run_record_path(output_dir);
  std::error_code ec;
  if (!overwrite && std::filesystem::exists(path, ec))
    throw ConfigError(path.string() +
                      " exists from an earlier run; not overwriting it. Pass --overwrite to "
                      "replace that run, or choose another directory with --output");
}

void write_run_record(const std::filesystem::path& output_dir, const nlohmann::json& record) {
  std::filesystem::create_directories(output_dir);
  dem::write_file_atomically(run_record_path(output_dir), record.dump(2) + "\n");
}

}  // namespace demcal::cli
