// Fuzzes the run-store record reader: a run file's text -> parse_run_record
// (what RunStore::load checks) -> the design-table row made from an accepted
// record (make_doe_table reads its observables and m(t) series). Nothing may
// throw: a record that is not whole is refused by parse_run_record.
#include "config/observables.hpp"
#include "config/run_record_reader.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // The digest of the seed corpus' records, so that fuzzing gets past that check.
  static const std::string kDigest = "fuzz";
  std::string problem;
  const auto record = demcal::config::parse_run_record(text, kDigest, &problem);
  if (record) {
    const nlohmann::json& r = *record;
    const nlohmann::json observables =
        demcal::config::with_stable_observables(r.contains("observables") ? r.at("observables") : nlohmann::json());
    (void)demcal::config::series_observables(r.contains("series") ? r.at("series") : nlohmann::json::object(),
                                          observables);
  }
  return 0;
}
