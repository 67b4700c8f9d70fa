#include "config/raw_recordings.hpp"

#include "config/doe_csv.hpp"
#include "config/observables.hpp"
#include "config/recordings_csv.hpp"
#include "dem/measure/angle_of_repose.hpp"
#include "dem/measure/discharge.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>

namespace demcal::config {

namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void fail(const std::string& file, std::size_t line, const std::string& what) {
  throw ConfigError(file + ":" + std::to_string(line) + ": " + what);
}
[[noreturn]] void fail_cell(const std::string& file, std::size_t line, std::size_t column,
                            const std::string& name, const std::string& what) {
  throw ConfigError(file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " +
                    name + ": " + what);
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

// The header (after a BOM and comment lines) and the data rows as (line, fields).
struct CsvRows {
  std::vector<std::pair<std::size_t, std::vector<std::string>>> rows;
  std::size_t last_line = 1;
};

CsvRows read_rows(std::istream& in, const std::string& file,
                  const std::vector<std::string>& header) {
  std::string expected;
  for (const auto& h : header) expected += (expected.empty() ? "" : ",") + h;
  std::string line;
  std::size_t n = 0;
  bool have_header = false;
  CsvRows out;
  while (std::getline(in, line)) {
    ++n;
    const std::string t = trim(n == 1 ? without_bom(line) : line);
    if (t.empty() || t[0] == '#') continue;
    std::vector<std::string> f = split_csv_line(t);
    for (auto& x : f) x = trim(x);
    if (!have_header) {
      if (f != header)
        fail(file, n, "expected the header " + expected + ", got \"" + printable(t) + "\"");
      have_header = true;
      continue;
    }
    if (f.size() != header.size())
      fail(file, n,
           "expected " + std::to_string(header.size()) + " fields (" + expected + "), got " +
               std::to_string(f.size()));
    out.rows.emplace_back(n, std::move(f));
  }
  out.last_line = std::max<std::size_t>(n, 1);
  if (!have_header) fail(file, out.last_line, "empty file; expected the header " + expected);
  return out;
}

double cell_number(const std::string& file, std::size_t line, std::size_t column,
                   const std::string& name, const std::string& text, const std::string& expected) {
  const auto v = parse_csv_number(text);
  if (!v)
    fail_cell(file, line, column, name,
              "expected " + expected + ", got " +
                  (text.empty() ? "an empty cell" : "\"" + printable(text) + "\""));
  return *v;
}

std::ifstream open(const fs::path& path) {
  return open_input_file(path, "a CSV file of readings", "cannot be read (no such file?)");
}

double degrees(double radians) { return radians * 180.0 / kPi; }

// Sum of squared deviations of n evenly spread abscissae over a span (the least-squares
// slope's denominator): n (n + 1) / (12 (n - 1)) span^2.
double spread_sxx(int n, double span) {
  if (n < 2 || !(span > 0.0)) return kNaN;
  const double m = n;
  return m * (m + 1.0) / (12.0 * (m - 1.0)) * span * span;
}

double mean_of(const std::vector<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

}  // namespace

std::optional<RawRecordingsConfig> read_raw_recordings(reader::Table& root,
                                                       const std::vector<std::string>& setups,
                                                       const std::string& study_file) {
  if (!root.has("raw_recordings")) return std::nullopt;
  reader::Table t = root.table("raw_recordings");
  RawRecordingsConfig c;
  const fs::path base = fs::path(study_file).parent_path();
  const auto paths = [&](reader::Table& s, const char* key) {
    std::vector<fs::path> out;
    for (const std::string& p : s.strings_or(key, {}, {})) {
      if (p.empty()) s.fail(key, "expected paths of CSV files, got an empty string");
      const fs::path f(p);
      out.push_back(f.is_absolute() ? f : base / f);
    }
    return out;
  };
  for (const auto& name : setups) {
    if (!t.has(name)) continue;
    reader::Table s = t.table(name);
    RawSetupRecordings r;
    r.setup = name;
    r.line = s.line();
    r.profiles = paths(s, "profiles");
    r.mass_series = paths(s, "mass_series");
    if (r.profiles.empty() && r.mass_series.empty())
      s.fail_here("expected profiles = [...] or mass_series = [...] (at least one file)");
    if (!r.profiles.empty()) {
      r.grain_diameter_m = s.number("grain_diameter_m", reader::between(0, true, 1, false));
      r.height_reading_error_m =
          s.number("height_reading_error_m", reader::between(0, true, 1, false));
    }
    if (!r.mass_series.empty()) {
      r.fill_mass_kg = s.number("fill_mass_kg", reader::between(0, true, 1e5, false));
      r.mass_reading_error_kg = s.number("mass_reading_error_kg", reader::above(0));
      r.time_reading_error_s = s.number("time_reading_error_s", reader::between(0, true, 1e3, false));
      if (!(r.mass_reading_error_kg < r.fill_mass_kg))
        s.fail("mass_reading_error_kg", "expected a number below fill_mass_kg (" +
                                            reader::format_number(r.fill_mass_kg) + ")");
    }
    s.finish();
    c.setups.push_back(std::move(r));
  }
  // A table named after no apparatus: listed as unknown, with the names that exist.
  t.finish();
  return c;
}

SurfaceProfile read_surface_profile_csv(std::istream& in, const std::string& file) {
  const CsvRows rows = read_rows(in, file, {"position_m", "height_m"});
  SurfaceProfile p;
  std::size_t readings = 0;
  for (const auto& [line, f] : rows.rows) {
    p.position_m.push_back(
        cell_number(file, line, 1, "position_m", f[0], "a finite number (metres)"));
    if (f[1].empty()) {
      p.height_m.push_back(kNaN);  // no reading at this position
      continue;
    }
    const double h = cell_number(file, line, 2, "height_m", f[1],
                                 "a finite number (metres above the floor) or an empty cell");
    if (h < 0.0)
      fail_cell(file, line, 2, "height_m",
                "expected a height >= 0 above the pile's floor, got " + printable(f[1]));
    p.height_m.push_back(h);
    ++readings;
  }
  if (readings < 4)
    fail(file, rows.last_line,
         "a surface profile needs at least 4 height readings, got " + std::to_string(readings));
  return p;
}

SurfaceProfile read_surface_profile_csv(const fs::path& path) {
  std::ifstream in = open(path);
  return read_surface_profile_csv(in, path.string());
}

MassSeries read_mass_series_csv(std::istream& in, const std::string& file, double fill_mass_kg) {
  const CsvRows rows = read_rows(in, file, {"time_s", "discharged_mass_kg"});
  MassSeries s;
  for (const auto& [line, f] : rows.rows) {
    const double t = cell_number(file, line, 1, "time_s", f[0],
                                 "a finite number >= 0 (seconds since the orifice opened)");
    if (t < 0.0)
      fail_cell(file, line, 1, "time_s",
                "expected a number >= 0 (seconds since the orifice opened), got " + f[0]);
    if (!s.time_s.empty() && !(t > s.time_s.back()))
      fail_cell(file, line, 1, "time_s",
                "expected times that increase, got " + printable(f[0]) + " after " +
                    reader::format_number(s.time_s.back()));
    const double m = cell_number(file, line, 2, "discharged_mass_kg", f[1],
                                 "a finite number >= 0 (kilograms)");
    if (m < 0.0 || m > fill_mass_kg)
      fail_cell(file, line, 2, "discharged_mass_kg",
                "expected a mass in [0, fill_mass_kg = " + reader::format_number(fill_mass_kg) +
                    "], got " + printable(f[1]));
    s.time_s.push_back(t);
    s.mass_kg.push_back(m);
  }
  if (s.time_s.size() < 2)
    fail(file, rows.last_line,
         "a mass series needs at least 2 samples, got " + std::to_string(s.time_s.size()));
  return s;
}

MassSeries read_mass_series_csv(const fs::path& path, double fill_mass_kg) {
  std::ifstream in = open(path);
  return read_mass_series_csv(in, path.string(), fill_mass_kg);
}

std::map<std::string, std::pair<double, double>> measure_profile(const SurfaceProfile& profile,
                                                                 double grain_diameter_m,
                                                                 double height_reading_error_m,
                                                                 std::string* skipped) {
  std::map<std::string, std::pair<double, double>> out;
  dem::AngleOfRepose a;
  try {
    a = dem::measure_profile_angle_of_repose(profile.position_m, profile.height_m,
                                             grain_diameter_m);
  } catch (const std::exception& e) {
    if (skipped) *skipped = e.what();
    return out;
  }
  if (!std::isfinite(a.mean_deg)) {
    if (skipped) *skipped = "no angle of repose could be fitted";
    return out;
  }
  // Reading error of each side's fitted slope, then of the mean of the sides.
  double var = 0.0;
  int sides = 0;
  for (const auto& s : a.sides) {
    if (!s.valid) continue;
    const double sxx = spread_sxx(s.points, s.fit_to_m - s.fit_from_m);
    const double slope_sd = std::isfinite(sxx) ? height_reading_error_m / std::sqrt(sxx) : kNaN;
    const double angle_sd = degrees(slope_sd / (1.0 + s.slope * s.slope));
    var += angle_sd * angle_sd;
    ++sides;
  }
  const double sigma = sides > 0 ? std::sqrt(var) / sides : kNaN;
  if (!std::isfinite(sigma) || !(sigma > 0.0)) {
    if (skipped) *skipped = "the reading error of the fitted sides could not be propagated";
    return out;
  }
  out["angle_of_repose_deg"] = {a.mean_deg, sigma};
  return out;
}

std::map<std::string, std::pair<double, double>> measure_mass_series(
    const MassSeries& series, double fill_mass_kg, double mass_reading_error_kg,
    double time_reading_error_s, std::string* skipped) {
  std::map<std::string, std::pair<double, double>> out;
  // The sandglass's own options (dem/apparatus/sandglass.cpp): a flat-bottomed hopper's dead
  // zones end the flow without a clog; a measured series needs a stall threshold above its
  // noise.
  dem::DischargeOptions o;
  o.complete_fraction = 1e-9;
  o.stall_mass_kg = 3.0 * mass_reading_error_kg;
  dem::DischargeAnalysis a;
  try {
    a = dem::analyse_discharge(series.time_s, series.mass_kg, fill_mass_kg, o);
  } catch (const std::exception& e) {
    if (skipped) *skipped = e.what();
    return out;
  }
  if (!std::isfinite(a.discharge_time_s)) {
    if (skipped) *skipped = "the discharge did not finish (" + a.status + ")";
    return out;
  }
  const double rate = a.mass_flow_rate_kg_s;
  // A crossing time moves by the clock's error and by the balance's over the rate.
  const auto time_sigma = [&] {
    const double m = std::isfinite(rate) && rate > 0.0 ? mass_reading_error_kg / rate : 0.0;
    return std::sqrt(time_reading_error_s * time_reading_error_s + m * m);
  };
  out["discharge_time_s"] = {a.discharge_time_s, time_sigma()};
  if (std::isfinite(rate) && rate > 0.0) {
    const double sxx = spread_sxx(static_cast<int>(a.steady_samples),
                                  a.steady_end_s - a.steady_start_s);
    const double noise = std::sqrt(mass_reading_error_kg * mass_reading_error_kg +
                                   rate * rate * time_reading_error_s * time_reading_error_s);
    if (std::isfinite(sxx)) out["mass_flow_rate_kg_s"] = {rate, noise / std::sqrt(sxx)};
  }
  // t25, t50, t75 exactly as the design tables read them off a run's series.
  nlohmann::json s = {{"discharged_mass", {{"time_s", series.time_s}, {"mass_kg", series.mass_kg}}}};
  const nlohmann::json obs = {{"discharge_time_s", a.discharge_time_s}};
  const nlohmann::json segments = series_observables(s, obs);
  for (const auto& name : series_observable_names())
    if (segments.contains(name) && segments[name].is_number())
      out[name] = {segments[name].get<double>(), time_sigma()};
  return out;
}

std::vector<RawMeasurement> measure_raw_recordings(const RawRecordingsConfig& config) {
  std::vector<RawMeasurement> all;
  for (const RawSetupRecordings& r : config.setups) {
    std::map<std::string, RawMeasurement> by;
    const auto add = [&](const std::map<std::string, std::pair<double, double>>& got,
                         const fs::path& file, const std::string& skipped) {
      if (got.empty()) {
        by["(none)"].skipped.push_back(file.string() + ": " + skipped);
        return;
      }
      for (const auto& [name, v] : got) {
        RawMeasurement& m = by[name];
        if (!observable_in_range(name, v.first)) {
          m.skipped.push_back(file.string() + ": " + name + " = " +
                              reader::format_number(v.first) + " outside " +
                              observable_range_text(name));
          continue;
        }
        m.values.push_back(v.first);
        m.reading_sigma.push_back(v.second);
      }
    };
    for (const auto& f : r.profiles) {
      std::string why;
      add(measure_profile(read_surface_profile_csv(f), r.grain_diameter_m,
                          r.height_reading_error_m, &why),
          f, why);
    }
    for (const auto& f : r.mass_series) {
      std::string why;
      add(measure_mass_series(read_mass_series_csv(f, r.fill_mass_kg), r.fill_mass_kg,
                              r.mass_reading_error_kg, r.time_reading_error_s, &why),
          f, why);
    }
    std::vector<std::string> unusable;
    if (auto it = by.find("(none)"); it != by.end()) {
      unusable = it->second.skipped;
      by.erase(it);
    }
    if (by.empty()) {
      std::string why;
      for (const auto& u : unusable) why += "; " + u;
      throw ConfigError("raw_recordings." + r.setup + ": no repeat gave a measurement" + why);
    }
    for (auto& [name, m] : by) {
      m.setup = r.setup;
      m.observable = name;
      m.skipped.insert(m.skipped.end(), unusable.begin(), unusable.end());
      if (m.values.empty()) continue;
      const double n = static_cast<double>(m.values.size());
      m.mean = mean_of(m.values);
      double var = 0.0;
      for (const double s : m.reading_sigma) var += s * s;
      m.sigma = std::sqrt(var) / n;
      double ss = 0.0;
      for (const double v : m.values) ss += (v - m.mean) * (v - m.mean);
      m.repeats_sd = m.values.size() > 1 ? std::sqrt(ss / (n - 1.0)) : kNaN;
      all.push_back(std::move(m));
    }
  }
  return all;
}

std::vector<calibrate::Recording> to_recordings(const std::vector<RawMeasurement>& measured) {
  std::vector<calibrate::Recording> out;
  for (const auto& m : measured) {
    calibrate::Recording r;
    r.setup = m.setup;
    r.observable = m.observable;
    r.value = m.mean;
    r.sigma = m.sigma;
    r.repeats = static_cast<int>(m.values.size());
    r.unit = unit_of_observable(m.observable);
    out.push_back(r);
  }
  return out;
}

std::vector<std::string> raw_recording_lines(const std::vector<RawMeasurement>& measured) {
  std::vector<std::string> lines;
  for (const auto& m : measured) {
    const std::string unit = " " + unit_of_observable(m.observable);
    std::ostringstream s;
    s << m.setup << " " << m.observable << " = " << reader::format_number(m.mean) << unit
      << ", the mean of " << m.values.size() << " repeat" << (m.values.size() == 1 ? "" : "s");
    if (std::isfinite(m.repeats_sd))
      s << " (their sd " << reader::format_number(m.repeats_sd) << unit
        << ": the test-to-test scatter observed)";
    s << "; sigma = " << reader::format_number(m.sigma) << unit
      << ", the stated reading error propagated to the mean (the test-to-test scatter is the "
         "DEM's over sqrt(repeats))";
    for (const auto& k : m.skipped) s << "; left out: " << k;
    s << ".";
    lines.push_back(s.str());
  }
  return lines;
}

}  // namespace demcal::config
