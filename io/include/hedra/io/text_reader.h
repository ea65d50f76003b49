// Line-by-line reading of text mesh formats with "file:line:" error locations.
#pragma once

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

/// Whole file as bytes. \throw IoError naming the file when it cannot be read.
std::string read_file(const std::string& path);

}  // namespace hedra::io
