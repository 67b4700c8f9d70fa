#pragma once
// A design point run by another DEM engine ([engine] kind = "liggghts" |
// "lammps", config/engine_config.hpp): demcal writes the engine's input deck
// from the study's apparatus (engines/apparatus_layout.hpp, the parameter
// mapping of engines/parameter_mapping.hpp), runs it with the [engine] launch
// line in a directory of its own, reads the final dump and the m(t) series back
// and measures them with demcal's own measurement code, so the run lands in the
// same run store, under the same observable names, as a demcal run.
//
// The run key (study/run_store.hpp) gains "engine": {"kind", "version"} for
// another engine; the version is asked of the binary once per launch line and
// process (it runs an empty deck and reads the first line of its log). For
// demcal's own engine the key is what it always was. The launch line is not in
// the key (it is recorded in the run file).
//
// The run record's "engine" says which engine ran (name, version, launch line,
// the deck's directory, demcal's version that wrote the deck), and
// "engine_deck" holds the parameter mapping, the layout and the measurement
// plan the deck was written from.

#include "config/study_config.hpp"
#include "dem/apparatus/apparatus.hpp"
#include "engines/deck.hpp"
#include "engines/engine_run.hpp"
#include "study/run_evaluator.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace demcal::study {

// The run key's "engine" member for a run of `apparatus`: nullopt when demcal's
// engine runs the study. Throws ConfigError at the [engine] table when the
// engine cannot run this apparatus (the refusal, by name) or its launch line
// does not start that engine.
std::optional<nlohmann::json> engine_run_key(const config::StudyConfig& study,
                                             const std::string& apparatus);

// The deck of one run of `apparatus` on the study's engine (kind liggghts or
// lammps); throws ConfigError naming [engine] and the refusal when there is none.
engines::Deck engine_deck(const config::StudyConfig& study,
                          const config::StudyApparatus& apparatus);

// The version line the engine started by `launch` writes first in its log
// ("LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0, ...)"), asked once per launch line
// in this process. Throws std::runtime_error when it does not run or names no engine.
// `kind` is "liggghts" or "lammps" (how the engine is started differs slightly).
std::string engine_version_of(const std::string& kind, const std::string& launch);

// The model reduction (coarse graining, reduced modulus) `apparatus` was built with.
dem::ModelReduction apparatus_reduction(const config::StudyApparatus& apparatus);

// One run on another engine: the PreparedRun the DEM evaluator
// (study/run_evaluator.hpp) makes when the study has an [engine] table.
class EngineEvaluator final : public PreparedRun {
 public:
  // nullopt when demcal's own engine runs the study; `directory` is where the
  // deck is written and run (emptied first). `poll` is called while the engine
  // runs and may throw to cancel it (engines::EngineLaunch::poll); it must outlive
  // the evaluator.
  static std::optional<EngineEvaluator> for_run(const config::StudyConfig& study,
                                                const config::StudyApparatus& apparatus,
                                                std::filesystem::path directory,
                                                std::function<void()> poll = {});

  // Writes the deck, runs the engine, reads and measures its output. Throws
  // std::runtime_error (the engine's ERROR line, a malformed dump) when it fails.
  dem::ApparatusResult run() override;

  // Says in `record` which engine ran and how ("engine", "engine_deck",
  // "time_step_s", "contact_law").
  void describe(nlohmann::json& record) const override;

 private:
  EngineEvaluator(engines::Deck deck, std::string launch, std::filesystem::path directory,
                  double time_step_s);

  engines::Deck deck_;
  std::string launch_;
  std::filesystem::path directory_;
  double time_step_s_ = 0.0;
  std::string version_;
  std::function<void()> poll_;
  std::optional<double> timeout_s_;  // [engine] timeout_s
  std::optional<engines::EngineRunResult> ran_;
};

}  // namespace demcal::study
