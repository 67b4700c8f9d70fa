// Fuzzes the study config reader: TOML text -> parse -> build_study (every
// apparatus built, as `demcal simulate/doe` do before anything runs). The only
// outcome allowed for bad input is a ConfigError.
#include "config/study_config.hpp"
#include "config/toml_reader.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    demcal::config::ConfigDocument doc = demcal::config::parse_config_string(text, "fuzz.toml");
    if (demcal::config::is_study_config(doc)) (void)demcal::config::build_study(std::move(doc));
  } catch (const demcal::config::ConfigError&) {
  }
  return 0;
}
