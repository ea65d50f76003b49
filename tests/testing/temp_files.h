// Scratch directories and files for tests: a fresh, empty directory per test, and text written
// to a file in one call.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace hedra::testing {

/// An empty directory under the system's temporary directory (emptied if it exists).
inline std::filesystem::path temp_dir(const std::string& name) {
  const std::filesystem::path d = std::filesystem::temp_directory_path() / ("hedra_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

/// Writes `text` to `path` (binary) and returns the path as a string.
inline std::string write(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

}  // namespace hedra::testing
