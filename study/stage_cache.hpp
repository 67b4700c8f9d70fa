#pragma once
// The stage cache of `demcal study`: each stage (fit, inspect, calibrate)
// records the digest of its inputs and of the outputs it wrote in
// <study dir>/stages.json, and is skipped while both are unchanged. Its
// outputs are written into a staging directory and put in place whole, so a
// stage that fails halfway leaves the previous outputs intact.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace demcal::study {

// SHA-256 over the regular files below `dir` (their relative paths and
// contents, in path order); that of an empty text when `dir` does not exist.
// What a stage's cache entry records of the files it reads and writes.
std::string directory_digest(const std::filesystem::path& dir);

// A stage's outputs are written whole into a staging directory and then put
// in place of `target` with two renames, so that a stage that fails halfway
// leaves the previous outputs intact: staging_directory(target) is the
// (emptied) directory to write into, replace_directory moves it to `target`.
std::filesystem::path staging_directory(const std::filesystem::path& target);
void replace_directory(const std::filesystem::path& staged, const std::filesystem::path& target);

class StageCache {
 public:
  // Reads `file` (stages.json); a missing or unreadable file is an empty cache.
  explicit StageCache(std::filesystem::path file);

  // Up to date: the inputs' digest is the one recorded, and the outputs on
  // disk are the ones the stage wrote (not edited, not left half by a failure).
  bool current(const std::string& stage, const std::string& digest,
               const std::filesystem::path& outputs) const;
  // Records that `stage` ran on inputs of `digest` and wrote `outputs`; saves the file.
  void done(const std::string& stage, const std::string& digest,
            const std::filesystem::path& outputs);
  // Forgets `stage` (a later stage whose inputs an earlier one has just rewritten);
  // saved with the next done().
  void forget(const std::string& stage);

 private:
  std::filesystem::path file_;
  nlohmann::json entries_ = nlohmann::json::object();
};

}  // namespace demcal::study
