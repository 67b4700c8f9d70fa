#include "config/run_record_reader.hpp"

#include "config/canonical_json.hpp"
#include "config/observables.hpp"

#include <cmath>

namespace demcal::config {

std::optional<nlohmann::json> parse_run_record(std::string_view text, const std::string& digest,
                                               std::string* problem) {
  auto bad = [&](const std::string& why) -> std::optional<nlohmann::json> {
    if (problem != nullptr) *problem = why;
    return std::nullopt;
  };
  nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) return bad("not a JSON object");
  const auto design = j.find("design");
  if (design == j.end() || !design->is_object()) return bad("no \"design\" block");
  const auto stored_digest = design->find("digest");
  if (stored_digest == design->end() || *stored_digest != digest)
    return bad("its design.digest is not this run's key digest " + digest);
  const auto status = design->find("status");
  if (status == design->end() || !status->is_string() || (*status != "ok" && *status != "failed"))
    return bad("design.status is neither \"ok\" nor \"failed\"");
  // Records written since the content digest exists carry it: a hand edit shows.
  if (const auto content = design->find("content_digest"); content != design->end())
    if (!content->is_string() || *content != record_content_digest(j))
      return bad(
          "design.content_digest does not match the record: it was changed after it was written");
  // What a design table reads from a record must be what a run writes.
  const auto observables = j.find("observables");
  if (*status == "ok" && (observables == j.end() || !observables->is_object()))
    return bad("an \"ok\" record without an \"observables\" object");
  if (observables != j.end()) {
    if (!observables->is_object()) return bad("\"observables\" is not an object");
    for (const auto& name : observable_names()) {
      const auto v = observables->find(name);
      if (v == observables->end() || v->is_null()) continue;
      if (!v->is_number() || !observable_in_range(name, v->get<double>()))
        return bad("observables." + name + " is " + v->dump() + "; expected null or " +
                   observable_range_text(name));
    }
  }
  if (const auto series = j.find("series"); series != j.end()) {
    if (!series->is_object()) return bad("\"series\" is not an object");
    if (const auto m = series->find("discharged_mass"); m != series->end()) {
      auto numbers = [&](const char* key) {
        const auto a = m->is_object() ? m->find(key) : m->end();
        if (a == m->end() || !a->is_array()) return false;
        for (const auto& x : *a)
          if (!x.is_number() || !std::isfinite(x.get<double>())) return false;
        return true;
      };
      if (!numbers("time_s") || !numbers("mass_kg") ||
          m->at("time_s").size() != m->at("mass_kg").size())
        return bad(
            "series.discharged_mass is not two arrays of numbers of one length, time_s and "
            "mass_kg");
    }
  }
  return j;
}

std::string record_content_digest(const nlohmann::json& record) {
  nlohmann::json copy = record;
  if (copy.is_object()) {
    // What differs between two identical runs (the clock, the path the study
    // was given as) is left out, so that their records keep one digest.
    copy.erase("written_utc");
    copy.erase("config_file");
    if (copy.contains("design") && copy["design"].is_object())
      copy["design"].erase("content_digest");
    if (copy.contains("results") && copy["results"].is_object()) {
      copy["results"].erase("wall_time_s");
      copy["results"].erase("particle_steps_per_s");
    }
  }
  return sha256_hex(canonical_json(copy));
}

}  // namespace demcal::config
