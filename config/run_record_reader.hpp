#pragma once
// Reading a stored run record (runs/<hash>.json of a run store,
// study/run_store.hpp) back: a record is taken only when it is whole, is the
// run's it claims to be and holds observables in their physical range; a file
// that is not such a record is redone, never read into a table.

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace demcal::config {

// The record in `text` when it is a complete one whose design.digest is
// `digest`, whose design.status is "ok" or "failed", whose design.content_digest
// (when present) matches it, and whose observables are null or numbers in
// their physical range (an "ok" record has them); otherwise nullopt and
// `problem` (if given) says why. What RunStore::load checks a file with.
std::optional<nlohmann::json> parse_run_record(std::string_view text, const std::string& digest,
                                               std::string* problem = nullptr);

// SHA-256 of the record's canonical text without design.content_digest (and
// without what the clock and the study's path change: written_utc,
// config_file, results.wall_time_s and .particle_steps_per_s): what
// RunStore::store writes into design.content_digest, so that a record edited
// by hand (an AoR changed to 89, to "fourteen") is not taken for a run's.
std::string record_content_digest(const nlohmann::json& record);

}  // namespace demcal::config
