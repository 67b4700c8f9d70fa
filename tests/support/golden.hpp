#pragma once
// Golden files: text a test produces, compared byte for byte with a file kept
// under tests/data/. To regenerate after an intended change, run the tests
// with DEMCAL_UPDATE_GOLDEN=1 in the environment: each golden is rewritten (and
// the test passes); review the diff before committing it.

#include "tests/support/test_files.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace demcal::testing {

inline bool updating_golden() {
  const char* v = std::getenv("DEMCAL_UPDATE_GOLDEN");
  return v != nullptr && std::string(v) == "1";
}

// Compares `actual` with the golden file (relative to tests/data/); on a
// mismatch reports the first differing line.
inline void expect_golden(const std::string& actual, const std::string& relative_path) {
  const std::filesystem::path path =
      std::filesystem::path(DEMCAL_SOURCE_DIR) / "tests/data" / relative_path;
  if (updating_golden()) {
    spit(path, actual);
    return;
  }
  ASSERT_TRUE(std::filesystem::exists(path))
      << path << " is missing; run with DEMCAL_UPDATE_GOLDEN=1 to write it";
  const std::string expected = slurp(path);
  if (expected == actual) return;
  std::size_t line = 1, i = 0;
  while (i < expected.size() && i < actual.size() && expected[i] == actual[i]) {
    if (expected[i] == '\n') ++line;
    ++i;
  }
  auto line_at = [](const std::string& s, std::size_t at) {
    const std::size_t b = s.rfind('\n', at == 0 ? 0 : at - 1);
    const std::size_t start = b == std::string::npos ? 0 : b + 1;
    return s.substr(start, s.find('\n', start) - start);
  };
  ADD_FAILURE() << relative_path << " differs from the golden file at line " << line
                << "\n  golden: " << line_at(expected, i) << "\n  actual: " << line_at(actual, i)
                << "\n(DEMCAL_UPDATE_GOLDEN=1 rewrites it after an intended change)";
}

}  // namespace demcal::testing
