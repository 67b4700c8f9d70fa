#include "engines/dump_reader.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

namespace demcal::engines {
namespace {

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw DumpFormatError(path.string() + ": cannot open");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Lines with their 1-based numbers; a final line without '\n' counts.
class Lines {
 public:
  Lines(const std::string& text, std::string name) : text_(text), name_(std::move(name)) {}
  bool next(std::string& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = text_.find('\n', pos_);
    line = text_.substr(pos_, end == std::string::npos ? std::string::npos : end - pos_);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos_ = end == std::string::npos ? text_.size() : end + 1;
    ++number_;
    return true;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw DumpFormatError(name_ + ":" + std::to_string(number_) + ": " + what);
  }
  [[noreturn]] void fail_at_end(const std::string& what) const {
    throw DumpFormatError(name_ + ":" + std::to_string(number_) + ": unexpected end of file, " +
                          what);
  }
  int number() const { return number_; }

 private:
  const std::string& text_;
  std::string name_;
  std::size_t pos_ = 0;
  int number_ = 0;
};

std::vector<std::string> words(const std::string& line) {
  std::istringstream s(line);
  std::vector<std::string> out;
  for (std::string w; s >> w;) out.push_back(w);
  return out;
}

std::optional<double> to_double(const std::string& w) {
  double v = 0.0;
  const auto [p, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
  if (ec != std::errc() || p != w.data() + w.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<std::int64_t> to_int(const std::string& w) {
  std::int64_t v = 0;
  const auto [p, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
  if (ec != std::errc() || p != w.data() + w.size()) return std::nullopt;
  return v;
}

}  // namespace

ParticleDump read_custom_dump(const std::filesystem::path& path) {
  return parse_custom_dump(slurp(path), path.string());
}

ParticleDump parse_custom_dump(const std::string& text, const std::string& name) {
  Lines lines(text, name);
  std::string line;
  std::optional<ParticleDump> last;
  auto expect_item = [&](const std::string& item) {
    if (!lines.next(line)) lines.fail_at_end("expected \"ITEM: " + item + "\"");
    if (line.rfind("ITEM: " + item, 0) != 0)
      lines.fail("expected \"ITEM: " + item + "\", found \"" + line + "\"");
  };
  while (lines.next(line)) {
    if (words(line).empty()) continue;  // blank lines between snapshots
    if (line.rfind("ITEM: TIMESTEP", 0) != 0)
      lines.fail("expected \"ITEM: TIMESTEP\", found \"" + line + "\"");
    ParticleDump d;
    if (!lines.next(line)) lines.fail_at_end("expected the timestep");
    const auto ts = to_int(words(line).size() == 1 ? words(line)[0] : "");
    if (!ts) lines.fail("expected one integer timestep, found \"" + line + "\"");
    d.timestep = *ts;
    expect_item("NUMBER OF ATOMS");
    if (!lines.next(line)) lines.fail_at_end("expected the number of atoms");
    const auto count = to_int(words(line).size() == 1 ? words(line)[0] : "");
    if (!count || *count < 0)
      lines.fail("expected a non-negative atom count, found \"" + line + "\"");
    expect_item("BOX BOUNDS");
    double* lo[3] = {&d.box_lower_m.x, &d.box_lower_m.y, &d.box_lower_m.z};
    double* hi[3] = {&d.box_upper_m.x, &d.box_upper_m.y, &d.box_upper_m.z};
    for (int a = 0; a < 3; ++a) {
      if (!lines.next(line)) lines.fail_at_end("expected box bounds");
      const auto w = words(line);
      // Orthogonal boxes have 2 numbers, triclinic ones a third (the tilt): ignored.
      if (w.size() != 2 && w.size() != 3)
        lines.fail("expected \"lo hi\" box bounds, found \"" + line + "\"");
      const auto l = to_double(w[0]), h = to_double(w[1]);
      if (!l || !h || !(*l <= *h)) lines.fail("invalid box bounds \"" + line + "\"");
      *lo[a] = *l;
      *hi[a] = *h;
    }
    expect_item("ATOMS");
    const auto header = words(line);
    std::map<std::string, std::size_t> col;
    for (std::size_t i = 2; i < header.size(); ++i) col[header[i]] = i - 2;
    for (const char* need : {"id", "x", "y", "z", "radius"})
      if (!col.count(need))
        lines.fail(std::string("the ATOMS columns lack \"") + need +
                   "\" (needed: id x y z radius; found \"" + line + "\")");
    d.has_velocity = col.count("vx") && col.count("vy") && col.count("vz");
    const bool has_type = col.count("type") > 0;
    const std::size_t ncol = header.size() - 2;
    d.id.reserve(*count);
    for (std::int64_t i = 0; i < *count; ++i) {
      if (!lines.next(line))
        lines.fail_at_end("expected " + std::to_string(*count) + " atom lines, found " +
                          std::to_string(i));
      const auto w = words(line);
      if (w.size() != ncol)
        lines.fail("expected " + std::to_string(ncol) + " columns, found " +
                   std::to_string(w.size()));
      auto number = [&](const char* c) {
        const auto v = to_double(w[col.at(c)]);
        if (!v)
          lines.fail(std::string("column ") + c + ": \"" + w[col.at(c)] +
                     "\" is not a finite number");
        return *v;
      };
      const auto id = to_int(w[col.at("id")]);
      if (!id) lines.fail("column id: \"" + w[col.at("id")] + "\" is not an integer");
      d.id.push_back(*id);
      if (has_type) {
        const auto t = to_int(w[col.at("type")]);
        if (!t) lines.fail("column type: \"" + w[col.at("type")] + "\" is not an integer");
        d.type.push_back(static_cast<int>(*t));
      } else {
        d.type.push_back(1);
      }
      d.position_m.push_back({number("x"), number("y"), number("z")});
      const double r = number("radius");
      if (!(r > 0.0)) lines.fail("column radius: " + w[col.at("radius")] + " is not positive");
      d.radius_m.push_back(r);
      d.velocity_m_s.push_back(d.has_velocity ? dem::Vec3{number("vx"), number("vy"), number("vz")}
                                              : dem::Vec3{});
    }
    last = std::move(d);
  }
  if (!last)
    throw DumpFormatError(name + ":" + std::to_string(lines.number()) +
                          ": no snapshot in the file");
  return std::move(*last);
}

double MassSeries::fill_mass_kg() const {
  if (time_s.empty()) return std::nan("");
  return discharged_kg.front() + above_orifice_kg.front();
}

MassSeries read_mass_series(const std::filesystem::path& path) {
  return parse_mass_series(slurp(path), path.string());
}

MassSeries parse_mass_series(const std::string& text, const std::string& name) {
  Lines lines(text, name);
  MassSeries m;
  std::string line;
  while (lines.next(line)) {
    const auto w = words(line);
    if (w.empty() || w[0][0] == '#') continue;
    if (w.size() != 3)
      lines.fail(
          "expected 3 columns (t_since_opening_s discharged_mass_kg mass_above_orifice_kg), "
          "found " +
          std::to_string(w.size()));
    double v[3];
    for (int i = 0; i < 3; ++i) {
      const auto x = to_double(w[i]);
      if (!x) lines.fail("\"" + w[i] + "\" is not a finite number");
      v[i] = *x;
    }
    if (!m.time_s.empty() && !(v[0] > m.time_s.back()))
      lines.fail("time " + w[0] + " does not increase (previous row " +
                 std::to_string(m.time_s.back()) + ")");
    // A rounding of the subtraction fill - above may dip a hair below 0.
    if (v[1] < -1e-12 * std::max(1.0, std::abs(v[2])) || v[2] < 0.0) lines.fail("negative mass");
    m.time_s.push_back(v[0]);
    m.discharged_kg.push_back(std::max(0.0, v[1]));
    m.above_orifice_kg.push_back(v[2]);
  }
  if (m.time_s.size() < 2)
    throw DumpFormatError(name + ":" + std::to_string(lines.number()) +
                          ": a mass series needs at least 2 rows, found " +
                          std::to_string(m.time_s.size()));
  return m;
}

}  // namespace demcal::engines
