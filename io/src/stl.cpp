#include "stl.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <algorithm>
#include <vector>

#include "hedra/io/text_reader.h"
#include "hedra/core/error.h"

namespace hedra::io {
namespace {

// Welds the triangles' corners into shared vertices: equal coordinates (== on doubles, so
// −0 and +0 are one point) get one id, ids in order of first appearance, the vertex stored as
// first seen. An open-addressing hash table on the coordinates' bits (−0 folded into +0),
// grown by doubling: O(1) per corner expected (was a std::map: O(log n) with a cache miss per
// level, most of the time of reading a million-triangle file).
struct Welder {
  PolygonSoup soup;
  std::vector<int> slots;  // vertex id + 1, 0 empty; size a power of two
  size_t mask = 0;

  explicit Welder(size_t expected_vertices = 0) { rehash(std::max<size_t>(64, 2 * expected_vertices)); }

  static std::uint64_t bits(double v) {
    v += 0.0;  // −0 → +0
    std::uint64_t u;
    std::memcpy(&u, &v, 8);
    return u;
  }
  static std::uint64_t hash(const Vec3& p) {
    std::uint64_t h = bits(p.x()) * 0x9E3779B97F4A7C15ull;
    h ^= bits(p.y()) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= bits(p.z()) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    h ^= h >> 33;
    h *= 0xFF51AFD7ED558CCDull;
    h ^= h >> 33;
    return h;
  }
  void rehash(size_t size) {
    size_t n = 64;
    while (n < size) n *= 2;
    slots.assign(n, 0);
    mask = n - 1;
    for (size_t i = 0; i < soup.vertices.size(); ++i) {
      size_t at = hash(soup.vertices[i]) & mask;
      while (slots[at] != 0) at = (at + 1) & mask;
      slots[at] = static_cast<int>(i) + 1;
    }
  }
  int id(const Vec3& p) {
    size_t at = hash(p) & mask;
    while (slots[at] != 0) {
      const int v = slots[at] - 1;
      if (soup.vertices[static_cast<size_t>(v)] == p) return v;
      at = (at + 1) & mask;
    }
    const int v = static_cast<int>(soup.vertices.size());
    soup.vertices.push_back(p);
    slots[at] = v + 1;
    if (2 * soup.vertices.size() > slots.size()) rehash(2 * slots.size());
    return v;
  }
  void triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
    soup.polygons.push_back({id(a), id(b), id(c)});
  }
};

PolygonSoup parse_binary(const std::string& path, const std::string& bytes) {
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  // A closed triangle mesh has about half as many vertices as triangles.
  Welder w(n / 2 + 16);
  w.soup.polygons.reserve(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    const char* record = bytes.data() + 84 + 50 * static_cast<size_t>(t);
    Vec3 p[3];
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, record + 12 + 12 * k, 12);
      p[k] = Vec3(xyz[0], xyz[1], xyz[2]);
      if (!p[k].allFinite())
        throw InvalidInput(path + ": triangle " + std::to_string(t) + " (byte " +
                           std::to_string(84 + 50 * static_cast<size_t>(t)) +
                           ") has a non-finite coordinate");
    }
    w.triangle(p[0], p[1], p[2]);
  }
  return std::move(w.soup);
}

PolygonSoup parse_ascii(const std::string& path, const std::string& text) {
  TextReader in(path, text);
  Welder w;
  if (!in.next_line(0) || in.tokens()[0] != "solid") in.fail("expected 'solid'");
  auto expect = [&](std::string_view word) {
    if (!in.next_line(0)) in.fail("unexpected end of file (expected '" + std::string(word) + "')");
    if (in.tokens()[0] != word)
      in.fail("expected '" + std::string(word) + "', got '" + std::string(in.tokens()[0]) + "'");
  };
  while (true) {
    if (!in.next_line(0)) in.fail("unexpected end of file (expected 'facet' or 'endsolid')");
    std::string_view word = in.tokens()[0];
    if (word == "endsolid") break;
    if (word != "facet") in.fail("expected 'facet' or 'endsolid', got '" + std::string(word) + "'");
    expect("outer");
    Vec3 p[3];
    for (int k = 0; k < 3; ++k) {
      expect("vertex");
      p[k] = Vec3(in.number(1, "x"), in.number(2, "y"), in.number(3, "z"));
    }
    expect("endloop");
    expect("endfacet");
    w.triangle(p[0], p[1], p[2]);
  }
  if (w.soup.polygons.empty()) in.fail("no facets");
  return std::move(w.soup);
}

}  // namespace

PolygonSoup parse_stl(const std::string& path, const std::string& bytes) {
  if (bytes.empty()) throw InvalidInput(path + ": empty file");
  if (bytes.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    if (84 + 50 * static_cast<std::uint64_t>(n) == bytes.size()) {
      if (n == 0) throw InvalidInput(path + ": binary STL with no triangles");
      return parse_binary(path, bytes);
    }
  }
  size_t first = bytes.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && bytes.compare(first, 5, "solid") == 0 &&
      bytes.find('\0') == std::string::npos)
    return parse_ascii(path, bytes);
  if (bytes.size() < 84)
    throw InvalidInput(path + ": truncated binary STL: " + std::to_string(bytes.size()) +
                       " bytes, shorter than the 84-byte header");
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  const std::uint64_t expected = 84 + 50 * static_cast<std::uint64_t>(n);
  const std::uint64_t size = bytes.size();
  std::string why;
  if ((size - 84) % 50 == 0)
    why = "; the file holds " + std::to_string((size - 84) / 50) +
          " whole triangles: wrong triangle count in the header";
  else if (size < expected)
    why = ": truncated file";
  else
    why = ": trailing bytes or a wrong triangle count";
  throw InvalidInput(path + ": binary STL header says " + std::to_string(n) +
                     " triangles, which need " + std::to_string(expected) +
                     " bytes, but the file has " + std::to_string(size) + why);
}

std::string format_stl_binary(const PolygonSoup& soup) {
  std::string out(84 + 50 * soup.polygons.size(), '\0');
  std::memcpy(out.data(), "binary STL written by hedra", 27);
  std::uint32_t n = static_cast<std::uint32_t>(soup.polygons.size());
  std::memcpy(out.data() + 80, &n, 4);
  for (size_t t = 0; t < soup.polygons.size(); ++t) {
    const auto& tri = soup.polygons[t];
    const Vec3 &a = soup.vertices[tri[0]], &b = soup.vertices[tri[1]], &c = soup.vertices[tri[2]];
    Vec3 normal = (b - a).cross(c - a);
    if (normal.norm() > 0) normal.normalize();
    float values[12];
    const Vec3* vs[4] = {&normal, &a, &b, &c};
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < 3; ++i) values[3 * k + i] = static_cast<float>((*vs[k])[i]);
    std::memcpy(out.data() + 84 + 50 * t, values, 48);
  }
  return out;
}

std::string format_stl_ascii(const PolygonSoup& soup) {
  std::string out = "solid hedra\n";
  char buf[128];
  for (const auto& tri : soup.polygons) {
    const Vec3 &a = soup.vertices[tri[0]], &b = soup.vertices[tri[1]], &c = soup.vertices[tri[2]];
    Vec3 normal = (b - a).cross(c - a);
    if (normal.norm() > 0) normal.normalize();
    std::snprintf(buf, sizeof buf, "  facet normal %.9g %.9g %.9g\n    outer loop\n", normal.x(),
                  normal.y(), normal.z());
    out += buf;
    for (const Vec3* p : {&a, &b, &c}) {
      std::snprintf(buf, sizeof buf, "      vertex %.17g %.17g %.17g\n", p->x(), p->y(), p->z());
      out += buf;
    }
    out += "    endloop\n  endfacet\n";
  }
  out += "endsolid hedra\n";
  return out;
}

}  // namespace hedra::io
