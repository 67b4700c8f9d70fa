#include "cli/run_store.hpp"

#include "cli/run_record.hpp"

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

namespace demcal::cli {

using namespace demcal::config;
namespace {

// ------------------------------------------------------------------ SHA-256
// FIPS 180-4, written out because the project takes no crypto dependency.

constexpr std::array<std::uint32_t, 64> kRoundConstants = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

constexpr std::uint32_t rotr(std::uint32_t x, int n) { return (x >> n) | (x << (32 - n)); }

void sha256_block(std::array<std::uint32_t, 8>& h, const unsigned char* p) {
  std::array<std::uint32_t, 64> w{};
  for (int i = 0; i < 16; ++i)
    w[i] = (std::uint32_t{p[4 * i]} << 24) | (std::uint32_t{p[4 * i + 1]} << 16) |
           (std::uint32_t{p[4 * i + 2]} << 8) | std::uint32_t{p[4 * i + 3]};
  for (int i = 16; i < 64; ++i) {
    const std::uint32_t s0 = rotr(w[i - 15], 7) ^ rotr(w[i - 15], 18) ^ (w[i - 15] >> 3);
    const std::uint32_t s1 = rotr(w[i - 2], 17) ^ rotr(w[i - 2], 19) ^ (w[i - 2] >> 10);
    w[i] = w[i - 16] + s0 + w[i - 7] + s1;
  }
  std::uint32_t a = h[0], b = h[1], c = h[2], d = h[3], e = h[4], f = h[5], g = h[6], k = h[7];
  for (int i = 0; i < 64; ++i) {
    const std::uint32_t t1 = k + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) +
                             kRoundConstants[i] + w[i];
    const std::uint32_t t2 = (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
    k = g;
    g = f;
    f = e;
    e = d + t1;
    d = c;
    c = b;
    b = a;
    a = t1 + t2;
  }
  h[0] += a;
  h[1] += b;
  h[2] += c;
  h[3] += d;
  h[4] += e;
  h[5] += f;
  h[6] += g;
  h[7] += k;
}

// ---------------------------------------------------------------- canonical

nlohmann::json canonical_numbers(const nlohmann::json& j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [k, v] : j.items()) out[k] = canonical_numbers(v);
    return out;
  }
  if (j.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& v : j) out.push_back(canonical_numbers(v));
    return out;
  }
  if (j.is_number_float()) {
    const double v = j.get<double>();
    constexpr double kExact = 9007199254740992.0;  // 2^53
    if (std::isfinite(v) && std::trunc(v) == v && std::fabs(v) < kExact)
      return static_cast<std::int64_t>(v);
  }
  return j;
}

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

std::string sha256_hex(std::string_view data) {
  std::array<std::uint32_t, 8> h = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                                    0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
  const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
  std::size_t n = data.size();
  std::size_t off = 0;
  for (; n - off >= 64; off += 64) sha256_block(h, bytes + off);
  // The tail, the 0x80 marker, zeros and the bit length (big-endian) in one or two blocks.
  std::array<unsigned char, 128> tail{};
  const std::size_t rest = n - off;
  std::memcpy(tail.data(), bytes + off, rest);
  tail[rest] = 0x80;
  const std::size_t blocks = rest + 1 + 8 <= 64 ? 1 : 2;
  const std::uint64_t bits = static_cast<std::uint64_t>(n) * 8;
  for (int i = 0; i < 8; ++i)
    tail[blocks * 64 - 1 - static_cast<std::size_t>(i)] =
        static_cast<unsigned char>(bits >> (8 * i));
  for (std::size_t b = 0; b < blocks; ++b) sha256_block(h, tail.data() + 64 * b);
  static const char* kHex = "0123456789abcdef";
  std::string out;
  out.reserve(64);
  for (std::uint32_t word : h)
    for (int shift = 28; shift >= 0; shift -= 4) out += kHex[(word >> shift) & 0xf];
  return out;
}

std::string canonical_json(const nlohmann::json& j) {
  // nlohmann::json keeps object keys sorted; dump() adds no whitespace and
  // writes doubles in their shortest round-trip form.
  return canonical_numbers(j).dump();
}

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
  return make_run_key({{"key_version", kRunKeyVersion},
                       {"apparatus", apparatus},
                       {"inputs", toml_to_json(inputs)},
                       {"seed", seed},
                       {"threads", threads}});
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
      return bad("design.content_digest does not match the record: it was changed after it was written");
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
      if (!numbers("time_s") || !numbers("mass_kg") || m->at("time_s").size() != m->at("mass_kg").size())
        return bad("series.discharged_mass is not two arrays of numbers of one length, time_s and mass_kg");
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
    if (copy.contains("design") && copy["design"].is_object()) copy["design"].erase("content_digest");
    if (copy.contains("results") && copy["results"].is_object()) {
      copy["results"].erase("wall_time_s");
      copy["results"].erase("particle_steps_per_s");
    }
  }
  return sha256_hex(canonical_json(copy));
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

}  // namespace demcal::cli
