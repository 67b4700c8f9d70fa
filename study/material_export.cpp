#include "study/material_export.hpp"

#include "io/atomic_file.hpp"
#include "config/study_config.hpp"
#include "config/toml_reader.hpp"
#include "study/engine_evaluator.hpp"
#include "study/run_record.hpp"
#include "study/run_store.hpp"
#include "study/study_directory.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <map>
#include <stdexcept>

namespace demcal::study {

using config::ConfigError;

namespace {

// A design key as a field of the material card ("interaction.particle_particle.
// rolling_friction" -> "particle_particle.rolling_friction"); empty when the
// key is not one of the material's.
std::string card_field(const std::string& path) {
  const std::string interaction = "interaction.", material = "material.";
  std::string field;
  if (path.rfind(interaction, 0) == 0) field = path.substr(interaction.size());
  if (path.rfind(material, 0) == 0) field = "particle." + path.substr(material.size());
  if (field.empty()) return "";
  try {
    dem::GranularMaterial probe;
    (void)engines::material_parameter(probe, field);
  } catch (const std::invalid_argument&) {
    return "";
  }
  return field;
}

nlohmann::json read_json(const std::filesystem::path& file, const std::string& what) {
  std::ifstream in(file);
  if (!in)
    throw ConfigError(file.string() + ": no " + what +
                      " (run `demcal calibrate` on the study first)");
  nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) throw ConfigError(file.string() + ": not JSON");
  return j;
}

// The version of the engine that made the study's runs, from one stored run.
std::string stored_engine_version(const std::filesystem::path& runs_dir, const std::string& name) {
  std::error_code ec;
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(runs_dir, ec))
    if (e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    std::ifstream in(f);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_object() && j.contains("engine") && j["engine"].value("name", "") == name)
      return j["engine"].value("version", "");
  }
  return "";
}

}  // namespace

engines::MaterialCardInput material_card_input(const std::filesystem::path& study_path,
                                               const std::vector<std::string>& overrides,
                                               const std::filesystem::path& calibration_json,
                                               const std::filesystem::path& runs_dir) {
  const config::StudyConfig study = config::load_study_config(study_path, overrides);
  if (!study.design)
    throw ConfigError(study.file + ": the study has no [design]: nothing was calibrated");
  const nlohmann::json cal = read_json(calibration_json, "calibration output");
  const nlohmann::json& joint = cal.at("joint");
  const auto& minima = joint.at("minima");
  if (!minima.is_array() || minima.empty())
    throw ConfigError(calibration_json.string() +
                      ": joint.minima: the calibration found no minimum");
  // Minima are listed best first.
  const nlohmann::json& theta = minima.at(0).at("theta");
  std::map<std::string, std::pair<double, double>> extent;
  if (joint.contains("region") && joint["region"].value("available", false))
    for (const auto& e : joint["region"].at("extent"))
      extent[e.at("parameter").get<std::string>()] = {e.at("lower").get<double>(),
                                                      e.at("upper").get<double>()};

  engines::MaterialCardInput in;
  in.material = study.material;
  const config::DesignConfig& design = *study.design;
  const auto& names = design.spec.parameters;
  if (theta.size() != names.size())
    throw ConfigError(calibration_json.string() + ": joint.minima[0].theta has " +
                      std::to_string(theta.size()) + " values; the study's design has " +
                      std::to_string(names.size()) +
                      " parameters (a calibration of another study?)");
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string field = card_field(design.parameter_paths[i]);
    if (field.empty())
      throw ConfigError(study.file + ":" + std::to_string(design.parameter_lines[i]) +
                        ": design.parameters." + names[i].name + ": \"" +
                        design.parameter_paths[i] +
                        "\" is not a material parameter; a material card cannot hold it");
    engines::CalibratedParameter c;
    c.name = field;
    c.value = theta.at(i).get<double>();
    if (const auto it = extent.find(names[i].name); it != extent.end()) {
      c.lower_95 = it->second.first;
      c.upper_95 = it->second.second;
    }
    engines::set_material_parameter(in.material, field, c.value);
    for (const std::string& tied : design.tied_paths.at(i))
      if (const std::string f = card_field(tied); !f.empty())
        engines::set_material_parameter(in.material, f, c.value);
    in.calibrated.push_back(c);
  }
  // The reductions of the first apparatus; another with different ones is noted.
  in.reduction = apparatus_reduction(study.apparatus.front());
  in.provenance.study = study.name;
  const std::string kind = study.engine ? study.engine->kind : "demcal";
  in.provenance.calibrated_engine = engines::engine_from_name(kind);
  in.provenance.calibrated_engine_version =
      kind == "demcal" ? engine_version() : stored_engine_version(runs_dir, kind);
  return in;
}

MaterialExportOutcome export_material_card(const MaterialExportOptions& o) {
  engines::CardFormat format;
  try {
    format = engines::card_format_from_name(o.to);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("--to: ") + e.what());
  }
  const config::StudyConfig study = config::load_study_config(o.study, o.overrides);
  const std::filesystem::path dir = study_directory(o.output_dir, study.name);
  MaterialExportOutcome out;
  out.input = material_card_input(
      o.study, o.overrides, dir / "reports" / "calibration" / "calibration.json", dir / "runs");
  for (const config::StudyApparatus& a : study.apparatus) {
    const dem::ModelReduction r = apparatus_reduction(a);
    if (r.coarse_graining_factor != out.input.reduction.coarse_graining_factor ||
        r.shear_modulus_pa != out.input.reduction.shear_modulus_pa)
      out.warnings.push_back("apparatus \"" + a.name + "\" ran with other reductions than \"" +
                             study.apparatus.front().name + "\", whose reductions the card states");
  }
  const engines::CardResult card = engines::write_material_card(out.input, format);
  if (!card.ok()) throw std::runtime_error("export --to " + o.to + ": " + card.refusal);
  const bool same_engine = (format == engines::CardFormat::kLammps &&
                            out.input.provenance.calibrated_engine == engines::Engine::kLammps) ||
                           (format == engines::CardFormat::kLiggghts &&
                            out.input.provenance.calibrated_engine == engines::Engine::kLiggghts) ||
                           format == engines::CardFormat::kJson;
  if (!same_engine)
    out.warnings.push_back("the study was calibrated on " +
                           engines::engine_name(out.input.provenance.calibrated_engine) +
                           ", the card is for " + o.to +
                           ": its values are mapped, not calibrated there (see the card's header)");
  const std::string ext = format == engines::CardFormat::kEdemCsv ? "csv"
                          : format == engines::CardFormat::kJson  ? "json"
                                                                  : "in";
  out.card = o.card ? *o.card
                    : dir / "material" /
                          (study.name + "." + (o.to == "edem-csv" ? "edem" : o.to) + "." + ext);
  if (out.card.has_parent_path()) std::filesystem::create_directories(out.card.parent_path());
  io::write_file_atomically(out.card, *card.text);
  return out;
}

}  // namespace demcal::study
