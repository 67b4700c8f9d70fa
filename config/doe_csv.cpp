#include "config/doe_csv.hpp"

#include "config/observables.hpp"
#include "config/toml_reader.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <tuple>

namespace demcal::config {
namespace {

[[noreturn]] void fail(const std::string& file, std::size_t line, const std::string& what) {
  throw ConfigError(file + ":" + std::to_string(line) + ": " + what);
}

double parse_number(const std::string& text, const std::string& file, std::size_t line,
                    const std::string& column) {
  if (text.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto v = parse_csv_number(text);
  if (!v)
    fail(file, line,
         "column " + column + ": expected a finite number or an empty cell, got \"" +
             printable(text) + "\"");
  return *v;
}

// The largest point or replicate index and seed a table may hold (the
// point and replicate are ints; a seed beyond 2^53 would not survive a double).
constexpr double kMaxIndex = 1e9;
constexpr double kMaxSeed = 9007199254740992.0;

double whole_number(const std::string& text, const std::string& file, std::size_t line,
                    const std::string& column, double max) {
  const double v = parse_number(text, file, line, column);
  if (std::isnan(v) || v < 0 || v > max || v != std::floor(v))
    fail(file, line,
         "column " + column + ": expected a whole number in [0, " +
             std::to_string(static_cast<long long>(max)) + "], got \"" + printable(text) + "\"");
  return v;
}

}  // namespace

// Control characters shown as \xNN, so that a message stays one readable line.
std::string printable(const std::string& s) {
  std::string out;
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      static const char* kHex = "0123456789abcdef";
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 0xf];
    } else {
      out += c;
    }
  }
  return out;
}

std::optional<double> parse_csv_number(const std::string& text) {
  // Decimal only: std::stod would also read hexadecimal ("0x10" = 16), "inf" and "nan".
  if (text.empty() || text.find_first_not_of("0123456789+-.eE") != std::string::npos)
    return std::nullopt;
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::ifstream open_input_file(const std::filesystem::path& path, const std::string& what,
                              const std::string& if_missing) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw ConfigError(path.string() + ": is a directory; expected " + what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path.string() + ": " + if_missing);
  return in;
}

std::string without_bom(const std::string& line) {
  return line.rfind("\xEF\xBB\xBF", 0) == 0 ? line.substr(3) : line;
}

int DoeCsv::observable_index(const std::string& name) const {
  const auto it = std::find(observable_names.begin(), observable_names.end(), name);
  return it == observable_names.end() ? -1 : static_cast<int>(it - observable_names.begin());
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        out.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        out.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.emplace_back();
    } else if (c != '\r') {
      out.back() += c;
    }
  }
  return out;
}

DoeCsv read_doe_csv(const std::filesystem::path& path) {
  std::ifstream in =
      open_input_file(path, "the design table, a CSV file (e.g. <output>/<study>/doe.csv)",
                      "cannot open the design table (run `demcal doe` first, or give --doe FILE)");
  return read_doe_csv(in, path.string());
}

DoeCsv read_doe_csv(std::istream& in, const std::string& file) {
  DoeCsv t;
  t.file = file;
  std::string line;
  if (!std::getline(in, line)) fail(t.file, 1, "empty file; expected a header line");
  const auto header = split_csv_line(without_bom(line));
  const auto col = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) fail(t.file, 1, "the header has no column \"" + name + "\"");
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t c_point = col("point"), c_rep = col("replicate"), c_seed = col("seed"),
                    c_app = col("apparatus"), c_status = col("status"), c_hash = col("hash");
  std::vector<std::size_t> c_obs;
  for (const auto& name : stable_observable_names()) {
    c_obs.push_back(col(name));
    t.observable_names.push_back(name);
  }
  // The series observables are newer than some checked-in tables: read when present.
  for (const auto& name : series_observable_names()) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) continue;
    c_obs.push_back(static_cast<std::size_t>(it - header.begin()));
    t.observable_names.push_back(name);
  }
  const std::size_t first_obs = *std::min_element(c_obs.begin(), c_obs.end());
  if (first_obs <= c_app + 1)
    fail(t.file, 1, "no parameter columns between \"apparatus\" and the observables");
  std::vector<std::size_t> c_par;
  for (std::size_t c = c_app + 1; c < first_obs; ++c) {
    c_par.push_back(c);
    t.parameter_names.push_back(header[c]);
  }
  // Every column is read once: a second column of a name, or one demcal does not read (a
  // misspelt optional observable such as "discharge_t50_sec"), would be dropped silently.
  {
    std::vector<bool> read(header.size(), false);
    for (const std::size_t c : {c_point, c_rep, c_seed, c_app, c_status, c_hash}) read[c] = true;
    for (const std::size_t c : c_obs) read[c] = true;
    for (const std::size_t c : c_par) read[c] = true;
    for (std::size_t c = 0; c < header.size(); ++c) {
      for (std::size_t e = 0; e < c; ++e)
        if (header[e] == header[c])
          fail(t.file, 1,
               "column \"" + printable(header[c]) + "\" appears twice (columns " +
                   std::to_string(e + 1) + " and " + std::to_string(c + 1) + "); each column once");
      if (!read[c]) {
        std::string optional;
        for (const auto& name : series_observable_names())
          optional += (optional.empty() ? "" : ", ") + name;
        fail(t.file, 1,
             "column " + std::to_string(c + 1) + " \"" + printable(header[c]) +
                 "\" is not one demcal reads; after the parameters come the observables (the "
                 "optional ones: " +
                 optional + "), then status and hash");
      }
    }
  }
  std::map<std::tuple<std::string, int, int>, std::size_t> seen;  // -> its line
  std::size_t n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty() || line == "\r") continue;
    const auto f = split_csv_line(line);
    if (f.size() != header.size())
      fail(t.file, n,
           "expected " + std::to_string(header.size()) + " fields like the header, got " +
               std::to_string(f.size()));
    DoeCsvRow r;
    r.line = n;
    r.point = static_cast<int>(whole_number(f[c_point], t.file, n, "point", kMaxIndex));
    r.replicate = static_cast<int>(whole_number(f[c_rep], t.file, n, "replicate", kMaxIndex));
    r.seed = static_cast<std::uint64_t>(whole_number(f[c_seed], t.file, n, "seed", kMaxSeed));
    r.apparatus = f[c_app];
    if (const std::string why = reader::file_name_problem(r.apparatus); !why.empty())
      fail(t.file, n,
           "column apparatus: \"" + printable(r.apparatus) +
               "\" cannot be a setup name (it names files): " + why);
    for (std::size_t k = 0; k < c_par.size(); ++k) {
      const double v = parse_number(f[c_par[k]], t.file, n, t.parameter_names[k]);
      if (std::isnan(v))
        fail(t.file, n, "column " + t.parameter_names[k] + ": a parameter value is required");
      r.parameters.push_back(v);
    }
    for (std::size_t k = 0; k < c_obs.size(); ++k) {
      const double v = parse_number(f[c_obs[k]], t.file, n, t.observable_names[k]);
      if (!std::isnan(v) && !observable_in_range(t.observable_names[k], v))
        fail(t.file, n,
             "column " + t.observable_names[k] + ": expected " +
                 observable_range_text(t.observable_names[k]) + " or an empty cell, got " +
                 f[c_obs[k]]);
      r.observables.push_back(v);
    }
    r.status = f[c_status];
    if (r.status != "ok" && r.status != "failed" && r.status != "missing")
      fail(t.file, n,
           "column status: expected \"ok\", \"failed\" or \"missing\", got \"" +
               printable(r.status) + "\"");
    r.hash = f[c_hash];
    // A row twice would count as an extra replicate of its point.
    const auto [it, fresh] = seen.try_emplace(std::tuple(r.apparatus, r.point, r.replicate), n);
    if (!fresh)
      fail(t.file, n,
           "point " + std::to_string(r.point) + " replicate " + std::to_string(r.replicate) +
               " of " + r.apparatus + " is already on line " + std::to_string(it->second) +
               "; each run appears once");
    t.rows.push_back(std::move(r));
  }
  return t;
}

}  // namespace demcal::config
