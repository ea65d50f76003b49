#include "hedra/io/text_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hedra/core/error.h"

namespace hedra::io {

namespace {

// std::isspace in the "C" locale (hedra never sets another), without a library call per byte.
bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
}

}  // namespace

TextReader::TextReader(std::string path, std::string text)
    : path_(std::move(path)), text_(std::move(text)) {}

bool TextReader::next_line(char comment) {
  while (position_ < text_.size()) {
    size_t end = text_.find('\n', position_);
    if (end == std::string::npos) end = text_.size();
    std::string_view line(text_.data() + position_, end - position_);
    position_ = end + 1;
    ++line_number_;
    if (size_t c = line.find(comment); c != std::string_view::npos) line = line.substr(0, c);
    tokens_.clear();
    size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_space(line[i])) ++i;
      size_t j = i;
      while (j < line.size() && !is_space(line[j])) ++j;
      if (j > i) tokens_.push_back(line.substr(i, j - i));
      i = j;
    }
    if (!tokens_.empty()) return true;
  }
  tokens_.clear();
  return false;
}

void TextReader::fail(const std::string& message) const {
  throw InvalidInput(path_ + ":" + std::to_string(line_number_) + ": " + message);
}

double TextReader::number(size_t i, const char* what) const {
  if (i >= tokens_.size()) fail(std::string("missing ") + what);
  std::string_view t = tokens_[i];
  double value = 0;
  auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (ec == std::errc::result_out_of_range)
    fail(std::string(what) + " '" + std::string(t) + "' is out of the range of double");
  if (ec != std::errc() || end != t.data() + t.size())
    fail(std::string("expected a number for ") + what + ", got '" + std::string(t) + "'");
  if (!std::isfinite(value))
    fail(std::string(what) + " is not finite ('" + std::string(t) + "')");
  return value;
}

long long TextReader::integer(size_t i, const char* what) const {
  if (i >= tokens_.size()) fail(std::string("missing ") + what);
  std::string_view t = tokens_[i];
  long long value = 0;
  auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (ec != std::errc() || end != t.data() + t.size())
    fail(std::string("expected an integer for ") + what + ", got '" + std::string(t) + "'");
  return value;
}

size_t max_input_bytes() {
  static const size_t limit = [] {
    if (const char* env = std::getenv("HEDRA_MAX_INPUT_BYTES")) {
      unsigned long long v = 0;
      auto [end, ec] = std::from_chars(env, env + std::strlen(env), v);
      if (ec == std::errc() && *end == '\0' && v > 0) return static_cast<size_t>(v);
    }
    return kDefaultMaxInputBytes;
  }();
  return limit;
}

std::string read_file(const std::string& path) { return read_file(path, max_input_bytes()); }

std::string read_file(const std::string& path, size_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_directory(status)) throw IoError(path + ": is a directory, not a file");
  auto too_large = [&](const std::string& size) {
    return IoError(path + ": " + size + " is more than the input limit of " +
                   std::to_string(max_bytes) + " bytes (HEDRA_MAX_INPUT_BYTES raises it)");
  };
  // A regular file's size is known: checked before anything is read, and reserved (with room
  // for the last, short block), so the blocks below are not copied as the string grows.
  size_t known_size = 0;
  if (fs::is_regular_file(status)) {
    const auto size = fs::file_size(path, ec);
    if (!ec && size > max_bytes) throw too_large("the file's " + std::to_string(size) + " bytes");
    if (!ec) known_size = static_cast<size_t>(size);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open the file for reading");
  // Read in blocks up to the limit: a device or a pipe (/dev/zero) has no size to check first.
  std::string bytes;
  if (known_size > 0) bytes.reserve(std::min(known_size + (1 << 20), max_bytes + 1));
  constexpr size_t kBlock = 1 << 20;
  while (in) {
    const size_t at = bytes.size();
    const size_t want = std::min(kBlock, max_bytes + 1 - at);
    bytes.resize(at + want);
    in.read(bytes.data() + at, static_cast<std::streamsize>(want));
    bytes.resize(at + static_cast<size_t>(in.gcount()));
    if (bytes.size() > max_bytes) throw too_large("its content beyond " + std::to_string(max_bytes) + " bytes");
  }
  if (in.bad()) throw IoError(path + ": read error");
  return bytes;
}

}  // namespace hedra::io
