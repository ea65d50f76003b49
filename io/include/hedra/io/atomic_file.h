// Output files appear whole or not at all, and a command's several outputs appear together.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hedra::io {

/// Writes `bytes` to a temporary file next to `path`, then renames it over `path`, so a failed
/// run never leaves a half-written file. \throw IoError naming the file.
void write_file_atomically(const std::string& path, const std::string& bytes);

/// All of a command's outputs or none: each add() writes its bytes at once to a temporary name
/// next to the target (so a missing directory or a full disk fails before anything is
/// visible); commit() renames them all into place. Destroyed without commit(), it removes
/// what it staged. A rename that fails half-way through commit() (not seen in practice: the
/// temporary names sit in the targets' own directories) leaves the earlier ones in place.
class OutputTransaction {
 public:
  OutputTransaction() = default;
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;
  ~OutputTransaction();

  /// Stages one file. \throw IoError naming `path`.
  void add(const std::string& path, const std::string& bytes);
  /// Stages one file written piece by piece: `produce` is called once with a function that
  /// appends bytes to the staged file (a report of hundreds of MB never held whole). An
  /// exception from `produce` removes the staged file and propagates. \throw IoError naming
  /// `path`.
  void add(const std::string& path,
           const std::function<void(const std::function<void(std::string_view)>& write)>& produce);
  /// Stages a directory of files (name, bytes): written into a temporary directory renamed to
  /// `dir` on commit when `dir` does not exist; into `dir` itself, file by file through
  /// temporary names, when it is an existing directory. \throw IoError when `dir` exists and is
  /// not a directory, or cannot be written.
  void add_directory(const std::string& dir,
                     const std::vector<std::pair<std::string, std::string>>& files);
  /// Renames every staged output into place. \throw IoError naming the output.
  void commit();

 private:
  struct Staged {
    std::filesystem::path temp, target;
    std::string name;  // target as the caller spelled it, for messages
  };
  std::vector<Staged> staged_;
  bool committed_ = false;
};

}  // namespace hedra::io
