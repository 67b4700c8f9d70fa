#include "study/study_calibration.hpp"

#include "calibrate/calibration.hpp"
#include "calibrate/confidence_region.hpp"
#include "calibrate/report/labels.hpp"
#include "config/calibration_config.hpp"
#include "config/study_config.hpp"
#include "study/calibration_targets.hpp"
#include "study/simulation_run.hpp"
#include "study/stage_cache.hpp"
#include "study/study_directory.hpp"
#include "surrogate/gaussian_process.hpp"
#include "surrogate/surrogate_fit.hpp"

#include <algorithm>
#include <fstream>
#include <optional>
#include <sstream>

namespace demcal::study {

using demcal::config::CalibrationConfig;
using demcal::config::ConfigError;
using demcal::config::StudyConfig;
using demcal::config::load_study_config;
namespace {

namespace fs = std::filesystem;

std::string theta_text_plain(const std::vector<calibrate::ParameterBounds>& params,
                             const Eigen::VectorXd& theta) {
  std::ostringstream s;
  s << "(";
  for (std::size_t i = 0; i < params.size(); ++i)
    s << (i ? ", " : "") << params[i].name << " = "
      << calibrate::human_number(theta(static_cast<Eigen::Index>(i)), 4);
  s << ")";
  return s.str();
}

}  // namespace

std::optional<calibrate::Headline> read_calibration_headline(const fs::path& calibration_json) {
  try {
    std::ifstream in(calibration_json);
    const auto j = nlohmann::json::parse(in);
    if (!j.contains("headline")) return std::nullopt;
    calibrate::Headline head;
    head.header = j["headline"]["header"].get<std::vector<std::string>>();
    head.rows = j["headline"]["rows"].get<std::vector<std::vector<std::string>>>();
    head.sentences = j["headline"]["sentences"].get<std::vector<std::string>>();
    return head;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

VerificationResult simulate_verification(const VerificationRun& run) {
  SimulationRunOptions options;
  options.config = run.config;
  options.overrides = run.overrides;
  options.output_dir = run.output_dir.string();
  options.overwrite = true;
  SilentObserver silent;
  const SimulationRunOutcome done = run_simulation(options, silent);
  return {done.observables, done.run_record};
}

StudyCalibrationOutcome calibrate_study_recordings(const StudyCalibrationOptions& o,
                                                   const Verifier& verify,
                                                   ProgressObserver& observer) {
  StudyConfig study = load_study_config(o.study, o.overrides);
  if (!study.calibration)
    throw ConfigError(study.file + ": the study has no [calibration] table (recordings = \"...\")");
  if (!study.design)
    throw ConfigError(study.file + ": the study has no [design] table; calibrate needs its bounds");
  const CalibrationConfig& cc = *study.calibration;
  const auto recordings = study_recordings(study);
  const auto params = design_bounds(study);
  const fs::path dir = study_directory(o.output_dir, study.name);
  const std::vector<calibrate::Target> all = calibration_targets(study, dir, recordings);
  const calibrate::CalibrationOptions co = calibration_options(cc);
  observer.on_message("calibrating " + study.name + " on " + std::to_string(all.size()) +
                      " recordings ...");
  const auto joint = calibrate::calibrate(params, all, co);
  std::optional<calibrate::CalibrationResult> alone;
  std::string alone_name = cc.alone ? *cc.alone : "angle_of_repose_deg";
  std::vector<calibrate::Target> single;
  for (const auto& t : all)
    if (t.observable == alone_name) single.push_back(t);
  if (!alone_name.empty() && single.size() < all.size() && !single.empty()) {
    observer.on_message("calibrating " + study.name + " on the " +
                        calibrate::observable_name(alone_name) + " alone, for the comparison ...");
    alone = calibrate::calibrate(params, single, co);
  } else if (cc.alone && !cc.alone->empty() && single.empty()) {
    throw ConfigError(study.file + ": [calibration] alone = \"" + alone_name +
                      "\" is not among the recordings");
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
        if (std::none_of(points.begin(), points.end(),
                         [&](const auto& q) { return q.isApprox(x, 1e-12); }))
          points.push_back(x);
      }
    }
    ro.design_points.resize(static_cast<Eigen::Index>(points.size()),
                            static_cast<Eigen::Index>(params.size()));
    for (std::size_t r = 0; r < points.size(); ++r)
      ro.design_points.row(static_cast<Eigen::Index>(r)) = points[r];
  }
  if (!cc.reference_label.empty()) {
    if (cc.reference_point.size() != params.size())
      throw ConfigError(study.file + ": [calibration] reference_point has " +
                        std::to_string(cc.reference_point.size()) +
                        " values; expected one per [design] parameter (" +
                        std::to_string(params.size()) + ")");
    calibrate::ReferencePoint ref{cc.reference_label, cc.reference_point};
    const Eigen::VectorXd theta = Eigen::Map<const Eigen::VectorXd>(
        cc.reference_point.data(), static_cast<Eigen::Index>(cc.reference_point.size()));
    const auto place = [&](const std::vector<calibrate::Target>& targets,
                           const calibrate::CalibrationResult& r, double& delta, bool& inside) {
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
    VerificationRun run;
    run.config = cc.verify;
    for (std::size_t i = 0; i < params.size(); ++i) {
      std::ostringstream s;
      s.precision(17);
      s << params[i].name << "=" << joint.minima[0].theta(static_cast<Eigen::Index>(i));
      run.overrides.push_back(s.str());
    }
    run.output_dir = dir / "verification" / cc.verify.parent_path().filename();
    observer.on_message("verifying: " + cc.verify.string() + " at the calibrated point ...");
    const VerificationResult v = verify(run);
    std::ostringstream s;
    s << "Verification: " << cc.verify.string() << " simulated at the calibrated point "
      << theta_text_plain(params, joint.minima[0].theta) << " gives";
    for (const auto& [k, val] : v.observables.items())
      if (!val.is_null()) s << " " << k << " = " << val.dump();
    s << " (" << v.run_record.string() << ").";
    ro.remarks.push_back(s.str());
  }
  // An adaptive design: what it ran, in which batch and why, and how it ended
  // (design_history.json, written by the campaign: study/adaptive_campaign.hpp).
  if (study.design && study.design->adaptive && fs::exists(dir / "design_history.json")) {
    std::ifstream in(dir / "design_history.json");
    const auto history = nlohmann::json::parse(in, nullptr, false);
    if (history.is_object() && history.contains("text")) {
      ro.remarks.push_back("The adaptive design (kind = \"adaptive\"; the acquisition, the batch "
                           "rule and the stopping rule with their references: "
                           "docs/adaptive_design.md), batch by batch:");
      std::istringstream lines(history.at("text").get<std::string>());
      for (std::string line; std::getline(lines, line);)
        if (!line.empty()) ro.remarks.push_back(line);
    }
  }
  // Written whole beside the previous report, then put in its place.
  const fs::path report_dir = dir / "reports" / "calibration";
  fs::create_directories(report_dir.parent_path());
  const fs::path staged = staging_directory(report_dir);
  const auto files =
      calibrate::write_calibration_report(staged, alone ? &*alone : nullptr, joint, ro);
  replace_directory(staged, report_dir);
  const fs::path html = report_dir / fs::relative(files.html, staged);
  const fs::path json = report_dir / fs::relative(files.json, staged);
  // The closing summary: the report's headline, made by the same code.
  return {html, json, study.name,
          calibrate::calibration_headline(alone ? &*alone : nullptr, joint, ro)};
}

}  // namespace demcal::study
