#include "hedra/io/mesh_io.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>
#include <unordered_map>
#include <cctype>
#include <filesystem>
#include <optional>

#include "hedra/io/atomic_file.h"
#include "obj.h"
#include "off.h"
#include "ply.h"
#include "stl.h"
#include "hedra/io/text_reader.h"
#include "hedra/core/error.h"
#include "hedra/mesh/self_intersection.h"

namespace hedra::io {

MeshFormat format_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".off") return MeshFormat::Off;
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".stl") return MeshFormat::Stl;
  if (ext == ".ply") return MeshFormat::Ply;
  throw InvalidInput(path + ": unknown mesh format '" + ext + "' (expected .off, .obj, .stl or .ply)");
}

PolygonSoup read_soup(const std::string& path) {
  const MeshFormat format = format_of(path);
  const std::string bytes = read_file(path);
  if (bytes.empty()) throw InvalidInput(path + ": empty file");
  switch (format) {
    case MeshFormat::Off: return parse_off(path, bytes);
    case MeshFormat::Obj: return parse_obj(path, bytes);
    case MeshFormat::Stl: return parse_stl(path, bytes);
    case MeshFormat::Ply: return parse_ply(path, bytes);
  }
  throw InvalidInput(path + ": unknown format");
}

namespace {

// The first body that intersects itself, as "component 1: faces 3 and 7 intersect near (…)".
std::optional<std::string> self_intersection(const std::vector<Body>& bodies) {
  for (size_t c = 0; c < bodies.size(); ++c)
    if (const auto hit = find_self_intersection(bodies[c]))
      return (bodies.size() > 1 ? "component " + std::to_string(c) + ": " : std::string()) +
             describe(*hit);
  return std::nullopt;
}

}  // namespace

std::vector<Body> read_bodies(const std::string& path, const ReadOptions& options) {
  PolygonSoup soup = read_soup(path);
  try {
    std::vector<Body> bodies = bodies_from_soup(soup, options.merge);
    // Validation up front (docs/io.md): every body read is checked for self-intersection, so
    // no command is asked about a polyhedron that does not exist.
    auto hit = self_intersection(bodies);
    if (hit && options.merge.coplanar_tolerance > 0 && options.merge.planarity_tolerance < 0) {
      // Snapping moved vertices (by at most the tolerance); if that made the surface touch
      // itself, the exactly merged input is taken, as for any other failure of snapping.
      MergeOptions exact = options.merge;
      exact.coplanar_tolerance = 0;
      bodies = bodies_from_soup(soup, exact);
      hit = self_intersection(bodies);
    }
    if (hit) throw InvalidInput("the surface intersects itself: " + *hit);
    return bodies;
  } catch (const InvalidInput& e) {
    throw InvalidInput(path + ": " + e.what());
  }
}

PolygonSoup soup_of(const std::vector<Body>& bodies, bool triangles_only) {
  PolygonSoup soup;
  for (const Body& body : bodies) {
    const int base = static_cast<int>(soup.vertices.size());
    soup.vertices.insert(soup.vertices.end(), body.vertices().begin(), body.vertices().end());
    std::vector<char> needs_triangles(body.face_count(), triangles_only);
    for (int f = 0; f < body.face_count(); ++f) {
      if (body.faces()[f].loops.size() > 1) needs_triangles[f] = 1;
      if (needs_triangles[f]) continue;
      std::vector<int> poly = body.faces()[f].loops[0];
      for (int& v : poly) v += base;
      soup.polygons.push_back(std::move(poly));
    }
    for (const Triangle& t : body.triangles())
      if (needs_triangles[t.face])
        soup.polygons.push_back({t.v[0] + base, t.v[1] + base, t.v[2] + base});
  }
  return soup;
}

namespace {

// STL stores no vertex numbers: a reader welds points of equal coordinates (as written: float32
// in binary STL). Two bodies sharing such a point (stacked boxes) would read back as one
// non-manifold mesh, which hedra rejects, so it does not write them. Cost O(V) expected.
void require_apart_in_stl(const std::vector<Body>& bodies, const WriteOptions& options) {
  if (bodies.size() < 2) return;
  struct Hash {
    size_t operator()(const std::array<double, 3>& p) const {
      size_t h = 0;
      for (double x : p) h = h * 0x9E3779B97F4A7C15ull + std::hash<double>()(x);
      return h;
    }
  };
  std::unordered_map<std::array<double, 3>, size_t, Hash> owner;
  const auto name = [&](size_t b) {
    return options.names.size() == bodies.size() ? "'" + options.names[b] + "'" : "#" + std::to_string(b);
  };
  for (size_t b = 0; b < bodies.size(); ++b)
    for (const Vec3& p : bodies[b].vertices()) {
      std::array<double, 3> key{p.x(), p.y(), p.z()};
      if (!options.stl_ascii)
        for (double& x : key) x = static_cast<float>(x);
      const auto [it, inserted] = owner.try_emplace(key, b);
      if (inserted || it->second == b) continue;
      char where[96];
      std::snprintf(where, sizeof where, "(%.9g, %.9g, %.9g)", key[0], key[1], key[2]);
      throw InvalidInput("bodies " + name(it->second) + " and " + name(b) + " share the point " + where +
                         (options.stl_ascii ? "" : " (in float32)") +
                         ": STL welds equal points, so the file would read back as one non-manifold mesh; "
                         "write OFF, OBJ, PLY or a scene file to keep them apart");
    }
}

// Binary STL stores float32 corners: a body whose rounding to float32 is not a valid body (two
// vertices become one point, a face collapses to a line, the surface touches itself: features
// below about 1e-7 of the coordinates) would be written as a file no reader takes for the solid
// it was. So the bytes are read back as hedra reads a file, and must give as many valid bodies
// as were written. Cost: one read of the file, O(T log T) (its self-intersection test).
void require_readable_stl(const std::string& bytes, size_t bodies) {
  const char* const fix = "; ASCII STL (which keeps doubles), OFF, OBJ, PLY or a scene file keep it";
  std::vector<Body> back;
  try {
    back = bodies_from_soup(parse_stl("STL", bytes));
    if (const auto hit = self_intersection(back))
      throw InvalidInput("the surface intersects itself: " + *hit);
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("rounded to float32 (binary STL), the bodies would not read back: ") + e.what() + fix);
  }
  if (back.size() != bodies)
    throw InvalidInput("rounded to float32 (binary STL), the " + std::to_string(bodies) + " bodies would read back as " +
                       std::to_string(back.size()) + fix);
}

}  // namespace

std::string format_bodies(const std::vector<Body>& bodies, MeshFormat format,
                          const WriteOptions& options) {
  switch (format) {
    case MeshFormat::Off: return format_off(soup_of(bodies, false));
    case MeshFormat::Obj: {
      std::vector<std::pair<size_t, std::string>> groups;
      if (options.names.size() == bodies.size()) {
        size_t first = 0;
        for (size_t b = 0; b < bodies.size(); ++b) {
          groups.emplace_back(first, options.names[b]);
          first += soup_of({bodies[b]}, false).polygons.size();
        }
      }
      return format_obj(soup_of(bodies, false), groups);
    }
    case MeshFormat::Ply: return format_ply(soup_of(bodies, false));
    case MeshFormat::Stl:
      require_apart_in_stl(bodies, options);
      if (options.stl_ascii) return format_stl_ascii(soup_of(bodies, true));
      {
        std::string bytes = format_stl_binary(soup_of(bodies, true));
        require_readable_stl(bytes, bodies.size());
        return bytes;
      }
  }
  throw InvalidInput("unknown mesh format");
}

void write_bodies(const std::vector<Body>& bodies, const std::string& path,
                  const WriteOptions& options) {
  const MeshFormat format = format_of(path);
  std::string bytes;
  try {
    bytes = format_bodies(bodies, format, options);
  } catch (const InvalidInput& e) {
    throw InvalidInput(path + ": " + e.what());
  }
  write_file_atomically(path, bytes);
}

}  // namespace hedra::io
