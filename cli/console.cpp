#include "cli/console.hpp"

#include <algorithm>
#include <mutex>
#include <set>
#include <sstream>

namespace demcal::cli {

namespace {

std::size_t display_width(const std::string& s) {
  std::size_t n = 0;
  for (unsigned char c : s) n += (c & 0xC0) != 0x80;
  return n;
}

}  // namespace

void warn_once(std::ostream& log, const std::string& text) {
  static std::mutex mutex;
  static std::set<std::string> printed;
  std::lock_guard<std::mutex> lock(mutex);
  if (!printed.insert(text).second) return;
  log << "warning: " << text << "\n";
}

std::string aligned_table(const std::vector<std::vector<std::string>>& rows,
                          const std::string& indent) {
  std::vector<std::size_t> width;
  for (const auto& r : rows) {
    if (width.size() < r.size()) width.resize(r.size(), 0);
    for (std::size_t j = 0; j < r.size(); ++j) width[j] = std::max(width[j], display_width(r[j]));
  }
  std::ostringstream s;
  for (const auto& r : rows) {
    std::string line = indent;
    for (std::size_t j = 0; j < r.size(); ++j) {
      line += r[j];
      if (j + 1 < r.size()) line += std::string(width[j] - display_width(r[j]) + 2, ' ');
    }
    s << line << "\n";
  }
  return s.str();
}

}  // namespace demcal::cli
