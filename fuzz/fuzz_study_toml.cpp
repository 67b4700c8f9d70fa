// Fuzzes the study config reader: TOML text -> parse -> build_study (every
// apparatus built, as `demcal simulate/doe` do before anything runs). The only
// outcome allowed for bad input is a ConfigError.
#include "cli/study_config.hpp"
#include "cli/toml_reader.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    demcal::cli::ConfigDocument doc = demcal::cli::parse_config_string(text, "fuzz.toml");
    if (demcal::cli::is_study_config(doc)) (void)demcal::cli::build_study(std::move(doc));
  } catch (const demcal::cli::ConfigError&) {
  }
  return 0;
}
