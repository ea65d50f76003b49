// A small JSON reader that remembers where every value starts, so scene-file errors can name
// the line and column ("scene.json:14:9: …"). nlohmann-json is used for writing; its parser
// does not expose value positions.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace hedra::io {

struct JsonValue {
  enum class Kind { Null, Bool, Number, String, Array, Object };
  Kind kind = Kind::Null;
  bool boolean = false;
  double number = 0;
  std::string string;
  std::vector<JsonValue> items;                            // Array
  std::vector<std::pair<std::string, JsonValue>> members;  // Object, in file order
  std::vector<std::pair<int, int>> key_positions;          // line, column of each member's key
  int line = 0, column = 0;

  // Declared here, defined where JsonValue is complete (json_value.cpp): `members` holds
  // pairs of an incomplete type, which clang's libstdc++ instantiation refuses inline.
  JsonValue();
  JsonValue(const JsonValue&);
  JsonValue(JsonValue&&) noexcept;
  JsonValue& operator=(const JsonValue&);
  JsonValue& operator=(JsonValue&&) noexcept;
  ~JsonValue();

  const char* kind_name() const;
  /// Member by key, or nullptr.
  const JsonValue* find(const std::string& key) const;
};

/// Parses RFC 8259 JSON (nesting limited to 200 levels; duplicate keys rejected).
/// \throw InvalidInput "path:line:column: message".
JsonValue parse_json(const std::string& path, const std::string& text);

}  // namespace hedra::io
