#include "study/surrogate_fitting.hpp"

#include "calibrate/report/inspection_report.hpp"
#include "calibrate/report/labels.hpp"
#include "config/doe_csv.hpp"
#include "config/study_config.hpp"
#include "config/surrogate_config.hpp"
#include "config/toml_reader.hpp"
#include "dem/output/atomic_file.hpp"
#include "study/stage_cache.hpp"
#include "surrogate/surrogate_fit.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace demcal::study {

using demcal::config::ConfigError;
using demcal::config::DoeCsv;
using demcal::config::DoeCsvRow;
using demcal::config::StudyConfig;
using demcal::config::SurrogateConfig;
using demcal::config::load_study_config;
using demcal::config::read_doe_csv;
namespace reader = demcal::config::reader;
namespace {

namespace fs = std::filesystem;

struct Campaign {
  StudyConfig study;
  DoeCsv table;
  fs::path dir;
  std::vector<double> lower, upper;
};

std::string point_text(const std::vector<std::string>& names, const std::vector<double>& values) {
  std::string s;
  for (std::size_t k = 0; k < names.size() && k < values.size(); ++k)
    s += (s.empty() ? "" : ", ") + names[k] + " = " + reader::format_number(values[k]);
  return s;
}

// Each row against the study's design: a point inside the design box,
// replicates of one point at one place. (The setup name, which becomes a file
// name, is checked by read_doe_csv.)
void check_rows_against_study(const Campaign& c) {
  std::map<std::pair<std::string, int>, const DoeCsvRow*> first_of_point;
  for (const DoeCsvRow& r : c.table.rows) {
    const std::string at = c.table.file + ":" + std::to_string(r.line) + ": ";
    for (std::size_t k = 0; k < r.parameters.size(); ++k) {
      const double span = c.upper[k] - c.lower[k];
      const double slack = 1e-9 * (std::fabs(span) + std::fabs(c.upper[k]) + std::fabs(c.lower[k]));
      if (r.parameters[k] < c.lower[k] - slack || r.parameters[k] > c.upper[k] + slack)
        throw ConfigError(at + "column " + c.table.parameter_names[k] + ": " +
                          reader::format_number(r.parameters[k]) +
                          " lies outside the design box [" + reader::format_number(c.lower[k]) +
                          ", " + reader::format_number(c.upper[k]) + "] of " + c.study.file +
                          " (the surrogates are valid inside it only)");
    }
    const auto [it, fresh] = first_of_point.try_emplace({r.apparatus, r.point}, &r);
    if (!fresh && it->second->parameters != r.parameters)
      throw ConfigError(
          at + "point " + std::to_string(r.point) + " replicate " + std::to_string(r.replicate) +
          " is at (" + point_text(c.table.parameter_names, r.parameters) + "), but line " +
          std::to_string(it->second->line) + " puts point " + std::to_string(r.point) + " at (" +
          point_text(c.table.parameter_names, it->second->parameters) +
          "); replicates of a point share its parameters");
  }
}

Campaign load_campaign(const SurrogateFitOptions& o) {
  Campaign c{load_study_config(o.study, o.overrides), {}, {}, {}, {}};
  c.dir = study_directory(o.output_dir, c.study.name);
  c.table = read_doe_csv(o.doe_csv ? *o.doe_csv : c.dir / "doe.csv");
  // The design box comes from the study's [design]: the surrogates are valid
  // inside it, and the calibration searches it.
  if (!c.study.design)
    throw ConfigError(c.study.file +
                      ": the study has no [design] table; fit needs its parameter bounds");
  const auto& params = c.study.design->spec.parameters;
  if (params.size() != c.table.parameter_names.size())
    throw ConfigError(c.table.file + ": " + std::to_string(c.table.parameter_names.size()) +
                      " parameter columns, but the study's [design] has " +
                      std::to_string(params.size()));
  for (std::size_t k = 0; k < params.size(); ++k) {
    if (params[k].name != c.table.parameter_names[k])
      throw ConfigError(c.table.file + ":1: parameter column " + std::to_string(k + 1) + " is \"" +
                        c.table.parameter_names[k] + "\", the study's [design] has \"" +
                        params[k].name + "\"");
    c.lower.push_back(params[k].lower);
    c.upper.push_back(params[k].upper);
  }
  check_rows_against_study(c);
  return c;
}

// The runs of one apparatus and one observable, replicates grouped by point.
surrogate::ReplicatedData data_for(const Campaign& c, const std::string& apparatus,
                                   int observable) {
  surrogate::ReplicatedData d;
  d.input_names = c.table.parameter_names;
  d.lower = c.lower;
  d.upper = c.upper;
  d.output_name = c.table.observable_names[static_cast<std::size_t>(observable)];
  std::vector<const DoeCsvRow*> rows;
  for (const auto& r : c.table.rows)
    if (r.apparatus == apparatus && r.status == "ok") rows.push_back(&r);
  const auto p = static_cast<Eigen::Index>(d.input_names.size());
  d.x.resize(static_cast<Eigen::Index>(rows.size()), p);
  d.y.resize(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    for (Eigen::Index j = 0; j < p; ++j)
      d.x(k, j) = rows[i]->parameters[static_cast<std::size_t>(j)];
    d.y(k) = rows[i]->observables[static_cast<std::size_t>(observable)];
    d.group.push_back(rows[i]->point);
  }
  return d;
}

std::set<std::string> apparatus_in(const DoeCsv& t) {
  std::set<std::string> a;
  for (const auto& r : t.rows) a.insert(r.apparatus);
  return a;
}

fs::path surrogate_file(const fs::path& dir, const std::string& apparatus,
                        const std::string& observable) {
  return dir / "surrogates" / (apparatus + "." + observable + ".json");
}

}  // namespace

SurrogateFitOutcome fit_surrogates(const SurrogateFitOptions& o, ProgressObserver& observer) {
  Campaign c = load_campaign(o);
  const SurrogateConfig config = c.study.surrogate ? *c.study.surrogate : SurrogateConfig{};
  SurrogateFitOutcome outcome;
  std::size_t failed_rows = 0, missing_rows = 0;
  for (const auto& r : c.table.rows) {
    failed_rows += r.status == "failed";
    missing_rows += r.status == "missing";
  }
  if (failed_rows + missing_rows > 0)
    outcome.warnings.push_back(c.table.file + ": " + std::to_string(failed_rows) + " failed and " +
                               std::to_string(missing_rows) +
                               " missing runs are left out of the fit");
  std::set<std::string> fitted_names;
  // Every surrogate is written into a staging directory that replaces
  // surrogates/ only once all are: a fit that fails halfway leaves the
  // previous set whole (calibrate never sees a mixed one).
  const fs::path final_dir = c.dir / "surrogates";
  fs::create_directories(c.dir);
  const fs::path staged = staging_directory(final_dir);
  struct RemoveStaged {
    fs::path dir;
    ~RemoveStaged() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{staged};
  for (const auto& apparatus : apparatus_in(c.table)) {
    for (std::size_t k = 0; k < c.table.observable_names.size(); ++k) {
      const std::string& name = c.table.observable_names[k];
      const bool requested = config.observables.empty() ||
                             std::find(config.observables.begin(), config.observables.end(),
                                       name) != config.observables.end();
      if (!requested) continue;
      auto data = data_for(c, apparatus, static_cast<int>(k));
      std::size_t finite = 0;
      for (Eigen::Index i = 0; i < data.y.size(); ++i) finite += std::isfinite(data.y(i));
      if (finite == 0)
        continue;  // this apparatus does not measure it (a container has no discharge time)
      // A column with one value throughout: nothing to fit (Q2 undefined), and
      // the calibration could not move it.
      {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (Eigen::Index i = 0; i < data.y.size(); ++i)
          if (std::isfinite(data.y(i))) {
            lo = std::min(lo, data.y(i));
            hi = std::max(hi, data.y(i));
          }
        if (finite > 1 && lo == hi)
          throw ConfigError(
              c.table.file + ": column " + name + ": every " + apparatus + " run gives " +
              reader::format_number(lo) +
              "; a constant cannot be fitted (its Q2 is undefined); leave the observable out "
              "of [surrogate] observables or check the runs");
      }
      fitted_names.insert(name);
      surrogate::FittedSurrogate f;
      try {
        f = surrogate::fit_surrogate(data, config.spec);
      } catch (const std::invalid_argument& e) {
        throw ConfigError(c.table.file + ": " + apparatus + ": " + e.what());
      }
      const fs::path file = surrogate_file(c.dir, apparatus, name);
      nlohmann::json j = f.to_json();
      j["setup"] = apparatus;
      j["study"] = c.study.name;
      j["doe_csv"] = c.table.file;
      dem::write_file_atomically(staged / file.filename(), j.dump(1) + "\n");
      outcome.files.push_back(file);
      if (!f.scatter_check.within_scatter)
        outcome.warnings.push_back(calibrate::humanize_identifiers(f.scatter_check.message));
      {
        std::ostringstream s;
        using calibrate::human_number;
        s << apparatus << " " << calibrate::observable_label(name) << ": "
          << calibrate::surrogate_description(f) << "; " << f.runs << " runs at "
          << f.scatter.points << " points; leave-one-out RMSE " << human_number(f.validation.rmse)
          << ", Q² " << human_number(f.validation.q_squared) << "; DEM scatter sd "
          << human_number(f.scatter.sd);
        if (f.scatter_trend.tested && f.scatter_trend.p_value < surrogate::kScatterTrendAlpha)
          s << " pooled; it changes over the design (p = " << human_number(f.scatter_trend.p_value)
            << "): " << human_number(f.scatter_trend.sd_smallest) << " to "
            << human_number(f.scatter_trend.sd_largest) << " at the replicated points";
        observer.on_message(s.str());
      }
    }
  }
  for (const auto& name : config.observables)
    if (!fitted_names.count(name))
      throw ConfigError(c.study.file + ": [surrogate] observables lists " + name +
                        ", but no run in " + c.table.file + " measured it");
  if (outcome.files.empty()) throw ConfigError(c.table.file + ": no observable with data to fit");
  replace_directory(staged, final_dir);
  return outcome;
}

InspectionOutcome inspect_surrogates(const SurrogateFitOptions& o, ProgressObserver& observer) {
  Campaign c = load_campaign(o);
  std::vector<calibrate::InspectedSurrogate> list;
  const fs::path sdir = c.dir / "surrogates";
  if (!fs::is_directory(sdir))
    throw ConfigError(sdir.string() + ": no surrogates; run `demcal fit` first");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(sdir))
    if (e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& file : files) {
    std::ifstream in = config::open_input_file(
        file, "a surrogate file (JSON) written by `demcal fit`", "cannot open the surrogate file");
    nlohmann::json j;
    try {
      in >> j;
    } catch (const nlohmann::json::exception& e) {
      throw ConfigError(file.string() + ": not a surrogate file (" + e.what() + ")");
    }
    calibrate::InspectedSurrogate s;
    s.setup = j.value("setup", "");
    try {
      s.fit = surrogate::fitted_surrogate_from_json(j);
    } catch (const std::exception& e) {
      throw ConfigError(file.string() + ": not a surrogate file (" + e.what() + ")");
    }
    const auto data = data_for(c, s.setup, c.table.observable_index(s.fit.output_name));
    s.design_x = data.x;
    s.design_y = data.y;
    if (s.fit.spec.model == "gaussian_process") {
      surrogate::SurrogateSpec poly;
      poly.model = "polynomial";
      try {
        s.companion_polynomial = surrogate::fit_surrogate(data, poly);
      } catch (const std::invalid_argument& e) {
        observer.on_message("note: no comparison polynomial for " + s.setup + " " +
                            s.fit.output_name + ": " + e.what());
      }
    }
    list.push_back(std::move(s));
  }
  if (list.empty()) throw ConfigError(sdir.string() + ": no surrogates; run `demcal fit` first");
  calibrate::InspectionReportOptions ro;
  ro.study_name = c.study.name;
  ro.parameter_names = c.table.parameter_names;
  ro.lower = c.lower;
  ro.upper = c.upper;
  // Written whole beside the previous report, then put in its place.
  const fs::path report_dir = c.dir / "reports" / "inspection";
  fs::create_directories(report_dir.parent_path());
  const fs::path staged = staging_directory(report_dir);
  const auto files_out = calibrate::write_inspection_report(staged, list, ro);
  replace_directory(staged, report_dir);
  return {report_dir / fs::relative(files_out.html, staged), files_out.warnings};
}

}  // namespace demcal::study
