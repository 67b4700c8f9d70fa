#pragma once
// The run store of a campaign: a plain directory of run files, one per run,
// each named by the hash of everything that determines the run
// (<output>/<study name>/runs/<hash>.json). A run already in the store is
// never computed again; stores are merged by copying their files together.
//
// The hash rule. The run key is the JSON object
//   { "key_version": 2,
//     "apparatus": "<name>",
//     "inputs": the study resolved for that apparatus after every override and
//               design value (resolved_for: [material], [wall_material],
//               [contact], [interaction], [protocol] and the one
//               [apparatus.<name>] table, each default written in), without
//               [study] (name, seed, threads), [output] and [design],
//     "seed": the run's seed, "threads": the run's thread count,
//     "engine": {"kind", "version"[, "deck_revision"]} only when [engine]
//               names another engine than demcal's (study/engine_evaluator.hpp;
//               deck_revision when above 1, engines/deck.hpp); [engine] itself
//               is not in "inputs" }
// written canonically: object keys sorted, no whitespace, a floating-point
// number with an integral value below 2^53 written as that integer (so 1 and
// 1.0 in a TOML file hash alike), other numbers in the shortest text that
// reads back exactly. digest = SHA-256 of that text (64 hex digits, stored in
// the run file); hash = its first 16 hex digits (the file name).
//
// So a parameter value enters through the input it sets: the same run reached
// from two designs, or a run of an apparatus that a design parameter does not
// touch, is one file. The engine version is deliberately not in the key (it is
// recorded in each run file, "engine.version"): a store survives rebuilds, and
// a change to the engine that changes results must be met with a new store
// (another --output) or a new key_version.
//
// Writes are atomic and durable: the file is written under a hidden temporary
// name in the same directory (".<name>.<host>.<pid>.<n>.tmp"), flushed to disk
// and renamed into place, so a reader sees a whole file or none. Temporaries
// are never read; those left by processes of this host that no longer run are
// removed by remove_stale_temporaries (those of other hosts, on a shared file
// system, are left alone: their writers may be alive).

#include "config/canonical_json.hpp"
#include "config/run_record_reader.hpp"
#include "config/study_config.hpp"
#include "io/atomic_file.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace demcal::study {

// History: 1 the first; 2 (issue 13) spatial particle order became the default of the
// config readers (absent [protocol] particle_order now means "spatial"), which changes the
// results of every run that does not name an order, so stores of version 1 are not reused.
inline constexpr int kRunKeyVersion = 2;

struct RunKey {
  nlohmann::json key;  // the run key object
  std::string digest;  // SHA-256 of its canonical text, 64 hex digits
  std::string hash;    // the first 16 digits: the run file's name
};

RunKey make_run_key(nlohmann::json key);

// The run key of one run of `apparatus` in `study` (already built with the
// design values applied), with `seed` and `threads` the run's own.
RunKey run_key_for(const config::StudyConfig& study, const std::string& apparatus,
                   std::uint64_t seed, int threads);

// The store writes through demcal's one atomic writer (io/atomic_file.hpp),
// whose clean-up of stale temporaries the design runner calls by this name.
using io::remove_stale_temporaries;

class RunStore {
 public:
  explicit RunStore(std::filesystem::path runs_dir);

  const std::filesystem::path& directory() const { return dir_; }
  std::filesystem::path file_for(const std::string& hash) const;

  // The record stored for `hash`, when a complete one whose design.digest is
  // `digest` and whose design.status is "ok" or "failed" is there. Otherwise
  // nullopt; when a file is there but not such a record, `problem` (if given)
  // says why (it will be redone and replaced).
  std::optional<nlohmann::json> load(const std::string& hash, const std::string& digest,
                                     std::string* problem = nullptr) const;

  // Writes the record of `hash` (creating the directory).
  void store(const std::string& hash, const nlohmann::json& record) const;

 private:
  std::filesystem::path dir_;
};

}  // namespace demcal::study
