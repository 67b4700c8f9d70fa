#pragma once
// The check of every option that names a directory demcal writes into (--output,
// --run-store): a path that exists, or whose nearest existing ancestor exists, as
// something other than a directory is refused when the command line is read (exit 2),
// before anything runs, instead of failing later inside std::filesystem.

#include <CLI/CLI.hpp>

#include <filesystem>
#include <string>
#include <system_error>

namespace demcal::cli {

inline CLI::Validator directory_to_write() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        namespace fs = std::filesystem;
        if (text.empty()) return "expected a directory, got an empty path";
        std::error_code ec;
        fs::path p(text);
        while (!p.empty()) {
          const fs::file_status s = fs::status(p, ec);
          if (fs::exists(s)) {
            if (fs::is_directory(s)) return {};
            const std::string what = p.string() == text ? "" : " (in \"" + text + "\")";
            return "\"" + p.string() + "\"" + what +
                   " exists and is not a directory; expected a directory (created if missing)";
          }
          if (!p.has_relative_path() || p == p.parent_path()) break;
          p = p.parent_path();
        }
        return {};
      },
      "DIR");
}

}  // namespace demcal::cli
