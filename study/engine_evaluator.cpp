#include "study/engine_evaluator.hpp"

#include "config/toml_reader.hpp"
#include "dem/apparatus/conical_pile.hpp"
#include "dem/apparatus/rectangular_container.hpp"
#include "dem/apparatus/sandglass.hpp"
#include "engines/apparatus_layout.hpp"
#include "engines/engine_measure.hpp"
#include "engines/lammps_deck.hpp"
#include "engines/liggghts_deck.hpp"
#include "study/run_record.hpp"

#include <unistd.h>

#include <atomic>
#include <map>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace demcal::study {

using config::ConfigError;
using config::StudyApparatus;
using config::StudyConfig;

namespace {

const config::EngineConfig* other_engine(const StudyConfig& study) {
  return study.engine && !study.engine->is_demcal() ? &*study.engine : nullptr;
}

const StudyApparatus& find_apparatus(const StudyConfig& study, const std::string& name) {
  for (const StudyApparatus& a : study.apparatus)
    if (a.name == name) return a;
  throw std::logic_error("engine: the study has no apparatus \"" + name + "\"");
}

// The apparatus as deck primitives, from the options it was built from.
engines::LayoutResult layout_of(const StudyConfig& study, const StudyApparatus& a) {
  const dem::Apparatus* built = a.apparatus.get();
  if (const auto* s = dynamic_cast<const dem::Sandglass*>(built))
    return engines::layout_sandglass(s->options(), study.material, study.protocol);
  if (const auto* c = dynamic_cast<const dem::ConicalPile*>(built))
    return engines::layout_conical_pile(c->options(), study.material, study.protocol);
  if (const auto* r = dynamic_cast<const dem::RectangularContainer*>(built))
    return engines::layout_rectangular_container(r->options(), study.material, study.protocol);
  return {std::nullopt, "no deck is written for the apparatus kind \"" + a.kind + "\""};
}

}  // namespace

dem::ModelReduction apparatus_reduction(const StudyApparatus& a) {
  const dem::Apparatus* built = a.apparatus.get();
  if (const auto* s = dynamic_cast<const dem::Sandglass*>(built)) return s->options().reduction;
  if (const auto* c = dynamic_cast<const dem::ConicalPile*>(built)) return c->options().reduction;
  if (const auto* r = dynamic_cast<const dem::RectangularContainer*>(built))
    return r->options().reduction;
  return {};
}

engines::Deck engine_deck(const StudyConfig& study, const StudyApparatus& apparatus) {
  const config::EngineConfig* engine = other_engine(study);
  if (engine == nullptr) throw std::logic_error("engine_deck: the study runs on demcal");
  const engines::LayoutResult layout = layout_of(study, apparatus);
  const std::string refused = engine->where() + ".kind: \"" + engine->kind +
                              "\" cannot run apparatus \"" + apparatus.name + "\": ";
  if (!layout.ok()) throw ConfigError(refused + layout.refusal);
  engines::DeckOptions options;
  options.mapping.allow_rolling_substitute = engine->allow_rolling_substitute;
  options.mapping.allow_dry_walls = engine->allow_dry_walls;
  const engines::DeckResult deck = engine->kind == "lammps"
                                       ? engines::write_lammps_deck(*layout.layout, options)
                                       : engines::write_liggghts_deck(*layout.layout);
  if (!deck.ok()) throw ConfigError(refused + deck.refusal);
  return *deck.deck;
}

std::string engine_version_of(const std::string& kind, const std::string& launch) {
  static std::mutex mutex;
  static std::map<std::string, std::string> asked;
  std::lock_guard<std::mutex> lock(mutex);
  if (const auto it = asked.find(launch); it != asked.end()) return it->second;
  // An empty deck: the engine starts, writes its version as the log's first
  // line, and ends.
  static std::atomic<int> counter{0};
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("demcal-engine-version-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  engines::Deck empty;
  empty.engine = kind;
  empty.script_name = "in.version";
  empty.final_dump_name = "in.version";  // run_engine wants a file it wrote: the deck itself
  engines::EngineLaunch l;
  l.command = launch;
  l.log_name = "log.version";
  std::string version;
  try {
    version = engines::run_engine(empty, l, dir).engine_version;
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    throw std::runtime_error("cannot ask \"" + launch + "\" for its version: " + e.what());
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  if (version.empty())
    throw std::runtime_error(
        "\"" + launch + "\" ran an empty deck but its log names no LAMMPS or LIGGGHTS version");
  asked[launch] = version;
  return version;
}

std::optional<nlohmann::json> engine_run_key(const StudyConfig& study,
                                             const std::string& apparatus) {
  const config::EngineConfig* engine = other_engine(study);
  if (engine == nullptr) return std::nullopt;
  // Refused before anything runs: the deck must be writable for every run.
  (void)engine_deck(study, find_apparatus(study, apparatus));
  std::string version;
  try {
    version = engine_version_of(engine->kind, engine->launch);
  } catch (const std::exception& e) {
    throw ConfigError(engine->where() + ".launch: " + e.what());
  }
  const std::string expected = engine->kind == "lammps" ? "LAMMPS (" : "LIGGGHTS (";
  if (version.rfind(expected, 0) != 0)
    throw ConfigError(engine->where() + ".launch: \"" + engine->launch + "\" does not start " +
                      engine->kind + ": its log begins \"" + version + "\"");
  nlohmann::json key{{"kind", engine->kind}, {"version", version}};
  // Absent at revision 1, so keys of runs from unchanged decks stay as they were.
  if (const int revision = engines::deck_revision(engine->kind); revision > 1)
    key["deck_revision"] = revision;
  // A substitution changes the deck, so it is in the key; absent when off (keys unchanged).
  if (engine->allow_rolling_substitute) key["allow_rolling_substitute"] = true;
  if (engine->allow_dry_walls) key["allow_dry_walls"] = true;
  return key;
}

EngineEvaluator::EngineEvaluator(engines::Deck deck, std::string launch,
                                 std::filesystem::path directory, double time_step_s)
    : deck_(std::move(deck)),
      launch_(std::move(launch)),
      directory_(std::move(directory)),
      time_step_s_(time_step_s) {}

std::optional<EngineEvaluator> EngineEvaluator::for_run(const StudyConfig& study,
                                                        const StudyApparatus& apparatus,
                                                        std::filesystem::path directory,
                                                        std::function<void()> poll) {
  const config::EngineConfig* engine = other_engine(study);
  if (engine == nullptr) return std::nullopt;
  engines::Deck deck = engine_deck(study, apparatus);
  const double dt = deck.record.at("layout").value("time_step_s", 0.0);
  EngineEvaluator e(std::move(deck), engine->launch, std::move(directory), dt);
  e.version_ = engine_version_of(engine->kind, engine->launch);  // asked already by the run key
  e.poll_ = std::move(poll);
  e.timeout_s_ = engine->timeout_s;
  return e;
}

dem::ApparatusResult EngineEvaluator::run() {
  // A run cut short earlier left its files: none of them may be read as this run's.
  std::filesystem::remove_all(directory_);
  engines::EngineLaunch launch;
  launch.command = launch_;
  launch.poll = poll_;
  launch.timeout_s = timeout_s_;
  ran_ = engines::run_engine(deck_, launch, directory_);
  dem::ApparatusResult result = engines::measure_engine_run(deck_, directory_);
  result.details["engine_wall_time_s"] = ran_->wall_time_s;
  return result;
}

void EngineEvaluator::describe(nlohmann::json& record) const {
  record["engine"] = {
      {"name", deck_.engine},
      {"version", ran_ && !ran_->engine_version.empty() ? ran_->engine_version : version_},
      {"launch", launch_},
      {"directory", directory_.string()},
      {"deck", deck_.script_name},
      {"deck_written_by", "demcal " + engine_version()}};
  if (timeout_s_) record["engine"]["timeout_s"] = *timeout_s_;
  record["engine_deck"] = deck_.record;
  record["time_step_s"] = time_step_s_;
  record["contact_law"] = "the mapping in engine_deck.mapping (engines/parameter_mapping.hpp)";
}

}  // namespace demcal::study
