// Fuzzes the design-table reader (doe.csv). The only outcome allowed for bad
// input is a ConfigError.
#include "config/doe_csv.hpp"
#include "config/toml_reader.hpp"

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    (void)demcal::config::read_doe_csv(in, "doe.csv");
  } catch (const demcal::config::ConfigError&) {
  }
  return 0;
}
