#include "study/study_pipeline.hpp"

#include "config/canonical_json.hpp"
#include "config/study_config.hpp"
#include "study/stage_cache.hpp"
#include "study/study_directory.hpp"

#include <fstream>
#include <sstream>

namespace demcal::study {

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A table of the resolved study as TOML text; empty when the study has none.
std::string table_text(const toml::table& t, const char* key) {
  std::ostringstream s;
  if (const auto* n = t.get(key)) s << toml::toml_formatter(toml::table{{key, *n}});
  return s.str();
}

// Everything the calibration reads of the laboratory: the recordings CSV and, with
// [raw_recordings], that table and every raw file's name and bytes, so that an edited
// profile or m(t) file recalibrates instead of leaving the report stale.
std::string recordings_text(const config::StudyConfig& study) {
  std::string text;
  if (!study.calibration->recordings.empty()) text = slurp(study.calibration->recordings);
  if (!study.raw_recordings) return text;
  text += table_text(study.resolved, "raw_recordings");
  for (const config::RawSetupRecordings& setup : study.raw_recordings->setups)
    for (const auto* files : {&setup.profiles, &setup.mass_series})
      for (const fs::path& f : *files) {
        text += '\n';
        text += f.string();
        text += '\n';
        text += slurp(f);
      }
  return text;
}

}  // namespace

fs::path run_study_pipeline(const StudyPipelineOptions& o, StudyPipelineSteps& steps,
                            ProgressObserver& observer) {
  if (!steps.run_design()) return {};
  const config::StudyConfig study = config::load_study_config(o.study, o.overrides);
  const fs::path dir = study_directory(o.output_dir, study.name);
  StageCache stages(dir / "stages.json");
  const std::string fit_digest =
      config::sha256_hex(slurp(dir / "doe.csv") + "\n" + table_text(study.resolved, "surrogate") +
                         table_text(study.resolved, "design"));
  const fs::path surrogates = dir / "surrogates";
  if (o.force || !stages.current("fit", fit_digest, surrogates)) {
    steps.fit();
    stages.done("fit", fit_digest, surrogates);
    stages.forget("inspect");
    stages.forget("calibrate");
  } else {
    observer.on_message("fit: up to date (doe.csv, [surrogate] and the surrogate files unchanged)");
  }
  // The later stages read the surrogate files: their digest is part of their inputs.
  const std::string surrogates_digest = directory_digest(surrogates);
  const std::string inspect_digest = config::sha256_hex(fit_digest + surrogates_digest);
  const fs::path inspection = dir / "reports" / "inspection" / "index.html";
  if (o.force || !stages.current("inspect", inspect_digest, inspection.parent_path()) ||
      !fs::exists(inspection)) {
    steps.inspect();
    stages.done("inspect", inspect_digest, inspection.parent_path());
  } else {
    observer.on_message("inspect: up to date");
    steps.skipped("inspect", study.name, inspection);
  }
  if (!study.calibration) return inspection;
  const std::string cal_digest = config::sha256_hex(fit_digest + surrogates_digest +
                                                    table_text(study.resolved, "calibration") +
                                                    recordings_text(study));
  const fs::path report = dir / "reports" / "calibration" / "index.html";
  if (o.force || !stages.current("calibrate", cal_digest, report.parent_path()) ||
      !fs::exists(report)) {
    steps.calibrate();
    stages.done("calibrate", cal_digest, report.parent_path());
  } else {
    observer.on_message(
        "calibrate: up to date (surrogates, [calibration] and recordings unchanged)");
    steps.skipped("calibrate", study.name, report);
  }
  return report;
}

}  // namespace demcal::study
