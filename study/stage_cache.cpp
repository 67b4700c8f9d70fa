#include "study/stage_cache.hpp"

#include "config/canonical_json.hpp"
#include "dem/output/atomic_file.hpp"

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <system_error>
#include <utility>
#include <vector>

namespace demcal::study {

using config::sha256_hex;

std::string directory_digest(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<fs::path> files;
  if (fs::is_directory(dir, ec))
    for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
      if (it->is_regular_file(ec)) files.push_back(it->path());
  std::sort(files.begin(), files.end());
  std::string all;
  for (const fs::path& f : files) {
    std::ifstream in(f, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    all += fs::relative(f, dir, ec).generic_string();
    all += '\n';
    all += sha256_hex(text.str());
    all += '\n';
  }
  return sha256_hex(all);
}

std::filesystem::path staging_directory(const std::filesystem::path& target) {
  // Built by appending: GCC 12 gives a false -Wrestrict on "." + std::string&&.
  std::string name(1, '.');
  name += target.filename().string();
  name += ".staging.";
  name += std::to_string(getpid());
  const std::filesystem::path staged = target.parent_path() / name;
  std::filesystem::remove_all(staged);
  std::filesystem::create_directories(staged);
  return staged;
}

void replace_directory(const std::filesystem::path& staged, const std::filesystem::path& target) {
  namespace fs = std::filesystem;
  std::string name(1, '.');
  name += target.filename().string();
  name += ".old.";
  name += std::to_string(getpid());
  const fs::path old = target.parent_path() / name;
  fs::remove_all(old);
  std::error_code ec;
  if (fs::exists(target, ec)) fs::rename(target, old);
  fs::rename(staged, target);
  fs::remove_all(old, ec);
}

StageCache::StageCache(std::filesystem::path file) : file_(std::move(file)) {
  std::ifstream in(file_);
  if (in) {
    try {
      entries_ = nlohmann::json::parse(in);
    } catch (const std::exception&) {
      entries_ = nlohmann::json::object();  // unreadable: every stage reruns
    }
  }
}

bool StageCache::current(const std::string& stage, const std::string& digest,
                         const std::filesystem::path& outputs) const {
  const std::string key = stage + ".outputs";
  return entries_.contains(stage) && entries_[stage] == digest && entries_.contains(key) &&
         std::filesystem::exists(outputs) && entries_[key] == directory_digest(outputs);
}

void StageCache::done(const std::string& stage, const std::string& digest,
                      const std::filesystem::path& outputs) {
  entries_[stage] = digest;
  entries_[stage + ".outputs"] = directory_digest(outputs);
  dem::write_file_atomically(file_, entries_.dump(1) + "\n");
}

void StageCache::forget(const std::string& stage) { entries_.erase(stage); }

}  // namespace demcal::study
