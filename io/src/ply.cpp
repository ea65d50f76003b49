#include "ply.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "hedra/io/text_reader.h"
#include "hedra/core/error.h"

namespace hedra::io {
namespace {

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parse_type(std::string_view s, Type& t) {
  if (s == "char" || s == "int8") t = Type::Int8;
  else if (s == "uchar" || s == "uint8") t = Type::UInt8;
  else if (s == "short" || s == "int16") t = Type::Int16;
  else if (s == "ushort" || s == "uint16") t = Type::UInt16;
  else if (s == "int" || s == "int32") t = Type::Int32;
  else if (s == "uint" || s == "uint32") t = Type::UInt32;
  else if (s == "float" || s == "float32") t = Type::Float32;
  else if (s == "double" || s == "float64") t = Type::Float64;
  else return false;
  return true;
}

size_t size_of(Type t) {
  switch (t) {
    case Type::Int8: case Type::UInt8: return 1;
    case Type::Int16: case Type::UInt16: return 2;
    case Type::Int32: case Type::UInt32: case Type::Float32: return 4;
    case Type::Float64: return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  Type type = Type::Float32;
  bool is_list = false;
  Type count_type = Type::UInt8;
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> properties;
};

enum class Format { Ascii, Little, Big };

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Reads values of an element's records from ASCII tokens or binary bytes.
class ValueSource {
 public:
  ValueSource(const std::string& path, const std::string& bytes, size_t start, Format format)
      : path_(path), bytes_(bytes), position_(start), format_(format) {}

  double read(Type t, const std::string& where) {
    if (format_ == Format::Ascii) return read_ascii(where);
    const size_t n = size_of(t);
    if (position_ + n > bytes_.size())
      throw InvalidInput(path_ + ": unexpected end of file in " + where);
    unsigned char raw[8];
    std::memcpy(raw, bytes_.data() + position_, n);
    position_ += n;
    if ((format_ == Format::Big) == (std::endian::native == std::endian::little))
      std::reverse(raw, raw + n);
    switch (t) {
      case Type::Int8: { std::int8_t v; std::memcpy(&v, raw, 1); return v; }
      case Type::UInt8: { std::uint8_t v; std::memcpy(&v, raw, 1); return v; }
      case Type::Int16: { std::int16_t v; std::memcpy(&v, raw, 2); return v; }
      case Type::UInt16: { std::uint16_t v; std::memcpy(&v, raw, 2); return v; }
      case Type::Int32: { std::int32_t v; std::memcpy(&v, raw, 4); return v; }
      case Type::UInt32: { std::uint32_t v; std::memcpy(&v, raw, 4); return v; }
      case Type::Float32: { float v; std::memcpy(&v, raw, 4); return v; }
      case Type::Float64: { double v; std::memcpy(&v, raw, 8); return v; }
    }
    return 0;
  }

 private:
  double read_ascii(const std::string& where) {
    while (position_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[position_])))
      ++position_;
    size_t end = position_;
    while (end < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[end]))) ++end;
    if (end == position_) throw InvalidInput(path_ + ": unexpected end of file in " + where);
    double v = 0;
    auto [stop, ec] = std::from_chars(bytes_.data() + position_, bytes_.data() + end, v);
    if (ec != std::errc() || stop != bytes_.data() + end)
      throw InvalidInput(path_ + ": expected a number in " + where + ", got '" +
                         bytes_.substr(position_, std::min<size_t>(end - position_, 20)) + "'");
    position_ = end;
    return v;
  }

  const std::string& path_;
  const std::string& bytes_;
  size_t position_;
  Format format_;
};

}  // namespace

PolygonSoup parse_ply(const std::string& path, const std::string& bytes) {
  if (bytes.empty()) throw InvalidInput(path + ": empty file");
  // Header: text lines up to "end_header".
  size_t header_end = bytes.find("end_header");
  if (bytes.compare(0, 3, "ply") != 0) throw InvalidInput(path + ":1: not a PLY file");
  if (header_end == std::string::npos) throw InvalidInput(path + ": PLY header has no end_header");
  size_t data_start = bytes.find('\n', header_end);
  data_start = data_start == std::string::npos ? bytes.size() : data_start + 1;
  TextReader header(path, bytes.substr(0, header_end));
  Format format = Format::Ascii;
  bool have_format = false;
  std::vector<Element> elements;
  header.next_line(0);  // "ply"
  while (header.next_line(0)) {
    const auto& t = header.tokens();
    if (t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "format") {
      if (t.size() < 2) header.fail("format line without a format");
      if (t[1] == "ascii") format = Format::Ascii;
      else if (t[1] == "binary_little_endian") format = Format::Little;
      else if (t[1] == "binary_big_endian") format = Format::Big;
      else header.fail("unknown PLY format '" + std::string(t[1]) + "'");
      have_format = true;
    } else if (t[0] == "element") {
      if (t.size() < 3) header.fail("element line needs a name and a count");
      Element e{std::string(t[1]), header.integer(2, "element count"), {}};
      if (e.count < 0 || e.count > 100'000'000) header.fail("implausible element count");
      elements.push_back(std::move(e));
    } else if (t[0] == "property") {
      if (elements.empty()) header.fail("property before any element");
      Property p;
      if (t.size() >= 5 && t[1] == "list") {
        p.is_list = true;
        if (!parse_type(t[2], p.count_type) || !parse_type(t[3], p.type))
          header.fail("unknown property type");
        p.name = t[4];
      } else if (t.size() >= 3) {
        if (!parse_type(t[1], p.type))
          header.fail("unknown property type '" + std::string(t[1]) + "'");
        p.name = t[2];
      } else {
        header.fail("malformed property line");
      }
      elements.back().properties.push_back(p);
    } else {
      header.fail("unexpected header line '" + std::string(t[0]) + "'");
    }
  }
  if (!have_format) throw InvalidInput(path + ": PLY header has no format line");

  // Structure first: the elements hedra reads must have the properties it reads.
  for (const Element& e : elements) {
    bool x = false, y = false, z = false, indices = false;
    for (const Property& p : e.properties) {
      x = x || p.name == "x";
      y = y || p.name == "y";
      z = z || p.name == "z";
      indices = indices || ((p.name == "vertex_indices" || p.name == "vertex_index") && p.is_list);
    }
    if (e.name == "vertex" && !(x && y && z))
      throw InvalidInput(path + ": vertex element lacks x, y or z");
    if (e.name == "face" && !indices) throw InvalidInput(path + ": face element lacks vertex_indices");
  }
  // Each record takes at least a byte per value (ASCII: a character and a separator), so the
  // declared counts must fit in the data; an element without properties has nothing to read.
  {
    long double need = 0;
    for (const Element& e : elements) {
      long double record = 0;
      for (const Property& p : e.properties)
        record += format == Format::Ascii ? 2 : static_cast<long double>(size_of(p.is_list ? p.count_type : p.type));
      need += record * e.count;
    }
    const long double have = bytes.size() - data_start + 1;  // the last value needs no separator
    if (need > have)
      throw InvalidInput(path + ": the header's element counts need at least " +
                         std::to_string(static_cast<long long>(need)) + " bytes of data, but the file has " +
                         std::to_string(bytes.size() - data_start));
  }
  PolygonSoup soup;
  ValueSource source(path, bytes, data_start, format);
  long long vertex_count = -1;
  for (const Element& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    int xi = -1, yi = -1, zi = -1, fi = -1;
    for (size_t k = 0; k < e.properties.size(); ++k) {
      const std::string& n = e.properties[k].name;
      if (is_vertex && n == "x") xi = static_cast<int>(k);
      if (is_vertex && n == "y") yi = static_cast<int>(k);
      if (is_vertex && n == "z") zi = static_cast<int>(k);
      if (is_face && (n == "vertex_indices" || n == "vertex_index") && e.properties[k].is_list)
        fi = static_cast<int>(k);
    }
    if (is_vertex && (xi < 0 || yi < 0 || zi < 0))
      throw InvalidInput(path + ": vertex element lacks x, y or z");
    if (is_face && fi < 0) throw InvalidInput(path + ": face element lacks vertex_indices");
    if (is_vertex) vertex_count = e.count;
    if (e.properties.empty()) continue;
    for (long long r = 0; r < e.count; ++r) {
      const std::string where = e.name + " " + std::to_string(r);
      Vec3 p = Vec3::Zero();
      std::vector<int> poly;
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const Property& prop = e.properties[k];
        if (prop.is_list) {
          double count = source.read(prop.count_type, where);
          // Negated so that NaN fails too (fuzz finding: a NaN count reached the int cast).
          if (!(count >= 0 && count <= 1e6)) throw InvalidInput(path + ": bad list size in " + where);
          for (int j = 0; j < static_cast<int>(count); ++j) {
            double value = source.read(prop.type, where);
            if (static_cast<int>(k) == fi) {
              if (value < 0 || value >= static_cast<double>(std::max(vertex_count, 0LL)) ||
                  value != std::floor(value))
                // %.17g, not a cast: 1.3e32 or NaN do not fit a long long (fuzz finding).
                throw InvalidInput(path + ": " + where + " refers to vertex " + number_text(value) +
                                   ", out of range");
              poly.push_back(static_cast<int>(value));
            }
          }
        } else {
          double value = source.read(prop.type, where);
          if (static_cast<int>(k) == xi) p.x() = value;
          if (static_cast<int>(k) == yi) p.y() = value;
          if (static_cast<int>(k) == zi) p.z() = value;
        }
      }
      if (is_vertex) {
        if (!p.allFinite()) throw InvalidInput(path + ": " + where + " has a non-finite coordinate");
        soup.vertices.push_back(p);
      }
      if (is_face) {
        if (poly.size() < 3)
          throw InvalidInput(path + ": " + where + " has " + std::to_string(poly.size()) +
                             " vertices; a face needs at least 3");
        soup.polygons.push_back(std::move(poly));
      }
    }
  }
  if (soup.polygons.empty()) throw InvalidInput(path + ": no faces");
  return soup;
}

std::string format_ply(const PolygonSoup& soup) {
  size_t largest = 0;
  for (const auto& poly : soup.polygons) largest = std::max(largest, poly.size());
  const std::string count_type = largest > 255 ? "uint" : "uchar";
  std::string out = "ply\nformat ascii 1.0\ncomment written by hedra\n";
  out += "element vertex " + std::to_string(soup.vertices.size()) + "\n";
  out += "property double x\nproperty double y\nproperty double z\n";
  out += "element face " + std::to_string(soup.polygons.size()) + "\n";
  out += "property list " + count_type + " int vertex_indices\nend_header\n";
  char buf[96];
  for (const Vec3& p : soup.vertices) {
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    out += buf;
  }
  for (const auto& poly : soup.polygons) {
    out += std::to_string(poly.size());
    for (int v : poly) out += " " + std::to_string(v);
    out += "\n";
  }
  return out;
}

}  // namespace hedra::io
