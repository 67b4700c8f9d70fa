#pragma once
// Reading a campaign table (doe.csv, as study/doe_table.hpp writes it, or a
// checked-in copy of one) back into numbers: what `demcal fit` fits and what
// tests use to fit without running DEM. Header:
//   point, replicate, seed, apparatus, <parameter columns...>,
//   <the stable observables>, [<the series observables>,] status, hash
// (the observables as io/observable_registry.hpp declares them: angle_of_repose_deg,
// discharge_time_s, ...).
// The parameter columns are those between "apparatus" and the first
// observable. Empty cells are NaN (not measured). A malformed file is a
// ConfigError naming file:line and what was expected.

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace demcal::config {

struct DoeCsvRow {
  std::size_t line = 0;
  int point = 0;
  int replicate = 0;
  std::uint64_t seed = 0;
  std::string apparatus;
  std::vector<double> parameters;
  std::vector<double> observables;  // aligned with DoeCsv::observable_names; NaN = empty
  std::string status;
  std::string hash;
};

struct DoeCsv {
  std::string file;
  std::vector<std::string> parameter_names;
  std::vector<std::string> observable_names;
  std::vector<DoeCsvRow> rows;
  // Index of an observable column, or -1.
  int observable_index(const std::string& name) const;
};

DoeCsv read_doe_csv(const std::filesystem::path& path);
// The same from a stream; `file` names it in messages (fuzzing, tests).
DoeCsv read_doe_csv(std::istream& in, const std::string& file);

// The text as a finite number when it is one written in full (no trailing
// characters), else nullopt: empty, "abc", "1.5x", "inf".
std::optional<double> parse_csv_number(const std::string& text);

// A file demcal reads (a CSV, a surrogate's JSON), opened in binary (the CSV readers drop
// the '\r' of CRLF): a
// ConfigError "<path>: <if_missing>" when it cannot be opened, and "<path>: is a
// directory; expected <what>" for a directory (which opens on Linux and reads as empty).
std::ifstream open_input_file(const std::filesystem::path& path, const std::string& what,
                              const std::string& if_missing);

// `s` with its control characters (a NUL, a tab, a stray '\r') shown as \xNN: how every
// CSV reader quotes a cell or a line in a message, so that it stays one readable line and
// an invisible byte does not make "3\x0096" look like the number 396.
std::string printable(const std::string& s);

// `line` without a leading UTF-8 byte order mark (some editors write one).
std::string without_bom(const std::string& line);

// One CSV line split into fields (double-quoted fields may hold commas and "").
std::vector<std::string> split_csv_line(const std::string& line);

}  // namespace demcal::config
