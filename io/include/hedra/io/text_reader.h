// Line-by-line reading of text mesh formats with "file:line:" error locations.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace hedra::io {

/// Splits a text into lines and lines into whitespace-separated tokens; every error it
/// raises names the file and the line.
class TextReader {
 public:
  TextReader(std::string path, std::string text);
  /// Advances to the next line that has tokens (after stripping `comment` and what follows).
  /// Returns false at the end of the text.
  bool next_line(char comment = '#');
  const std::vector<std::string_view>& tokens() const { return tokens_; }
  int line_number() const { return line_number_; }
  /// "file:line: message", as an InvalidInput.
  [[noreturn]] void fail(const std::string& message) const;
  /// Token i of the current line as a finite double / a non-negative or signed integer.
  double number(size_t i, const char* what) const;
  long long integer(size_t i, const char* what) const;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string text_;
  size_t position_ = 0;
  int line_number_ = 0;
  std::vector<std::string_view> tokens_;
};

/// Largest input file read by default: 1 GiB. Every reader's memory is bounded by a small
/// multiple of its input (docs/io.md, "Resource limits"), so this bounds them all.
constexpr size_t kDefaultMaxInputBytes = size_t{1} << 30;
/// The input limit in force: HEDRA_MAX_INPUT_BYTES from the environment if set, else
/// kDefaultMaxInputBytes.
size_t max_input_bytes();

/// Whole file as bytes, at most max_input_bytes() of them. \throw IoError naming the file
/// when it cannot be read, is a directory, or is larger than the limit (a device such as
/// /dev/zero stops at the limit).
std::string read_file(const std::string& path);
/// The same with an explicit limit.
std::string read_file(const std::string& path, size_t max_bytes);

}  // namespace hedra::io
