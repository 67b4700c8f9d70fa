#include "study/run_store.hpp"

#include "config/canonical_json.hpp"
#include "config/run_record_reader.hpp"
#include "study/engine_evaluator.hpp"
#include "study/run_record.hpp"
#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>
#include <vector>

namespace demcal::study {

using demcal::config::StudyConfig;
using demcal::config::canonical_json;
using demcal::config::parse_run_record;
using demcal::config::record_content_digest;
using demcal::config::resolved_for;
using demcal::config::sha256_hex;
RunKey make_run_key(nlohmann::json key) {
  RunKey k;
  k.key = std::move(key);
  k.digest = sha256_hex(canonical_json(k.key));
  k.hash = k.digest.substr(0, 16);
  return k;
}

RunKey run_key_for(const StudyConfig& study, const std::string& apparatus, std::uint64_t seed,
                   int threads) {
  toml::table inputs = resolved_for(study, apparatus);
  inputs.erase("study");
  inputs.erase("output");
  inputs.erase("design");
  inputs.erase("engine");  // another engine is keyed below, demcal's is not (keys unchanged)
  nlohmann::json key = {{"key_version", kRunKeyVersion},
                        {"apparatus", apparatus},
                        {"inputs", toml_to_json(inputs)},
                        {"seed", seed},
                        {"threads", threads}};
  if (std::optional<nlohmann::json> engine = engine_run_key(study, apparatus))
    key["engine"] = std::move(*engine);
  return make_run_key(std::move(key));
}

RunStore::RunStore(std::filesystem::path runs_dir) : dir_(std::move(runs_dir)) {}

std::filesystem::path RunStore::file_for(const std::string& hash) const {
  return dir_ / (hash + ".json");
}

std::optional<nlohmann::json> RunStore::load(const std::string& hash, const std::string& digest,
                                             std::string* problem) const {
  const std::filesystem::path path = file_for(hash);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  std::string why;
  auto record = parse_run_record(text.str(), digest, &why);
  if (!record && problem != nullptr) *problem = path.string() + ": " + why;
  return record;
}

void RunStore::store(const std::string& hash, const nlohmann::json& record) const {
  std::filesystem::create_directories(dir_);
  nlohmann::json sealed = record;
  if (sealed.contains("design") && sealed["design"].is_object())
    sealed["design"]["content_digest"] = record_content_digest(sealed);
  io::write_file_atomically(file_for(hash), sealed.dump(2) + "\n");
}

}  // namespace demcal::study
