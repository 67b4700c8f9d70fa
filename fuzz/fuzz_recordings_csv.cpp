// Fuzzes the recordings CSV reader (and the series CSV reader on the same
// bytes). The only outcome allowed for bad input is a ConfigError.
#include "config/recordings_csv.hpp"
#include "config/toml_reader.hpp"

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    std::istringstream in(text);
    (void)demcal::config::read_recordings_csv(in, "recordings.csv", {"sandglass", "conical_pile", "container"});
  } catch (const demcal::config::ConfigError&) {
  }
  try {
    std::istringstream in(text);
    (void)demcal::config::read_series_csv(in, "series.csv", "sandglass");
  } catch (const demcal::config::ConfigError&) {
  }
  return 0;
}
