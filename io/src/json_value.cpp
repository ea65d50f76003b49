#include "json_value.h"

#include <charconv>
#include <cmath>
#include <cstring>

#include "hedra/core/error.h"

namespace hedra::io {

JsonValue::JsonValue() = default;
JsonValue::JsonValue(const JsonValue&) = default;
JsonValue::JsonValue(JsonValue&&) noexcept = default;
JsonValue& JsonValue::operator=(const JsonValue&) = default;
JsonValue& JsonValue::operator=(JsonValue&&) noexcept = default;
JsonValue::~JsonValue() = default;


const char* JsonValue::kind_name() const {
  switch (kind) {
    case Kind::Null: return "null";
    case Kind::Bool: return "a boolean";
    case Kind::Number: return "a number";
    case Kind::String: return "a string";
    case Kind::Array: return "an array";
    case Kind::Object: return "an object";
  }
  return "?";
}

const JsonValue* JsonValue::find(const std::string& key) const {
  for (const auto& [k, v] : members)
    if (k == key) return &v;
  return nullptr;
}

namespace {

constexpr int kMaxDepth = 200;

class Parser {
 public:
  Parser(const std::string& path, const std::string& text) : path_(path), text_(text) {}

  JsonValue document() {
    skip_space();
    if (at_end()) fail("empty file (expected a JSON value)");
    JsonValue v = value(0);
    skip_space();
    if (!at_end()) fail("unexpected text after the JSON value");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { fail_at(line_, column_, message); }
  [[noreturn]] void fail_at(int line, int column, const std::string& message) const {
    throw InvalidInput(path_ + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " +
                       message);
  }
  bool at_end() const { return pos_ >= text_.size(); }
  char peek() const { return at_end() ? '\0' : text_[pos_]; }
  char get() {
    char c = text_[pos_++];
    if (c == '\n') { ++line_; column_ = 1; } else { ++column_; }
    return c;
  }
  void skip_space() {
    while (!at_end() && (peek() == ' ' || peek() == '\t' || peek() == '\n' || peek() == '\r')) get();
  }
  void expect(char c, const char* what) {
    skip_space();
    if (peek() != c) fail(std::string("expected ") + what);
    get();
  }

  JsonValue value(int depth) {
    if (depth > kMaxDepth) fail("nesting deeper than 200 levels");
    skip_space();
    JsonValue v;
    v.line = line_;
    v.column = column_;
    const char c = peek();
    if (c == '{') {
      get();
      v.kind = JsonValue::Kind::Object;
      skip_space();
      if (peek() == '}') { get(); return v; }
      while (true) {
        skip_space();
        const int kl = line_, kc = column_;
        if (peek() != '"') fail("expected a key in double quotes");
        std::string key = string_literal();
        if (v.find(key)) fail_at(kl, kc, "duplicate key '" + key + "'");
        expect(':', "':' after the key");
        JsonValue member = value(depth + 1);
        v.members.emplace_back(std::move(key), std::move(member));
        v.key_positions.emplace_back(kl, kc);
        skip_space();
        if (peek() == ',') { get(); continue; }
        if (peek() == '}') { get(); return v; }
        fail("expected ',' or '}' in an object");
      }
    }
    if (c == '[') {
      get();
      v.kind = JsonValue::Kind::Array;
      skip_space();
      if (peek() == ']') { get(); return v; }
      while (true) {
        v.items.push_back(value(depth + 1));
        skip_space();
        if (peek() == ',') { get(); continue; }
        if (peek() == ']') { get(); return v; }
        fail("expected ',' or ']' in an array");
      }
    }
    if (c == '"') {
      v.kind = JsonValue::Kind::String;
      v.string = string_literal();
      return v;
    }
    if (c == 't' || c == 'f' || c == 'n') {
      for (const char* word : {"true", "false", "null"}) {
        if (text_.compare(pos_, std::strlen(word), word) == 0) {
          for (size_t i = 0; i < std::strlen(word); ++i) get();
          v.kind = word[0] == 'n' ? JsonValue::Kind::Null : JsonValue::Kind::Bool;
          v.boolean = word[0] == 't';
          return v;
        }
      }
      fail("unknown word (expected true, false or null)");
    }
    if (c == '-' || (c >= '0' && c <= '9')) return number(v);
    if (at_end()) fail("unexpected end of file");
    fail(std::string("unexpected character '") + c + "'");
  }

  JsonValue number(JsonValue v) {
    const size_t start = pos_;
    if (peek() == '-') get();
    if (!(peek() >= '0' && peek() <= '9')) fail("malformed number");
    while (peek() >= '0' && peek() <= '9') get();
    if (peek() == '.') {
      get();
      if (!(peek() >= '0' && peek() <= '9')) fail("malformed number");
      while (peek() >= '0' && peek() <= '9') get();
    }
    if (peek() == 'e' || peek() == 'E') {
      get();
      if (peek() == '+' || peek() == '-') get();
      if (!(peek() >= '0' && peek() <= '9')) fail("malformed number");
      while (peek() >= '0' && peek() <= '9') get();
    }
    double x = 0;
    auto [end, ec] = std::from_chars(text_.data() + start, text_.data() + pos_, x);
    if (ec == std::errc::result_out_of_range || !std::isfinite(x))
      fail_at(v.line, v.column, "number out of the range of double");
    if (ec != std::errc() || end != text_.data() + pos_) fail_at(v.line, v.column, "malformed number");
    v.kind = JsonValue::Kind::Number;
    v.number = x;
    return v;
  }

  static void append_utf8(std::string& out, unsigned code) {
    if (code < 0x80) {
      out += static_cast<char>(code);
    } else if (code < 0x800) {
      out += static_cast<char>(0xC0 | (code >> 6));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else if (code < 0x10000) {
      out += static_cast<char>(0xE0 | (code >> 12));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (code >> 18));
      out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    }
  }

  unsigned hex4() {
    unsigned code = 0;
    for (int i = 0; i < 4; ++i) {
      if (at_end()) fail("unexpected end of file in a \\u escape");
      char h = get();
      code <<= 4;
      if (h >= '0' && h <= '9') code |= h - '0';
      else if (h >= 'a' && h <= 'f') code |= h - 'a' + 10;
      else if (h >= 'A' && h <= 'F') code |= h - 'A' + 10;
      else fail("bad \\u escape");
    }
    return code;
  }

  std::string string_literal() {
    get();  // opening quote
    std::string out;
    while (true) {
      if (at_end()) fail("unterminated string");
      char c = get();
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) fail("control character in a string");
      if (c != '\\') { out += c; continue; }
      if (at_end()) fail("unterminated string");
      char e = get();
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          unsigned code = hex4();
          if (code >= 0xD800 && code < 0xDC00) {
            if (peek() != '\\') fail("lone surrogate in a \\u escape");
            get();
            if (peek() != 'u') fail("lone surrogate in a \\u escape");
            get();
            unsigned low = hex4();
            if (low < 0xDC00 || low >= 0xE000) fail("bad surrogate pair");
            code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
          }
          append_utf8(out, code);
          break;
        }
        default: fail(std::string("bad escape '\\") + e + "'");
      }
    }
  }

  const std::string& path_;
  const std::string& text_;
  size_t pos_ = 0;
  int line_ = 1, column_ = 1;
};

}  // namespace

JsonValue parse_json(const std::string& path, const std::string& text) {
  return Parser(path, text).document();
}

}  // namespace hedra::io
