#pragma once
// <output>/<study name>: where doe, fit, inspect, calibrate and diagnose keep a
// study's files (runs/, doe.csv, surrogates/, reports/, stages.json).

#include <filesystem>
#include <string>

namespace demcal::study {

inline std::filesystem::path study_directory(const std::filesystem::path& output_dir,
                                             const std::string& study_name) {
  return output_dir / study_name;
}

}  // namespace demcal::study
