#include "cli/calibrate_command.hpp"

#include "calibrate/calibration.hpp"
#include "calibrate/confidence_region.hpp"
#include "calibrate/report/calibration_report.hpp"
#include "calibrate/report/labels.hpp"
#include "config/calibration_config.hpp"
#include "study/calibration_targets.hpp"
#include "cli/console.hpp"
#include "config/recordings_csv.hpp"
#include "study/run_store.hpp"
#include "study/stage_cache.hpp"
#include "cli/simulate_command.hpp"
#include "config/study_config.hpp"
#include "dem/output/atomic_file.hpp"
#include "surrogate/gaussian_process.hpp"
#include "surrogate/surrogate_fit.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace demcal::cli {

using namespace demcal::config;
using namespace demcal::study;
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string theta_text_plain(const std::vector<calibrate::ParameterBounds>& params, const Eigen::VectorXd& theta) {
  std::ostringstream s;
  s << "(";
  for (std::size_t i = 0; i < params.size(); ++i)
    s << (i ? ", " : "") << params[i].name << " = " << calibrate::human_number(theta(static_cast<Eigen::Index>(i)), 4);
  s << ")";
  return s.str();
}

// The closing summary: the report's headline box as text.
void print_headline(std::ostream& log, const std::string& study, const calibrate::Headline& head) {
  std::vector<std::vector<std::string>> rows{head.header};
  for (const auto& r : head.rows) rows.push_back(r);
  log << "\n" << study << ": the calibrated values\n" << aligned_table(rows);
  for (const auto& s : head.sentences) log << "  - " << s << "\n";
  log << "  (the solver's notes, the figures and the tables: in the calibration report)\n\n";
}

}  // namespace

CalibrateOutcome calibrate_study(const FitOptions& o, std::ostream& out, std::ostream& log) {
  StudyConfig study = load_study_config(o.study, o.overrides);
  if (!study.calibration)
    throw ConfigError(study.file + ": the study has no [calibration] table (recordings = \"...\")");
  if (!study.design) throw ConfigError(study.file + ": the study has no [design] table; calibrate needs its bounds");
  const CalibrationConfig& cc = *study.calibration;
  const auto recordings = study_recordings(study);
  const auto params = design_bounds(study);
  const fs::path dir = study_directory(o.output_dir, study.name);
  const std::vector<calibrate::Target> all = calibration_targets(study, dir, recordings);
  const calibrate::CalibrationOptions co = calibration_options(cc);
  log << "calibrating " << study.name << " on " << all.size() << " recordings ...\n";
  const auto joint = calibrate::calibrate(params, all, co);
  std::optional<calibrate::CalibrationResult> alone;
  std::string alone_name = cc.alone ? *cc.alone : "angle_of_repose_deg";
  std::vector<calibrate::Target> single;
  for (const auto& t : all)
    if (t.observable == alone_name) single.push_back(t);
  if (!alone_name.empty() && single.size() < all.size() && !single.empty()) {
    log << "calibrating " << study.name << " on the " << calibrate::observable_name(alone_name)
        << " alone, for the comparison ...\n";
    alone = calibrate::calibrate(params, single, co);
  } else if (cc.alone && !cc.alone->empty() && single.empty()) {
    throw ConfigError(study.file + ": [calibration] alone = \"" + alone_name + "\" is not among the recordings");
  }

  calibrate::CalibrationReportOptions ro;
  ro.study_name = study.name;
  // The design points (those a Gaussian process was fitted to) and the surrogates, for
  // the report's region parts and its diagnostics over the region.
  {
    std::vector<Eigen::RowVectorXd> points;
    for (const auto& t : all) {
      ro.models.push_back(t.model);
      const auto* gp = dynamic_cast<const surrogate::GaussianProcess*>(t.model.get());
      if (!gp || gp->state().x.cols() != static_cast<Eigen::Index>(params.size())) continue;
      for (Eigen::Index r = 0; r < gp->state().x.rows(); ++r) {
        const Eigen::RowVectorXd x = gp->state().x.row(r);
        if (std::none_of(points.begin(), points.end(), [&](const auto& q) { return q.isApprox(x, 1e-12); }))
          points.push_back(x);
      }
    }
    ro.design_points.resize(static_cast<Eigen::Index>(points.size()), static_cast<Eigen::Index>(params.size()));
    for (std::size_t r = 0; r < points.size(); ++r) ro.design_points.row(static_cast<Eigen::Index>(r)) = points[r];
  }
  if (!cc.reference_label.empty()) {
    if (cc.reference_point.size() != params.size())
      throw ConfigError(study.file + ": [calibration] reference_point has " + std::to_string(cc.reference_point.size()) +
                        " values; expected one per [design] parameter (" + std::to_string(params.size()) + ")");
    calibrate::ReferencePoint ref{cc.reference_label, cc.reference_point};
    const Eigen::VectorXd theta = Eigen::Map<const Eigen::VectorXd>(cc.reference_point.data(),
                                                                    static_cast<Eigen::Index>(cc.reference_point.size()));
    const auto place = [&](const std::vector<calibrate::Target>& targets, const calibrate::CalibrationResult& r,
                           double& delta, bool& inside) {
      if (!r.region.available) return;
      const calibrate::CalibrationProblem problem(params, targets);
      delta = problem.chi_squared(theta) - r.region.chi_squared_min;
      inside = calibrate::region_contains(problem, r.region, theta);
    };
    place(all, joint, ref.delta_chi_square_joint, ref.inside_joint);
    if (alone) place(single, *alone, ref.delta_chi_square_alone, ref.inside_alone);
    ro.references.push_back(ref);
  }
  if (!cc.verify.empty() && !joint.minima.empty()) {
    // Another study's apparatus at the calibrated point: the paper verified
    // its pair on a conical pile, a test outside the calibration's design.
    SimulateOptions so;
    so.config = cc.verify;
    for (std::size_t i = 0; i < params.size(); ++i) {
      std::ostringstream s;
      s.precision(17);
      s << params[i].name << "=" << joint.minima[0].theta(static_cast<Eigen::Index>(i));
      so.overrides.push_back(s.str());
    }
    so.output_dir = (dir / "verification" / cc.verify.parent_path().filename()).string();
    so.overwrite = true;
    so.quiet = true;
    log << "verifying: " << cc.verify.string() << " at the calibrated point ...\n";
    std::ostringstream sink;
    const auto v = simulate(so, sink, log);
    std::ostringstream s;
    s << "Verification: " << cc.verify.string() << " simulated at the calibrated point "
      << theta_text_plain(params, joint.minima[0].theta) << " gives";
    for (const auto& [k, val] : v.observables.items())
      if (!val.is_null()) s << " " << k << " = " << val.dump();
    s << " (" << v.run_record.string() << ").";
    ro.remarks.push_back(s.str());
  }
  // Written whole beside the previous report, then put in its place.
  const fs::path report_dir = dir / "reports" / "calibration";
  fs::create_directories(report_dir.parent_path());
  const fs::path staged = staging_directory(report_dir);
  const auto files = calibrate::write_calibration_report(staged, alone ? &*alone : nullptr, joint, ro);
  replace_directory(staged, report_dir);
  const fs::path html = report_dir / fs::relative(files.html, staged);
  const fs::path json = report_dir / fs::relative(files.json, staged);
  // The closing summary: the report's headline, made by the same code.
  if (!o.quiet) {
    print_headline(log, study.name, calibrate::calibration_headline(alone ? &*alone : nullptr, joint, ro));
  }
  out << "calibration report: " << html.string() << "\n";
  return {html, json};
}

namespace {

std::string table_text(const toml::table& t, const char* key) {
  std::ostringstream s;
  if (const auto* n = t.get(key)) s << toml::toml_formatter(toml::table{{key, *n}});
  return s.str();
}

}  // namespace

fs::path run_study(const StudyOptions& o, std::ostream& out, std::ostream& log) {
  const DoeOutcome d = run_doe(o.doe, out, log);
  if (d.not_run > 0 || d.missing > 0) {
    log << "demcal study: " << d.not_run + d.missing << " runs are not done; run the same command again\n";
    return {};
  }
  StudyConfig study = load_study_config(o.doe.study, o.doe.overrides);
  const fs::path dir = study_directory(o.doe.output_dir, study.name);
  StageCache stages(dir / "stages.json");
  FitOptions fo;
  fo.study = o.doe.study;
  fo.overrides = o.doe.overrides;
  fo.output_dir = o.doe.output_dir;
  fo.quiet = o.doe.quiet;
  const std::string doe_csv = slurp(dir / "doe.csv");
  const std::string fit_digest = sha256_hex(doe_csv + "\n" + table_text(study.resolved, "surrogate") +
                                            table_text(study.resolved, "design"));
  const fs::path surrogates = dir / "surrogates";
  if (o.force || !stages.current("fit", fit_digest, surrogates)) {
    fit(fo, out, log);
    stages.done("fit", fit_digest, surrogates);
    stages.forget("inspect");
    stages.forget("calibrate");
  } else {
    log << "fit: up to date (doe.csv, [surrogate] and the surrogate files unchanged)\n";
  }
  // The later stages read the surrogate files: their digest is part of their inputs.
  const std::string surrogates_digest = directory_digest(surrogates);
  const std::string inspect_digest = sha256_hex(fit_digest + surrogates_digest);
  const fs::path inspection = dir / "reports" / "inspection" / "index.html";
  if (o.force || !stages.current("inspect", inspect_digest, inspection.parent_path()) || !fs::exists(inspection)) {
    inspect(fo, out, log);
    stages.done("inspect", inspect_digest, inspection.parent_path());
  } else {
    log << "inspect: up to date\n";
    out << "inspection report: " << inspection.string() << "\n";
  }
  if (!study.calibration) return inspection;
  const std::string cal_digest = sha256_hex(fit_digest + surrogates_digest + table_text(study.resolved, "calibration") +
                                            slurp(study.calibration->recordings));
  const fs::path report = dir / "reports" / "calibration" / "index.html";
  if (o.force || !stages.current("calibrate", cal_digest, report.parent_path()) || !fs::exists(report)) {
    calibrate_study(fo, out, log);
    stages.done("calibrate", cal_digest, report.parent_path());
  } else {
    log << "calibrate: up to date (surrogates, [calibration] and recordings unchanged)\n";
    // The main result all the same: the headline the report's JSON keeps.
    try {
      std::ifstream in(report.parent_path() / "calibration.json");
      const auto j = nlohmann::json::parse(in);
      if (!o.doe.quiet && j.contains("headline")) {
        calibrate::Headline head;
        head.header = j["headline"]["header"].get<std::vector<std::string>>();
        head.rows = j["headline"]["rows"].get<std::vector<std::vector<std::string>>>();
        head.sentences = j["headline"]["sentences"].get<std::vector<std::string>>();
        print_headline(log, study.name, head);
      }
    } catch (const std::exception&) {
      // An older report without a headline: its path is enough.
    }
    out << "calibration report: " << report.string() << "\n";
  }
  return report;
}

}  // namespace demcal::cli
