#include "study/doe_plan.hpp"

#include "config/study_config.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <utility>

namespace demcal::study {

using config::build_study;
using config::ConfigDocument;
using config::ConfigError;
using config::replicate_seed;
using config::shortest_decimal;
using config::study_override_aliases;
using config::StudyApparatus;
using config::StudyConfig;
using config::StudySource;
using config::without_file_prefix;

namespace {

std::string design_example() {
  return "e.g.\n  [design]\n  kind = \"full_factorial\"\n  replicates = 1\n"
         "  parameters = { mu_r = { lower = 0.05, upper = 0.6, levels = 5 }, "
         "mu_s = { lower = 0.2, upper = 0.9, levels = 5 } }";
}

}  // namespace

std::string describe_point(const DoePlan& plan, std::size_t point) {
  std::string s;
  const auto& params = plan.design.spec.parameters;
  for (std::size_t i = 0; i < params.size(); ++i) {
    if (!s.empty()) s += ", ";
    s += params[i].name + " = " + shortest_decimal(plan.generated.points[point][i]);
  }
  return s;
}

ConfigDocument run_document(const DoePlan& plan, const PlannedRun& run) {
  ConfigDocument doc = plan.source.document();
  apply_design_values(doc, plan.design, plan.generated.points.at(run.point),
                      "design point " + std::to_string(run.point));
  set_config_value(doc, "study.seed",
                   toml::value<std::int64_t>(static_cast<std::int64_t>(run.seed)),
                   "replicate " + std::to_string(run.replicate) + "'s seed");
  set_config_value(doc, "study.threads", toml::value<std::int64_t>(plan.threads_per_run),
                   "--threads-per-run " + std::to_string(plan.threads_per_run));
  return doc;
}

DoePlan plan_doe(const std::filesystem::path& study, const std::vector<std::string>& overrides,
                 const std::vector<std::string>& apparatus, int threads_per_run) {
  if (threads_per_run < 1)
    throw ConfigError("--threads-per-run " + std::to_string(threads_per_run) +
                      ": expected an integer >= 1");
  DoePlan plan;
  plan.source = StudySource::read(study, {});
  plan.file = plan.source.file;
  plan.threads_per_run = threads_per_run;
  if (!is_study_config(plan.source.document()))
    throw ConfigError(plan.file +
                      ": not a study config (it has no [apparatus.*] tables); `demcal doe` runs "
                      "the design of a study");
  plan.source.overrides = overrides;

  {
    StudyConfig base = build_study(plan.source.document());
    plan.study_name = base.name;
    plan.study_seed = base.protocol.seed;
    plan.study_asks_for_vtk = base.output.vtk;
    if (!base.design)
      throw ConfigError(plan.file +
                        ":1: design: the study has no [design] table; `demcal doe` "
                        "runs the design it describes, " +
                        design_example());
    plan.design = *base.design;
    // A --set of a design parameter would be overwritten at every design point.
    for (const std::string& o : overrides) {
      const std::string key = o.substr(0, std::min(o.find('='), o.size()));
      const auto alias = study_override_aliases().find(key);
      const std::string path = alias == study_override_aliases().end() ? key : alias->second;
      const auto& params = plan.design.spec.parameters;
      for (std::size_t i = 0; i < params.size(); ++i) {
        bool tied = false;
        if (i < plan.design.tied_paths.size())
          for (const auto& t : plan.design.tied_paths[i]) tied = tied || t == path;
        if (key == params[i].name || path == plan.design.parameter_paths[i] || tied)
          throw ConfigError(plan.file + ":" + std::to_string(plan.design.parameter_lines[i]) +
                            ": --set " + o + ": " + key + " is set by the design parameter " +
                            params[i].name +
                            " at every design point, so the --set would be "
                            "ignored; change design.parameters." +
                            params[i].name + " (lower, upper) instead");
      }
    }
    if (apparatus.empty()) {
      for (const StudyApparatus& a : base.apparatus) plan.apparatus.push_back(a.name);
    } else {
      // In the study's order, each once; select_apparatus reports one not defined.
      std::vector<bool> wanted(base.apparatus.size(), false);
      for (const std::string& name : apparatus) {
        const StudyApparatus& a = select_apparatus(base, name);
        wanted[static_cast<std::size_t>(&a - base.apparatus.data())] = true;
      }
      for (std::size_t i = 0; i < base.apparatus.size(); ++i)
        if (wanted[i]) plan.apparatus.push_back(base.apparatus[i].name);
    }
  }

  if (plan.design.adaptive) {
    check_design_bounds(plan.source, plan.design);
    return plan;  // its points come batch by batch: plan_adaptive_runs
  }
  if (plan.study_seed > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) -
                            static_cast<std::uint64_t>(plan.design.replicates - 1))
    throw ConfigError(plan.file + ": study.seed: " + std::to_string(plan.study_seed) +
                      " leaves no room for the seeds of " + std::to_string(plan.design.replicates) +
                      " replicates (study.seed + replicate)");
  check_design_bounds(plan.source, plan.design);
  try {
    plan.generated = surrogate::generate_design(plan.design.spec);
  } catch (const std::logic_error& e) {
    throw ConfigError(plan.file + ":" + std::to_string(plan.design.line) + ": design: " + e.what());
  }

  std::map<std::string, std::size_t> run_of_digest;
  for (std::size_t p = 0; p < plan.generated.points.size(); ++p) {
    std::optional<StudyConfig> built;
    try {
      ConfigDocument doc = plan.source.document();
      apply_design_values(doc, plan.design, plan.generated.points[p],
                          "design point " + std::to_string(p));
      built.emplace(build_study(std::move(doc)));
    } catch (const ConfigError& e) {
      throw ConfigError(plan.file + ":" + std::to_string(plan.design.line) + ": design: point " +
                        std::to_string(p) + " (" + describe_point(plan, p) +
                        ") is refused: " + without_file_prefix(e.what(), plan.file));
    }
    for (int r = 0; r < plan.design.replicates; ++r) {
      const std::uint64_t seed = replicate_seed(plan.study_seed, r);
      for (const std::string& a : plan.apparatus) {
        RunKey key = run_key_for(*built, a, seed, threads_per_run);
        auto [it, inserted] = run_of_digest.emplace(key.digest, plan.runs.size());
        if (inserted) plan.runs.push_back({std::move(key), p, r, seed, a, {}, {}});
        plan.rows.push_back({p, r, seed, a, it->second, {}, {}});
      }
    }
  }
  return plan;
}

// The top 53 bits: a study's seed must be an integer a double holds exactly (doe.csv's seed
// column and the run key's canonical JSON are read as numbers), i.e. below 2^53.
std::uint64_t dem_seed(std::uint64_t design_run_seed) { return design_run_seed >> 11; }

void plan_adaptive_runs(DoePlan& plan, const std::vector<calibrate::RunRequest>& requests) {
  plan.generated.points.clear();
  plan.rows.clear();
  plan.runs.clear();
  std::map<std::vector<double>, std::size_t> point_of_theta;
  std::map<std::string, std::size_t> run_of_digest;
  std::vector<std::optional<StudyConfig>> built;
  for (const calibrate::RunRequest& req : requests) {
    const auto [pt, fresh] = point_of_theta.emplace(req.theta, plan.generated.points.size());
    const std::size_t p = pt->second;
    if (fresh) {
      plan.generated.points.push_back(req.theta);
      try {
        ConfigDocument doc = plan.source.document();
        apply_design_values(doc, plan.design, req.theta, "design point " + std::to_string(p));
        built.emplace_back(build_study(std::move(doc)));
      } catch (const ConfigError& e) {
        throw ConfigError(plan.file + ":" + std::to_string(plan.design.line) + ": design: point " +
                          std::to_string(p) + " (" + describe_point(plan, p) +
                          ") is refused: " + without_file_prefix(e.what(), plan.file));
      }
    }
    const std::uint64_t seed = dem_seed(req.seed);
    for (const std::string& a : plan.apparatus) {
      RunKey key = run_key_for(*built[p], a, seed, plan.threads_per_run);
      auto [it, inserted] = run_of_digest.emplace(key.digest, plan.runs.size());
      if (inserted)
        plan.runs.push_back({std::move(key), p, req.replicate, seed, a, req.batch, req.slot});
      plan.rows.push_back({p, req.replicate, seed, a, it->second, req.batch, req.slot});
    }
  }
}

}  // namespace demcal::study
