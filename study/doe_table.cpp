#include "study/doe_table.hpp"

#include "io/atomic_file.hpp"

#include "study/run_record.hpp"

#include <algorithm>

namespace demcal::study {

using demcal::config::observable_names;
using demcal::config::series_observable_names;
using demcal::config::series_observables;
using demcal::config::shortest_decimal;
namespace {

std::string observable_text(const nlohmann::json& v) {
  if (v.is_number()) return shortest_decimal(v.get<double>());
  if (v.is_null()) return "";
  return v.is_string() ? v.get<std::string>() : v.dump();
}

}  // namespace

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

DoeTable make_doe_table(const DoePlan& plan,
                        const std::vector<std::optional<nlohmann::json>>& records) {
  DoeTable table;
  const auto& params = plan.design.spec.parameters;
  const std::vector<std::string>& observables = observable_names();

  std::string& csv = table.csv;
  csv = "point,replicate,seed,apparatus";
  for (const auto& p : params) {
    csv += ',';
    csv += csv_field(p.name);
  }
  for (const auto& o : observables) {
    csv += ',';
    csv += o;
  }
  csv += ",status,hash\n";

  nlohmann::json rows = nlohmann::json::array();
  for (const PlanRow& row : plan.rows) {
    const PlannedRun& run = plan.runs[row.run];
    const std::optional<nlohmann::json>& record = records[row.run];
    std::string status = "missing";
    if (record) status = record->at("design").at("status").get<std::string>();
    (status == "ok" ? table.ok : status == "failed" ? table.failed : table.missing) += 1;

    csv += std::to_string(row.point) + "," + std::to_string(row.replicate) + "," +
           std::to_string(row.seed) + "," + csv_field(row.apparatus);
    nlohmann::json values = nlohmann::json::object();
    for (std::size_t i = 0; i < params.size(); ++i) {
      const double v = plan.generated.points[row.point][i];
      csv += ',';
      csv += shortest_decimal(v);
      values[params[i].name] = v;
    }
    nlohmann::json observed = nlohmann::json::object();
    const nlohmann::json* stored =
        record && record->contains("observables") ? &record->at("observables") : nullptr;
    // A run stored before the series observables existed: read them off its series, once;
    // a newer record has them already.
    nlohmann::json derived = nlohmann::json::object();
    const auto& series_names = series_observable_names();
    if (stored && record->contains("series") &&
        std::any_of(series_names.begin(), series_names.end(),
                    [&](const std::string& n) { return !stored->contains(n); }))
      derived = series_observables(record->at("series"), *stored);
    for (const auto& o : observables) {
      nlohmann::json v = nullptr;
      if (stored && stored->contains(o))
        v = stored->at(o);
      else
        v = derived.value(o, nlohmann::json());
      csv += ',';
      csv += csv_field(observable_text(v));
      observed[o] = v;
    }
    csv += ',';
    csv += status;
    csv += ',';
    csv += run.key.hash;
    csv += '\n';

    nlohmann::json j = {{"point", row.point},
                        {"replicate", row.replicate},
                        {"seed", row.seed},
                        {"apparatus", row.apparatus},
                        {"parameters", values},
                        {"observables", observed},
                        {"status", status},
                        {"hash", run.key.hash},
                        {"file", "runs/" + run.key.hash + ".json"}};
    if (row.batch) j["batch"] = *row.batch;
    if (row.slot) j["slot"] = *row.slot;
    if (status == "failed" && record->contains("results") &&
        record->at("results").contains("error"))
      j["error"] = record->at("results").at("error");
    rows.push_back(std::move(j));
  }

  const surrogate::DesignSpec& spec = plan.design.spec;
  nlohmann::json parameters = nlohmann::json::array();
  for (std::size_t i = 0; i < params.size(); ++i) {
    nlohmann::json p = {{"name", params[i].name},
                        {"key", plan.design.parameter_paths[i]},
                        {"lower", params[i].lower},
                        {"upper", params[i].upper}};
    if (spec.kind == surrogate::DesignKind::kFullFactorial) p["levels"] = params[i].levels;
    parameters.push_back(std::move(p));
  }
  nlohmann::json design = {{"kind", plan.design.adaptive ? std::string("adaptive")
                                                          : surrogate::design_kind_name(spec.kind)},
                           {"parameters", parameters},
                           {"points", plan.generated.points.size()},
                           {"replicates", plan.design.replicates},
                           {"matrix", plan.generated.points}};
  if (spec.kind == surrogate::DesignKind::kLatinHypercube) design["seed"] = spec.seed;
  if (spec.kind == surrogate::DesignKind::kSobol) design["skip"] = spec.skip;

  const char* seed_rule = plan.design.adaptive
                              ? "seed = (the design's SplitMix64 seed of (batch, slot)) >> 11"
                              : "seed = study.seed + replicate";
  table.json = {{"study", plan.study_name},
                {"study_file", plan.file},
                {"design", design},
                {"seed_rule", seed_rule},
                {"study_seed", plan.study_seed},
                {"threads_per_run", plan.threads_per_run},
                {"apparatus", plan.apparatus},
                {"columns", nlohmann::json::array()},
                {"rows", rows},
                {"summary",
                 {{"rows", plan.rows.size()},
                  {"runs", plan.runs.size()},
                  {"ok", table.ok},
                  {"failed", table.failed},
                  {"missing", table.missing}}}};
  for (const auto& p : params) table.json["columns"].push_back(p.name);
  for (const auto& o : observables) table.json["columns"].push_back(o);
  return table;
}

DoeTable write_doe_table(const DoePlan& plan, const RunStore& store,
                         const std::filesystem::path& study_dir, bool complete_only) {
  std::vector<std::optional<nlohmann::json>> records;
  records.reserve(plan.runs.size());
  for (const PlannedRun& run : plan.runs)
    records.push_back(store.load(run.key.hash, run.key.digest));
  DoeTable table = make_doe_table(plan, records);
  if (complete_only && table.missing > 0) return table;
  std::filesystem::create_directories(study_dir);
  io::write_file_atomically(study_dir / "doe.csv", table.csv);
  io::write_file_atomically(study_dir / "doe.json", table.json.dump(2) + "\n");
  return table;
}

}  // namespace demcal::study
