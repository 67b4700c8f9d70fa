#pragma once
// Output files are written under a temporary name and renamed into place, so
// a crash or a full disk leaves either the previous file or none, never a
// truncated one that a reader (ParaView, a calibration script) would half-parse.

#include <filesystem>
#include <string_view>

namespace demcal::dem {

// Writes `content` to `file` atomically (same-directory temporary + rename).
// Throws std::runtime_error naming the file when writing or renaming fails.
void write_file_atomically(const std::filesystem::path& file, std::string_view content);

}  // namespace demcal::dem
