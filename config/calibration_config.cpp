#include "config/calibration_config.hpp"

#include "config/observables.hpp"
#include "config/study_config.hpp"
#include "config/toml_reader.hpp"

#include <limits>

namespace demcal::config {

std::optional<CalibrationConfig> read_calibration(reader::Table& root,
                                                  const std::string& study_file,
                                                  const std::optional<DesignConfig>& design,
                                                  bool has_raw_recordings) {
  if (!root.has("calibration")) return std::nullopt;
  reader::Table t = root.table("calibration");
  CalibrationConfig c;
  // Without raw series the CSV is the only source of recordings, so the key is required
  // (and its absence reported as before).
  if (!has_raw_recordings && !t.has("recordings"))
    // Name both ways in, so that a laboratory with only profiles and m(t) files learns of the
    // second.
    t.fail("recordings",
           "missing required key; expected a string (the path of the recordings CSV), or a "
           "[raw_recordings] table giving each setup's surface profiles and mass series");
  if (t.has("recordings")) {
    const std::string rec = t.string("recordings");
    if (rec.empty())
      t.fail("recordings", "expected the path of the recordings CSV, got an empty string");
    const std::filesystem::path p(rec);
    c.recordings = p.is_absolute() ? p : std::filesystem::path(study_file).parent_path() / p;
  }
  if (t.has("alone")) {
    std::vector<std::string> options = observable_names();
    options.push_back("");
    c.alone = t.choice("alone", options);
  }
  c.confidence = t.number_or("confidence", 0.95, reader::between(0, true, 1, true));
  c.grid_points_per_axis = static_cast<int>(t.integer_or("grid_points_per_axis", 121, 11, 1001));
  c.multistart_points = static_cast<int>(t.integer_or("multistart_points", 16, 1, 1000));
  c.mcmc_samples = static_cast<int>(t.integer_or("mcmc_samples", 20000, 0, 10000000));
  c.mcmc_burn_in = static_cast<int>(t.integer_or("mcmc_burn_in", 4000, 0, 10000000));
  c.mcmc_chains = static_cast<int>(t.integer_or("mcmc_chains", 2, 1, 16));
  c.seed = static_cast<std::uint64_t>(
      t.integer_or("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  const std::string verify = t.string_or("verify", "");
  if (!verify.empty()) {
    const std::filesystem::path v(verify);
    c.verify = v.is_absolute() ? v : std::filesystem::path(study_file).parent_path() / v;
    if (!std::filesystem::exists(c.verify))
      t.fail("verify", "no such study config: " + c.verify.string());
    if (std::filesystem::is_directory(c.verify))
      t.fail("verify", c.verify.string() + " is a directory; expected a study config file");
    // Read now, not after both calibrations have run: a verification that cannot start
    // should stop `--dry-run`, not the end of a study. Only read (its own keys are checked
    // when it runs), so that two studies verifying each other do not recurse.
    ConfigDocument doc;
    try {
      doc = read_config_file(c.verify);
    } catch (const ConfigError& e) {
      t.fail("verify", std::string("cannot be read as a study config: ") + e.what());
    }
    if (!is_study_config(doc))
      t.fail("verify", c.verify.string() +
                           " is not a study config (it has no [apparatus] table); verification "
                           "runs a study's apparatus at the calibrated point");
  }
  c.reference_label = t.string_or("reference_label", "");
  c.reference_point = t.numbers_or_empty("reference_point");
  if (c.reference_label.empty() != c.reference_point.empty())
    t.fail(c.reference_label.empty() ? "reference_point" : "reference_label",
           "reference_label and reference_point go together: give both or neither");
  if (design && !c.reference_point.empty()) {
    const auto& params = design->spec.parameters;
    // One value per parameter, in the design's order: checked here, at the key, rather than
    // after both calibrations have run. (A diagnosis' derived studies have no [calibration].)
    if (c.reference_point.size() != params.size()) {
      std::string names;
      for (const auto& q : params) names += (names.empty() ? "" : ", ") + q.name;
      t.fail("reference_point", "expected " + std::to_string(params.size()) +
                                    " values, one per [design] parameter (" + names + "), got " +
                                    std::to_string(c.reference_point.size()));
    }
    for (std::size_t k = 0; k < params.size(); ++k)
      if (c.reference_point[k] < params[k].lower || c.reference_point[k] > params[k].upper)
        t.fail("reference_point",
               "entry " + std::to_string(k) + " (" + params[k].name + ") is " +
                   reader::format_number(c.reference_point[k]) + ", outside the design box [" +
                   reader::format_number(params[k].lower) + ", " +
                   reader::format_number(params[k].upper) + "]; the surrogates say nothing there");
  }
  t.finish();
  return c;
}

}  // namespace demcal::config
