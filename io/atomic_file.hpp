#pragma once
// demcal's one atomic file writer. Every file demcal writes (run records, the
// run store, design tables, the stage cache, surrogates, reports, VTK output)
// goes through it, so a crash, a kill or a full disk leaves the previous file
// or none, never a truncated one that a reader would half-parse.
//
// The file is written under a hidden temporary name in the same directory
// (".<name>.<host>.<pid>.<n>.tmp": rename is atomic only within one file
// system, and the name is unique across threads, processes and the hosts of a
// shared file system), flushed to disk (fsync) and renamed into place.
// Temporaries left by processes of this host that no longer run are removed
// by remove_stale_temporaries; those of other hosts are left alone (their
// writers may be alive).

#include <cstddef>
#include <filesystem>
#include <string_view>

namespace demcal::io {

// Writes `content` to `file` atomically and durably. The directory must exist.
// Throws std::runtime_error naming the file on failure (the temporary is removed).
void write_file_atomically(const std::filesystem::path& file, std::string_view content);

// Removes the temporaries in `dir` that processes of this host left and that
// no longer run; returns how many.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir);

}  // namespace demcal::io
