#include "config/recordings_csv.hpp"

#include "config/doe_csv.hpp"
#include "config/observables.hpp"
#include "config/toml_reader.hpp"
#include "io/observable_registry.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>

namespace demcal::config {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, std::size_t line,
                       const std::string& what) {
  throw ConfigError(file.string() + ":" + std::to_string(line) + ": " + what);
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

double number(const std::filesystem::path& file, std::size_t line, const std::string& column,
              const std::string& text) {
  if (text.empty()) fail(file, line, column + ": missing; expected a number");
  const auto v = parse_csv_number(text);
  if (!v) fail(file, line, column + ": expected a finite number, got \"" + printable(text) + "\"");
  return *v;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

}  // namespace

const std::string& unit_of_observable(const std::string& observable) {
  // A view of the registry (io/observable_registry.hpp), kept as strings so the
  // reference stays valid.
  static const std::map<std::string, std::string> units = [] {
    std::map<std::string, std::string> u;
    for (const io::ObservableInfo& o : io::observable_registry())
      if (o.kind == io::ObservableKind::stable || o.kind == io::ObservableKind::series)
        u.emplace(std::string(o.name), std::string(o.unit));
    return u;
  }();
  return units.at(observable);
}

void require_measured_by_setup(const calibrate::Recording& recording,
                               const std::filesystem::path& file, std::size_t line,
                               const std::vector<RecordedSetup>& setups,
                               const std::string& given_by) {
  const auto s = std::find_if(setups.begin(), setups.end(),
                              [&](const RecordedSetup& x) { return x.name == recording.setup; });
  if (s == setups.end() || io::measures(s->kind, recording.observable)) return;
  const auto measured = io::recordable_observables(s->kind);
  fail(file, line,
       "observable \"" + recording.observable + "\"" +
           (given_by.empty() ? "" : " (given by " + given_by + ")") +
           " is not measured by setup \"" + recording.setup + "\", a " + s->kind + "; a " +
           s->kind + " measures " +
           (measured.empty() ? std::string("nothing demcal calibrates") : joined(measured)));
}

void require_measured_by_setups(const std::vector<calibrate::Recording>& recordings,
                                const std::filesystem::path& file,
                                const std::vector<RecordedSetup>& setups) {
  for (const auto& r : recordings) require_measured_by_setup(r, file, r.line, setups);
}

std::vector<calibrate::Recording> read_recordings_csv(const std::filesystem::path& path,
                                                      const std::vector<std::string>& setups) {
  std::ifstream in =
      open_input_file(path, "the recordings, a CSV file", "cannot open the recordings file");
  return read_recordings_csv(in, path, setups);
}

std::vector<calibrate::Recording> read_recordings_csv(std::istream& in,
                                                      const std::filesystem::path& path,
                                                      const std::vector<std::string>& setups) {
  std::string line;
  if (!std::getline(in, line))
    fail(path, 1, "empty file; expected the header setup,observable,value,sigma,unit");
  std::vector<std::string> header;
  for (const auto& h : split_csv_line(without_bom(line))) header.push_back(trim(h));
  std::vector<std::string> expected = {"setup", "observable", "value", "sigma", "unit"};
  const bool with_repeats = header.size() == 6 && header.back() == "repeats";
  if (with_repeats) expected.push_back("repeats");
  if (header != expected)
    fail(path, 1,
         "expected the header setup,observable,value,sigma,unit (and optionally ,repeats), got \"" +
             printable(line) + "\"");
  std::vector<calibrate::Recording> out;
  std::set<std::pair<std::string, std::string>> seen;
  std::size_t n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    auto f = split_csv_line(line);
    for (auto& x : f) x = trim(x);
    if (f.size() != expected.size())
      fail(path, n,
           "expected " + std::to_string(expected.size()) + " fields (" + joined(expected) +
               "), got " + std::to_string(f.size()));
    calibrate::Recording r;
    r.file = path.string();
    r.line = n;
    r.setup = f[0];
    r.observable = f[1];
    if (std::find(setups.begin(), setups.end(), r.setup) == setups.end())
      fail(path, n,
           "setup \"" + printable(r.setup) +
               "\" is not an apparatus of the study; expected one of " + joined(setups));
    const auto& names = observable_names();
    if (std::find(names.begin(), names.end(), r.observable) == names.end())
      fail(path, n,
           "observable \"" + printable(r.observable) +
               "\" is not one demcal measures; expected one of " + joined(names));
    r.value = number(path, n, "value", f[2]);
    if (!observable_in_range(r.observable, r.value))
      fail(path, n,
           "value: expected " + observable_range_text(r.observable) + " for " + r.observable +
               ", got " + printable(f[2]));
    if (f[3].empty())
      fail(path, n, "sigma: missing; every recording needs its standard uncertainty (> 0)");
    r.sigma = number(path, n, "sigma", f[3]);
    if (!(r.sigma > 0.0)) fail(path, n, "sigma: expected a number > 0, got " + printable(f[3]));
    if (!observable_in_range(r.observable, r.sigma))
      fail(path, n,
           "sigma: expected a number > 0 within " + observable_range_text(r.observable) +
               " (an uncertainty wider than the observable's physical range says nothing), got " +
               f[3]);
    r.unit = f[4];
    if (r.unit != unit_of_observable(r.observable))
      fail(path, n,
           "unit \"" + printable(r.unit) + "\" does not fit " + r.observable + "; expected \"" +
               unit_of_observable(r.observable) + "\" (SI, as the name says)");
    if (with_repeats) {
      const double k = number(path, n, "repeats", f[5]);
      if (!(k >= 1.0) || k != std::floor(k) || k > 1e6)
        fail(path, n,
             "repeats: expected a whole number >= 1 (how many tests the value is the mean of), "
             "got " +
                 printable(f[5]));
      r.repeats = static_cast<int>(k);
    }
    if (!seen.insert({r.setup, r.observable}).second)
      fail(path, n,
           r.setup + " " + r.observable +
               " is recorded twice; give one value (the mean) with its sigma");
    out.push_back(r);
  }
  if (out.empty()) fail(path, n, "no recordings");
  return out;
}

calibrate::RecordedSeries read_series_csv(const std::filesystem::path& path,
                                          const std::string& setup) {
  std::ifstream in = open_input_file(path, "a series, a CSV file", "cannot open the series file");
  return read_series_csv(in, path, setup);
}

calibrate::RecordedSeries read_series_csv(std::istream& in, const std::filesystem::path& path,
                                          const std::string& setup) {
  std::string line;
  if (!std::getline(in, line)) fail(path, 1, "empty file; expected the header time_s,<quantity>");
  auto header = split_csv_line(without_bom(line));
  for (auto& h : header) h = trim(h);
  if (header.size() != 2 || header[0] != "time_s" || header[1].empty())
    fail(path, 1, "expected the header time_s,<quantity> (e.g. time_s,discharged_mass_kg)");
  calibrate::RecordedSeries s;
  s.setup = setup;
  s.quantity = header[1];
  s.file = path.string();
  std::size_t n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (trim(line).empty()) continue;
    auto f = split_csv_line(line);
    if (f.size() != 2) fail(path, n, "expected 2 fields, got " + std::to_string(f.size()));
    const double t = number(path, n, "time_s", trim(f[0]));
    if (t < 0.0)
      fail(path, n,
           "time_s: expected a number >= 0 (time since the orifice opened), got " + trim(f[0]));
    if (!s.time_s.empty() && !(t > s.time_s.back())) fail(path, n, "time_s must increase");
    s.time_s.push_back(t);
    s.value.push_back(number(path, n, header[1], trim(f[1])));
  }
  if (s.time_s.size() < 2) fail(path, n, "a series needs at least 2 samples");
  return s;
}

}  // namespace demcal::config
