#pragma once
// What the console prints, in one place: each warning once per process (a study runs
// fit and then inspect, which would repeat fit's), and tables aligned by their
// characters, not their bytes ("±", "–" and "²" are two or three bytes in UTF-8).

#include <ostream>
#include <string>
#include <vector>

namespace demcal::cli {

// Prints "warning: <text>" unless this process has printed the same text before.
void warn_once(std::ostream& log, const std::string& text);

// Rows (the first is the header) padded to their columns' widths, two spaces apart,
// each line starting with `indent`.
std::string aligned_table(const std::vector<std::vector<std::string>>& rows,
                          const std::string& indent = "  ");

}  // namespace demcal::cli
