// Scratch directories and files for tests: a fresh, empty directory per test, and text written
// to a file in one call.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>
#include <vector>

namespace hedra::testing {

/// Removes the directories made by temp_dir() when the test program ends (unless the
/// environment sets HEDRA_KEEP_TEST_FILES, to look at them).
class TempDirs {
 public:
  static TempDirs& instance() {
    static TempDirs dirs;
    return dirs;
  }
  void add(const std::filesystem::path& d) { dirs_.push_back(d); }
  ~TempDirs() {
    if (std::getenv("HEDRA_KEEP_TEST_FILES")) return;
    std::error_code ec;
    for (const auto& d : dirs_) std::filesystem::remove_all(d, ec);
  }

 private:
  std::vector<std::filesystem::path> dirs_;
};

/// An empty directory under the system's temporary directory, private to this process (ctest
/// runs each test of a program as its own process, several at once: a shared name would let
/// one test empty another's files), removed at exit.
inline std::filesystem::path temp_dir(const std::string& name) {
  const std::filesystem::path d = std::filesystem::temp_directory_path() /
                                  ("hedra_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  TempDirs::instance().add(d);
  return d;
}

/// Writes `text` to `path` (binary) and returns the path as a string.
inline std::string write(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

/// The whole content of the file at `path` ("" if it cannot be read).
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace hedra::testing
