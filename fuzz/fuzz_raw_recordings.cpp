// Fuzzes the raw recordings' readers (config/raw_recordings.hpp): the surface profile and the
// m(t) CSV on the same bytes, and whatever they accept measured as a study would. The only
// outcome allowed for bad input is a ConfigError; the measurements report what they cannot
// measure rather than throw.
#include "config/raw_recordings.hpp"
#include "config/toml_reader.hpp"

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    std::istringstream in(text);
    const auto p = demcal::config::read_surface_profile_csv(in, "profile.csv");
    std::string why;
    (void)demcal::config::measure_profile(p, 5e-4, 1e-4, &why);
  } catch (const demcal::config::ConfigError&) {
  }
  try {
    std::istringstream in(text);
    const auto m = demcal::config::read_mass_series_csv(in, "mass.csv", 0.5);
    std::string why;
    (void)demcal::config::measure_mass_series(m, 0.5, 1e-3, 1e-3, &why);
  } catch (const demcal::config::ConfigError&) {
  }
  return 0;
}
