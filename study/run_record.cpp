#include "study/run_record.hpp"

#include "dem/output/atomic_file.hpp"
#include "dem/simulation.hpp"
#include "demcal_version.hpp"  // DEMCAL_VERSION, written at build time (cmake/version.cmake)

#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <sstream>

namespace demcal::study {

using demcal::config::ConfigError;
using demcal::config::SimulationConfig;
using demcal::config::StudyApparatus;
using demcal::config::StudyConfig;
using demcal::config::resolved_for;
using demcal::config::series_observables;
using demcal::config::with_stable_observables;
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

std::string engine_version() { return DEMCAL_VERSION; }

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

namespace {

// What every run record starts with, whatever assembled the simulation.
nlohmann::json record_header(const std::string& file, const toml::table& resolved,
                             const dem::Simulation& sim, const RunResults& results) {
  nlohmann::json r;
  r["engine"] = {{"name", "demcal"}, {"version", engine_version()}};
  r["config_file"] = file;
  r["written_utc"] = utc_now();
  r["inputs"] = toml_to_json(resolved);
  r["seed"] = sim.options().seed;
  r["threads"] = sim.options().threads;
  r["time_step_s"] = results.time_step_s;
  r["contact_law"] = sim.contact_law().describe();
  return r;
}

nlohmann::json common_results(const dem::Simulation& sim, const RunResults& results) {
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
  return res;
}

nlohmann::json outputs_json(const RunResults& results) {
  nlohmann::json outputs;
  outputs["vtk_series"] = results.vtk_series.empty() ? nlohmann::json(nullptr)
                                                     : nlohmann::json(results.vtk_series.string());
  outputs["vtk_walls_series"] = results.vtk_walls_series.empty()
                                    ? nlohmann::json(nullptr)
                                    : nlohmann::json(results.vtk_walls_series.string());
  outputs["snapshots"] = results.snapshots;
  return outputs;
}

}  // namespace

nlohmann::json make_run_record(const SimulationConfig& config, const RunResults& results) {
  const dem::Simulation& sim = *config.simulation;
  nlohmann::json r = record_header(config.file, config.resolved, sim, results);
  nlohmann::json res = common_results(sim, results);
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
  r["outputs"] = outputs_json(results);
  return r;
}

nlohmann::json make_apparatus_run_record(const StudyConfig& study, const StudyApparatus& apparatus,
                                         const RunResults& results,
                                         const dem::ApparatusResult* result) {
  const dem::Simulation& sim = apparatus.apparatus->simulation();
  nlohmann::json r = record_header(study.file, resolved_for(study, apparatus.name), sim, results);
  r["study"] = study.name;
  r["apparatus"] = apparatus.name;
  nlohmann::json res = common_results(sim, results);
  if (!results.phase.empty()) res["phase"] = results.phase;
  r["results"] = res;
  r["observables"] = with_stable_observables(result ? result->observables : nlohmann::json());
  r["series"] = result ? result->series : nlohmann::json::object();
  const nlohmann::json from_series = series_observables(r["series"], r["observables"]);
  for (const auto& [name, v] : from_series.items()) r["observables"][name] = v;
  r["details"] = result ? result->details : nlohmann::json::object();
  r["outputs"] = outputs_json(results);
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

void prepare_output_directory(const std::filesystem::path& output_dir, bool overwrite) {
  check_no_previous_run(output_dir, overwrite);
  if (overwrite) {
    std::filesystem::remove_all(output_dir / "vtk");
    std::filesystem::remove(output_dir / "particles.pvd");
    std::filesystem::remove(output_dir / "walls.pvd");
  }
  std::filesystem::create_directories(output_dir);
}

void write_run_record(const std::filesystem::path& output_dir, const nlohmann::json& record) {
  std::filesystem::create_directories(output_dir);
  dem::write_file_atomically(run_record_path(output_dir), record.dump(2) + "\n");
}

std::filesystem::path write_failed_run_record(const std::filesystem::path& output_dir,
                                              const nlohmann::json& record) {
  const std::filesystem::path previous = run_record_path(output_dir);
  bool previous_is_good = false;
  if (std::ifstream in(previous, std::ios::binary); in) {
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    const nlohmann::json* why = nullptr;
    if (j.is_object() && j.contains("results") && j["results"].is_object() &&
        j["results"].contains("stopped_because"))
      why = &j["results"]["stopped_because"];
    previous_is_good = why != nullptr && why->is_string() && *why != "error";
  }
  if (!previous_is_good) {
    write_run_record(output_dir, record);
    return previous;
  }
  const std::filesystem::path failed = output_dir / "run.failed.json";
  dem::write_file_atomically(failed, record.dump(2) + "\n");
  return failed;
}

std::unique_ptr<dem::VtkSeries> open_vtk_series(const std::filesystem::path& dir, bool enabled,
                                                RunResults& results) {
  if (!enabled) return nullptr;
  auto vtk = std::make_unique<dem::VtkSeries>(dir);
  results.vtk_series = vtk->particles_pvd();
  results.vtk_walls_series = vtk->walls_pvd();
  return vtk;
}

}  // namespace demcal::study
