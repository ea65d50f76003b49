#include "hedra/io/text_reader.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "hedra/core/error.h"

namespace hedra::io {

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
      while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      size_t j = i;
      while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
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

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open the file for reading");
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw IoError(path + ": read error");
  return s.str();
}

}  // namespace hedra::io
