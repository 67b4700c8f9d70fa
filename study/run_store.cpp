#include "study/run_store.hpp"

#include "config/canonical_json.hpp"
#include "config/run_record_reader.hpp"
#include "study/engine_evaluator.hpp"
#include "study/run_record.hpp"

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

using namespace demcal::config;
namespace {

// ------------------------------------------------------------- temporaries

std::string host_name() {
  char buf[256] = {};
  if (gethostname(buf, sizeof buf - 1) != 0 || buf[0] == '\0') return "localhost";
  std::string s(buf);
  // The name is part of a file name.
  for (char& c : s)
    if (c == '/' || c == '\\') c = '_';
  return s;
}

const std::string& this_host() {
  static const std::string name = host_name();
  return name;
}

constexpr std::string_view kTempSuffix = ".tmp";

std::string temporary_name(const std::filesystem::path& file) {
  static std::atomic<std::uint64_t> counter{0};
  // Built by appending: GCC 12 gives a false -Wrestrict on "." + std::string&&.
  std::string name(1, '.');
  name += file.filename().string();
  name += '.';
  name += this_host();
  name += '.';
  name += std::to_string(getpid());
  name += '.';
  name += std::to_string(counter.fetch_add(1));
  name += kTempSuffix;
  return name;
}

// The writer's pid when `name` is a temporary of this host, else -1.
long temporary_writer_on_this_host(const std::string& name) {
  if (name.size() < 2 || name[0] != '.' || name.size() <= kTempSuffix.size() ||
      name.compare(name.size() - kTempSuffix.size(), kTempSuffix.size(), kTempSuffix) != 0)
    return -1;
  std::string rest = name.substr(0, name.size() - kTempSuffix.size());
  // ".<name>.<host>.<pid>.<n>"
  const std::size_t n_dot = rest.rfind('.');
  if (n_dot == std::string::npos || n_dot == 0) return -1;
  const std::size_t pid_dot = rest.rfind('.', n_dot - 1);
  if (pid_dot == std::string::npos) return -1;
  const std::string pid_text = rest.substr(pid_dot + 1, n_dot - pid_dot - 1);
  if (pid_text.empty() || pid_text.find_first_not_of("0123456789") != std::string::npos ||
      pid_text.size() > 9)
    return -1;
  const std::string head = rest.substr(0, pid_dot);
  const std::string host_part = "." + this_host();
  if (head.size() <= host_part.size() ||
      head.compare(head.size() - host_part.size(), host_part.size(), host_part) != 0)
    return -1;
  return std::stol(pid_text);
}

bool process_alive(long pid) {
  if (pid <= 0) return false;
  return kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

}  // namespace

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

void write_file_durably(const std::filesystem::path& file, std::string_view content) {
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
  const std::filesystem::path tmp = dir / temporary_name(file);
  auto fail = [&](const std::string& what, int err) -> std::runtime_error {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    return std::runtime_error("cannot write " + file.string() + ": " + what + ": " +
                              std::strerror(err));
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) throw fail("cannot create " + tmp.string(), errno);
  std::size_t done = 0;
  while (done < content.size()) {
    const ssize_t w = ::write(fd, content.data() + done, content.size() - done);
    if (w < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      ::close(fd);
      throw fail("write", err);
    }
    done += static_cast<std::size_t>(w);
  }
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    throw fail("fsync", err);
  }
  if (::close(fd) != 0) throw fail("close", errno);
  if (::rename(tmp.c_str(), file.c_str()) != 0) throw fail("rename", errno);
}

std::size_t remove_stale_temporaries(const std::filesystem::path& dir) {
  std::size_t removed = 0;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const long pid = temporary_writer_on_this_host(name);
    if (pid < 0 || process_alive(pid)) continue;
    std::error_code rm;
    if (std::filesystem::remove(entry.path(), rm)) ++removed;
  }
  return removed;
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
  write_file_durably(file_for(hash), sealed.dump(2) + "\n");
}

}  // namespace demcal::study
