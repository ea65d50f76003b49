#include "hedra/core/body.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cmath>
#include <limits>
#include <cstdio>
#include <map>
#include <numeric>
#include <span>
#include <string>
#include <tuple>

#include "core/exact_solid.h"
#include "hedra/core/error.h"
#include "hedra/core/face_geometry.h"
#include "hedra/core/parallel.h"
#include "hedra/core/tolerance.h"
#include "hedra/core/triangulate.h"

namespace hedra {

struct Body::Impl {
  std::vector<Vec3> vertices;
  std::vector<Face> faces;
  std::vector<Edge> edges;
  std::vector<Plane> planes;
  std::vector<std::array<int, 3>> supports;
  std::vector<Triangle> triangles;
  std::vector<double> face_areas;
  std::vector<int> off_plane;  // Body::faces_off_plane()
  BodyMatrix matrix;
  Eigen::AlignedBox3d bbox;
  double scale = 0;
  double volume = 0;
  double area = 0;
  Vec3 centroid = Vec3::Zero();
  bool two_sided = false;
  // The exact solid this body rounds (Body::exact_solid()), or null.
  std::shared_ptr<const internal::ExactSolid> exact;
  // is_convex()'s verdict, decided on first use (−1: not yet).
  mutable std::atomic<int> convexity{-1};
};

namespace {

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string vec(const Vec3& v) {
  return "(" + fmt(v.x()) + ", " + fmt(v.y()) + ", " + fmt(v.z()) + ")";
}

std::string str(int i) { return std::to_string(i); }


// Stage: coordinates.
void check_vertices(const std::vector<Vec3>& vertices) {
  if (vertices.size() < 4) throw InvalidInput("a body needs at least 4 vertices, got " +
                                              std::to_string(vertices.size()));
  for (size_t i = 0; i < vertices.size(); ++i) {
    const Vec3& p = vertices[i];
    if (!p.allFinite())
      throw InvalidInput("vertex " + std::to_string(i) + " has a non-finite coordinate " + vec(p));
    if (p.cwiseAbs().maxCoeff() > kMaxAbsCoordinate)
      throw InvalidInput("vertex " + std::to_string(i) + " has a coordinate beyond ±" +
                         fmt(kMaxAbsCoordinate) + ": " + vec(p));
  }
}

// The loops of a face list, as the checks below read them: Body's faces, or the polygons of
// a soup (each one loop), which are then checked without being copied into faces.
struct FaceLoops {
  const std::vector<Face>& faces;
  size_t size() const { return faces.size(); }
  std::span<const std::vector<int>> operator[](size_t f) const { return faces[f].loops; }
};
struct PolygonLoops {
  const std::vector<std::vector<int>>& polygons;
  size_t size() const { return polygons.size(); }
  std::span<const std::vector<int>> operator[](size_t f) const { return {&polygons[f], 1}; }
};

// Stage: face lists.
template <class Loops>
void check_faces(const Loops& faces, size_t vertex_count) {
  if (faces.size() < 4) throw InvalidInput("a body needs at least 4 faces, got " +
                                           std::to_string(faces.size()));
  std::vector<int> seen(vertex_count, -1);
  for (size_t f = 0; f < faces.size(); ++f) {
    const std::span<const std::vector<int>> loops = faces[f];
    if (loops.empty()) throw InvalidInput("face " + std::to_string(f) + " is empty");
    for (size_t l = 0; l < loops.size(); ++l) {
      const auto& loop = loops[l];
      auto where = [&] {  // built only for a message: a string per loop costs more than the check
        return "face " + std::to_string(f) + (l ? " (hole " + std::to_string(l) + ")" : "");
      };
      if (loop.size() < 3)
        throw InvalidInput(where() + " has " + std::to_string(loop.size()) +
                           " vertices; a face needs at least 3");
      for (int v : loop) {
        if (v < 0 || static_cast<size_t>(v) >= vertex_count)
          throw InvalidInput(where() + " refers to vertex " + std::to_string(v) +
                             ", out of range (the body has " + std::to_string(vertex_count) +
                             " vertices)");
        if (seen[v] == static_cast<int>(f))
          throw InvalidInput(where() + " uses vertex " + std::to_string(v) + " twice");
        seen[v] = static_cast<int>(f);
      }
    }
  }
  for (size_t v = 0; v < vertex_count; ++v)
    if (seen[v] == -1)
      throw InvalidInput("vertex " + std::to_string(v) + " is not used by any face");
}

// Stage: orientation, closedness, manifold vertices; builds the edge list. With `twin_out`,
// also each half-edge's twin (half-edges in traversal order: face, loop, position).
template <class Loops>
std::vector<Edge> check_topology(const Loops& faces, const std::vector<Vec3>& vertices,
                                 std::vector<int>* twin_out = nullptr) {
  const size_t vertex_count = vertices.size();
  // Half-edges h in traversal order (face, loop, position), grouped by their start vertex and
  // sorted by end vertex inside each group (counting sort, then a sort of each small group):
  // finding a directed edge is a binary search among the edges leaving one vertex. Cost
  // O(H log d), d the largest vertex degree; no hashing.
  std::vector<int> from, to, face_of, prev;
  {
    size_t corners = 0;
    for (size_t f = 0; f < faces.size(); ++f)
      for (const auto& loop : faces[f]) corners += loop.size();
    from.reserve(corners);
    to.reserve(corners);
    face_of.reserve(corners);
    prev.reserve(corners);
  }
  for (size_t f = 0; f < faces.size(); ++f)
    for (const auto& loop : faces[f]) {
      const int base = static_cast<int>(from.size()), k = static_cast<int>(loop.size());
      for (int i = 0; i < k; ++i) {
        from.push_back(loop[static_cast<size_t>(i)]);
        to.push_back(loop[static_cast<size_t>((i + 1) % k)]);
        face_of.push_back(static_cast<int>(f));
        prev.push_back(base + (i + k - 1) % k);
      }
    }
  const int h_count = static_cast<int>(from.size());
  std::vector<int> start(vertex_count + 1, 0), order(static_cast<size_t>(h_count));
  for (int h = 0; h < h_count; ++h) ++start[static_cast<size_t>(from[static_cast<size_t>(h)]) + 1];
  for (size_t v = 1; v <= vertex_count; ++v) start[v] += start[v - 1];
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int h = 0; h < h_count; ++h)
      order[static_cast<size_t>(fill[static_cast<size_t>(from[static_cast<size_t>(h)])]++)] = h;
  }
  // By end vertex, then traversal order; vertices in parallel (each group is its own range).
  parallel_blocks(vertex_count, 0, 4096, [&](size_t begin, size_t end) {
    for (size_t v = begin; v != end; ++v)
      std::sort(order.begin() + start[v], order.begin() + start[v + 1], [&](int x, int y) {
        return std::tie(to[static_cast<size_t>(x)], x) < std::tie(to[static_cast<size_t>(y)], y);
      });
  });
  // The first half-edge a → b in traversal order, or −1.
  auto find = [&](int a, int b) {
    auto first = order.begin() + start[static_cast<size_t>(a)];
    auto last = order.begin() + start[static_cast<size_t>(a) + 1];
    auto it = std::lower_bound(first, last, b,
                               [&](int h, int key) { return to[static_cast<size_t>(h)] < key; });
    return it != last && to[static_cast<size_t>(*it)] == b ? *it : -1;
  };

  // Repeated directed edges: every later copy conflicts with the first one.
  std::vector<int> conflicts(faces.size(), 0), sizes(faces.size(), 0);
  for (int h = 0; h < h_count; ++h) ++sizes[static_cast<size_t>(face_of[static_cast<size_t>(h)])];
  int first_conflict = -1, first_owner = -1;
  for (size_t i = 1; i < order.size(); ++i) {
    const int h = order[i], g = order[i - 1];
    if (from[static_cast<size_t>(h)] != from[static_cast<size_t>(g)] ||
        to[static_cast<size_t>(h)] != to[static_cast<size_t>(g)])
      continue;
    const int owner = find(from[static_cast<size_t>(h)], to[static_cast<size_t>(h)]);
    ++conflicts[static_cast<size_t>(face_of[static_cast<size_t>(h)])];
    ++conflicts[static_cast<size_t>(face_of[static_cast<size_t>(owner)])];
    if (first_conflict < 0 || h < first_conflict) {
      first_conflict = h;
      first_owner = owner;
    }
  }
  if (first_conflict >= 0) {
    // A single flipped face conflicts with its neighbours along all its edges.
    int flipped = -1, count = 0;
    for (size_t f = 0; f < faces.size(); ++f)
      if (conflicts[f] == sizes[f]) { flipped = static_cast<int>(f); ++count; }
    if (count == 1)
      throw InvalidInput("inconsistent orientation: face " + str(flipped) +
                         " is flipped (it runs along every edge in the same direction as its "
                         "neighbours)");
    throw InvalidInput("inconsistent orientation or non-manifold edge: faces " +
                       str(face_of[static_cast<size_t>(first_owner)]) + " and " +
                       str(face_of[static_cast<size_t>(first_conflict)]) + " both run along edge " +
                       str(from[static_cast<size_t>(first_conflict)]) + "→" +
                       str(to[static_cast<size_t>(first_conflict)]));
  }

  // Closed: every half-edge has its twin (in parallel, each in its own place).
  std::vector<int> twin(static_cast<size_t>(h_count));
  parallel_blocks(static_cast<size_t>(h_count), 0, 8192, [&](size_t begin, size_t end) {
    for (size_t h = begin; h != end; ++h) twin[h] = find(to[h], from[h]);
  });
  int boundary = 0, bound_a = -1, bound_b = -1;
  for (int h = 0; h < h_count; ++h)
    if (twin[static_cast<size_t>(h)] < 0 && boundary++ == 0) {
      bound_a = from[static_cast<size_t>(h)];
      bound_b = to[static_cast<size_t>(h)];
    }
  if (boundary > 0)
    throw InvalidInput("not closed: " + str(boundary) + " boundary edge" +
                       (boundary > 1 ? "s" : "") + ", first between vertices " + str(bound_a) +
                       " " + vec(vertices[static_cast<size_t>(bound_a)]) + " and " + str(bound_b) +
                       " " + vec(vertices[static_cast<size_t>(bound_b)]));
  // The edges (a < b) sorted by (a, b) as they come: vertex a's half-edges are grouped in
  // `order` by their end vertex, ascending, and no directed edge repeats.
  std::vector<Edge> edges;
  edges.reserve(static_cast<size_t>(h_count) / 2);
  for (const int h : order) {
    const int a = from[static_cast<size_t>(h)], b = to[static_cast<size_t>(h)];
    if (a < b)
      edges.push_back({a, b, face_of[static_cast<size_t>(h)], face_of[static_cast<size_t>(twin[static_cast<size_t>(h)])]});
  }

  // Manifold vertices: the corners around each vertex form one cycle. The corner at the start
  // of half-edge h (v → w, entered by prev(h) = u → v) is followed around v by the corner of
  // the twin of prev(h), v → u.
  // The walk stays at the vertex, so the vertices are counted in parallel (corners of v:
  // the half-edges leaving v, order[start[v] … start[v + 1])).
  std::vector<int> cycles_of(vertex_count, 0);
  std::vector<char> visited(static_cast<size_t>(h_count), 0);
  parallel_blocks(vertex_count, 0, 4096, [&](size_t begin, size_t end) {
    for (size_t v = begin; v != end; ++v)
      for (int i = start[v]; i < start[v + 1]; ++i) {
        const int c = order[static_cast<size_t>(i)];
        if (visited[static_cast<size_t>(c)]) continue;
        ++cycles_of[v];
        int k = c;
        while (!visited[static_cast<size_t>(k)]) {
          visited[static_cast<size_t>(k)] = 1;
          k = twin[static_cast<size_t>(prev[static_cast<size_t>(k)])];
        }
      }
  });
  for (size_t v = 0; v < vertex_count; ++v)
    if (cycles_of[v] > 1)
      throw InvalidInput("non-manifold vertex " + str(static_cast<int>(v)) + ": its faces form " +
                         str(cycles_of[v]) + " separate fans (two parts touching at a point?)");
  if (twin_out) *twin_out = std::move(twin);
  return edges;
}

double body_scale(const std::vector<Vec3>& vertices, const Eigen::AlignedBox3d& box) {
  double m = 0;
  for (const Vec3& p : vertices) m = std::max(m, p.cwiseAbs().maxCoeff());
  return std::max(m, box.diagonal().norm());
}

}  // namespace

void check_polygon_mesh(const std::vector<Vec3>& vertices, const std::vector<Face>& faces) {
  check_vertices(vertices);
  check_faces(FaceLoops{faces}, vertices.size());
  check_topology(FaceLoops{faces}, vertices);
}

std::vector<int> check_polygon_mesh(const std::vector<Vec3>& vertices,
                                    const std::vector<std::vector<int>>& polygons) {
  check_vertices(vertices);
  check_faces(PolygonLoops{polygons}, vertices.size());
  std::vector<int> twin;
  check_topology(PolygonLoops{polygons}, vertices, &twin);
  return twin;
}

Body::Body(std::vector<Vec3> vertices, std::vector<Face> faces, const BodyOptions& options) {
  auto impl = std::make_shared<Impl>();
  // Stage: combinatorial validation.
  check_vertices(vertices);
  check_faces(FaceLoops{faces}, vertices.size());
  impl->edges = check_topology(FaceLoops{faces}, vertices);

  impl->bbox.setEmpty();
  for (const Vec3& p : vertices) impl->bbox.extend(p);
  impl->scale = body_scale(vertices, impl->bbox);
  const double tolerance = options.planarity_tolerance >= 0
                               ? options.planarity_tolerance
                               : kRoundingPlanarity * impl->scale;

  // Stage: per-face geometry: plane, planarity, loops, triangulation.
  const int n = static_cast<int>(faces.size());
  impl->planes.resize(n);
  impl->supports.resize(n);
  impl->face_areas.resize(n);
  impl->matrix.resize(4, n);
  // Faces in parallel, in chunks of a fixed size (each chunk's triangles in its own list,
  // joined in face order); the first failing face of each chunk is kept and the smallest one
  // reported, so the message is the sequential loop's whatever the threads.
  constexpr int kChunk = 2048;
  const int chunks = (n + kChunk - 1) / kChunk;
  std::vector<std::vector<Triangle>> chunk_triangles(static_cast<size_t>(chunks));
  std::vector<std::vector<int>> chunk_off_plane(static_cast<size_t>(chunks));
  std::vector<std::pair<int, std::string>> chunk_error(static_cast<size_t>(chunks), {-1, {}});
  parallel_for(static_cast<size_t>(chunks), 0, [&](size_t chunk) {
    std::vector<Triangle>& out = chunk_triangles[chunk];
    const int chunk_end = std::min(n, static_cast<int>(chunk + 1) * kChunk);
    for (int f = static_cast<int>(chunk) * kChunk; f < chunk_end; ++f) {
      try {
        const Face& face = faces[f];
        // Built only for a message: a string per face cost more than the checks.
        const auto where = [f] { return "face " + str(f); };
        // One loop: exact signs where rounding cannot tell (a sliver triangle read from a file).
        const Vec3 outward = face.loops.size() == 1 ? oriented_normal(vertices, face.loops[0])
                                                    : newell_normal(vertices, face.loops);
        // stableNorm and the unit normal below: the squares of a tiny face's normal (a body of
        // size 1e-100) underflow, those of a huge one overflow; the checks use the unit normal.
        const double length = outward.stableNorm();
        if (!(length > 0) || !std::isfinite(length))
          throw InvalidInput(where() + " has zero area (its vertices are collinear)");
        const Vec3 unit = outward / length;
        std::array<int, 3> s = support_triple(vertices, face.loops[0], unit);
        if (s[2] < 0) throw InvalidInput(where() + " has zero area (its vertices are collinear)");
        if (collinear(vertices[s[0]], vertices[s[1]], vertices[s[2]]))
          throw InvalidInput(where() + " is degenerate (its vertices are collinear)");
        impl->supports[f] = s;
        // Inner normal = −outward; d from the vertex average of the outer loop.
        Vec3 centre = Vec3::Zero();
        for (int v : face.loops[0]) centre += vertices[v];
        centre /= static_cast<double>(face.loops[0].size());
        impl->planes[f] = Plane::through(centre, -unit);
        impl->planes[f].coefficients.array() += 0.0;  // −0 becomes +0: cleaner matrices
        impl->matrix.col(f) = impl->planes[f].coefficients;
        impl->face_areas[f] = length / 2;

        // Planarity: exact first; then within the tolerance.
        const Vec3& a = vertices[s[0]];
        const Vec3& b = vertices[s[1]];
        const Vec3& c = vertices[s[2]];
        bool off_plane = false;
        for (const auto& loop : face.loops)
          for (int v : loop) {
            if (v == s[0] || v == s[1] || v == s[2]) continue;
            if (orient3d(a, b, c, vertices[v]) == Sign::Zero) continue;
            double off = std::abs(impl->planes[f].value(vertices[v]));
            // The fitted plane of a long thin face tilts by about ε · length / width (a fine
            // cylinder's side, 5e-4 wide and 2 long, moved: 7e-14 at its corners where they
            // are 4e-16 off the exact image); the distance from the support triple's plane,
            // computed exactly, is what the corners' rounding makes it.
            if (off > tolerance) off = distance_from_plane(a, b, c, vertices[v]);
            if (off > tolerance)
              throw InvalidInput(where() + " is not planar: vertex " + str(v) + " is " + fmt(off) +
                                 " off its plane (tolerance " + fmt(tolerance) + ")");
            off_plane = true;
          }
        if (off_plane) chunk_off_plane[chunk].push_back(f);
        for (size_t l = 1; l < face.loops.size(); ++l)
          if (newell_normal(vertices, face.loops[l]).dot(unit) >= 0)
            throw InvalidInput(
                where() + ": hole " + str(static_cast<int>(l)) +
                " runs the same way as the outer loop (holes must run the other way)");
        if (newell_normal(vertices, face.loops[0]).dot(unit) <= 0)
          throw InvalidInput(where() + ": its outer loop is smaller than its holes");
        try {
          for (const auto& t : triangulate_polygon(vertices, face.loops, unit))
            out.push_back({t, f});
        } catch (const InvalidInput& e) {
          throw InvalidInput(where() + " is not a simple polygon: " + e.what());
        }
      } catch (const InvalidInput& e) {
        chunk_error[chunk] = {f, e.what()};
        return;
      }
    }
  });
  for (const auto& [face, message] : chunk_error)
    if (face >= 0) throw InvalidInput(message);
  {
    size_t total = 0;
    for (const auto& t : chunk_triangles) total += t.size();
    impl->triangles.reserve(total);
    for (auto& t : chunk_triangles) {
      impl->triangles.insert(impl->triangles.end(), t.begin(), t.end());
      t = {};
    }
    for (const auto& faces_off : chunk_off_plane)
      impl->off_plane.insert(impl->off_plane.end(), faces_off.begin(), faces_off.end());
  }

  // Stage: repeated faces (same vertex set). Faces are sorted by a hash of their sorted vertex
  // set and compared exactly only within equal hashes: O(F log F) on small records.
  {
    auto sorted_ids = [&](int f) {
      std::vector<int> ids;
      for (const auto& loop : faces[f].loops) ids.insert(ids.end(), loop.begin(), loop.end());
      std::sort(ids.begin(), ids.end());
      return ids;
    };
    std::vector<std::pair<std::uint64_t, int>> hashes(static_cast<size_t>(n));
    std::vector<int> ids;
    for (int f = 0; f < n; ++f) {
      ids.clear();
      for (const auto& loop : faces[f].loops) ids.insert(ids.end(), loop.begin(), loop.end());
      std::sort(ids.begin(), ids.end());
      std::uint64_t h = 1469598103934665603ull;
      for (int v : ids) h = (h ^ static_cast<std::uint32_t>(v)) * 1099511628211ull;
      hashes[static_cast<size_t>(f)] = {h, f};
    }
    std::sort(hashes.begin(), hashes.end());
    // The first face (in order) whose vertex set an earlier face has: the old message's pair.
    int repeat = -1, original = -1;
    for (size_t i = 0; i < hashes.size();) {
      size_t j = i;
      while (j < hashes.size() && hashes[j].first == hashes[i].first) ++j;
      for (size_t a = i; a < j; ++a)
        for (size_t b = a + 1; b < j; ++b) {  // faces in ascending order within a hash
          const int fa = hashes[a].second, fb = hashes[b].second;
          if ((repeat < 0 || fb < repeat) && sorted_ids(fa) == sorted_ids(fb)) {
            repeat = fb;
            original = fa;
          }
        }
      i = j;
    }
    if (repeat >= 0) {
      // The earliest face with the repeated face's vertex set.
      for (int f = 0; f < repeat; ++f)
        if (sorted_ids(f) == sorted_ids(repeat)) { original = f; break; }
      throw InvalidInput("faces " + str(original) + " and " + str(repeat) +
                         " have the same vertices (a repeated face)");
    }
  }

  // Stage: volume, area, centroid from the triangles (divergence theorem about the bbox
  // centre, which keeps the products small for bodies far from the origin).
  // The moments are fourth powers of the coordinates: they are summed over coordinates scaled
  // by one power of two (exact) to the unit, so that they neither overflow for a body 1e100
  // across nor underflow for one 1e-100 across.
  const Vec3 o = impl->bbox.center();
  int exponent = 0;
  std::frexp(std::max(impl->bbox.diagonal().maxCoeff(), std::numeric_limits<double>::min()), &exponent);
  const double unit = std::ldexp(1.0, -exponent);
  double volume6 = 0, scaled_volume6 = 0;
  Vec3 moment = Vec3::Zero();
  for (const Triangle& t : impl->triangles) {
    Vec3 a = vertices[t.v[0]] - o, b = vertices[t.v[1]] - o, c = vertices[t.v[2]] - o;
    volume6 += a.dot(b.cross(c));
    a *= unit, b *= unit, c *= unit;
    const double v6 = a.dot(b.cross(c));
    scaled_volume6 += v6;
    moment += v6 * (a + b + c);
  }
  for (double fa : impl->face_areas) impl->area += fa;
  impl->volume = volume6 / 6;

  // Flat bodies: every vertex in the plane of face 0 (exact).
  {
    const auto& s = impl->supports[0];
    bool flat = std::all_of(vertices.begin(), vertices.end(), [&](const Vec3& p) {
      return orient3d(vertices[s[0]], vertices[s[1]], vertices[s[2]], p) == Sign::Zero;
    });
    if (flat) throw InvalidInput("flat body: all vertices lie in one plane (volume is zero)");
  }
  // Not flat, yet no volume at all: every product of three coordinate differences underflowed
  // (a body about 1e-108 across or smaller); saying "oriented inwards" would mislead.
  if (impl->bbox.diagonal().maxCoeff() < 1e-90 &&
      std::abs(impl->volume) < std::numeric_limits<double>::min())
    throw InvalidInput("body too small for double precision: its volume (about the cube of " +
                       fmt(impl->bbox.diagonal().maxCoeff()) +
                       ") underflows; bodies down to about 1e-100 across are accepted");
  if (!(impl->volume > 0))
    throw InvalidInput("faces are oriented inwards (signed volume " + fmt(impl->volume) +
                       "): every face must run counter-clockwise seen from outside");
  impl->centroid = o + std::ldexp(1.0, exponent) * (moment / (4 * scaled_volume6));

  impl->vertices = std::move(vertices);
  impl->faces = std::move(faces);
  impl_ = std::move(impl);
}

const std::vector<Vec3>& Body::vertices() const { return impl_->vertices; }
const std::vector<Face>& Body::faces() const { return impl_->faces; }
const std::vector<Edge>& Body::edges() const { return impl_->edges; }
const Plane& Body::plane(int f) const { return impl_->planes.at(f); }
const BodyMatrix& Body::matrix() const { return impl_->matrix; }
const std::array<int, 3>& Body::support(int f) const { return impl_->supports.at(f); }
const std::vector<Triangle>& Body::triangles() const { return impl_->triangles; }
const std::vector<int>& Body::faces_off_plane() const { return impl_->off_plane; }
bool Body::face_off_plane(int f) const {
  return !impl_->off_plane.empty() && std::binary_search(impl_->off_plane.begin(), impl_->off_plane.end(), f);
}
double Body::volume() const { return impl_->volume; }
double Body::area() const { return impl_->area; }
double Body::face_area(int f) const { return impl_->face_areas.at(f); }
Vec3 Body::centroid() const { return impl_->centroid; }
const Eigen::AlignedBox3d& Body::bbox() const { return impl_->bbox; }
double Body::scale() const { return impl_->scale; }

Sign Body::face_side(int f, const Vec3& p) const {
  const auto& s = support(f);
  const auto& v = impl_->vertices;
  return -orient3d(v[s[0]], v[s[1]], v[s[2]], p);
}

Location Body::classify(const Vec3& p) const {
  const auto& v = impl_->vertices;
  const Eigen::AlignedBox3d& box = impl_->bbox;
  // Outside the closed bounding box: exact comparisons of doubles.
  for (int i = 0; i < 3; ++i)
    if (p[i] < box.min()[i] || p[i] > box.max()[i]) return Location::Outside;
  for (const Triangle& t : impl_->triangles)
    if (on_triangle(p, v[t.v[0]], v[t.v[1]], v[t.v[2]])) return Location::OnBoundary;
  // A two-sided body has no interior: every ray crosses both sides of each face it crosses.
  if (impl_->two_sided) return Location::Outside;

  // Parity of crossings of a segment from p to a far point. Directions from a fixed
  // low-discrepancy sequence, so results are deterministic; a ray that touches an edge, a
  // vertex or a face plane (Degenerate) is abandoned for the next direction.
  const double reach = 4 * (box.diagonal().norm() + (p - box.center()).norm()) + 1;
  for (int attempt = 0; attempt < 64; ++attempt) {
    const double golden = 0.6180339887498949;
    double u = std::fmod(0.1234 + attempt * golden, 1.0);
    double w = std::fmod(0.5678 + attempt * 0.7548776662466927, 1.0);
    double z = 2 * u - 1, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * 3.141592653589793 * w;
    Vec3 q = p + reach * Vec3(r * std::cos(phi), r * std::sin(phi), z);
    int crossings = 0;
    bool degenerate = false;
    for (const Triangle& t : impl_->triangles) {
      SegmentTriangle rel = segment_triangle(p, q, v[t.v[0]], v[t.v[1]], v[t.v[2]]);
      if (rel == SegmentTriangle::Degenerate) { degenerate = true; break; }
      if (rel == SegmentTriangle::Crossing) ++crossings;
    }
    if (!degenerate) return crossings % 2 ? Location::Inside : Location::Outside;
  }
  HEDRA_UNREACHABLE("classify: every ray was degenerate");  // not reachable in practice
}

Body Body::transformed(const Transform& t) const {
  std::vector<Vec3> moved;
  moved.reserve(impl_->vertices.size());
  for (size_t i = 0; i < impl_->vertices.size(); ++i) {
    Vec4 h = t.apply_homogeneous(impl_->vertices[i]);
    if (!(h.w() > 0))
      throw InvalidInput("vertex " + std::to_string(i) +
                         " maps onto or behind the centre of projection (w = " + fmt(h.w()) + ")");
    moved.push_back(h.w() == 1.0 ? Vec3(h.head<3>()) : Vec3(h.head<3>() / h.w()));
  }
  std::vector<Face> faces = impl_->faces;
  // Orientation flips when the map reverses handedness (reflections). For a projective map
  // with w > 0 on the body the sign of det(M) tells the same.
  if (t.matrix().determinant() < 0)
    for (Face& face : faces)
      for (auto& loop : face.loops) std::reverse(loop.begin(), loop.end());
  if (impl_->two_sided && faces.size() > 2) {
    // Rounded coordinates: planar within rounding, as a transformed body's faces.
    Eigen::AlignedBox3d box;
    for (const Vec3& p : moved) box.extend(p);
    std::vector<std::vector<int>> front;
    for (size_t f = 0; f < faces.size() / 2; ++f) front.push_back(faces[f].loops[0]);
    return two_sided_surface(moved, front, kRoundingPlanarity * body_scale(moved, box));
  }
  if (impl_->two_sided) {
    std::vector<Vec3> polygon;
    for (int v : faces[0].loops[0]) polygon.push_back(moved[static_cast<size_t>(v)]);
    // Rounded coordinates: planar within rounding, as a transformed body's faces.
    Eigen::AlignedBox3d box;
    for (const Vec3& p : polygon) box.extend(p);
    const double tolerance = kRoundingPlanarity * body_scale(polygon, box);
    return two_sided_polygon(std::move(polygon), tolerance);
  }
  Body out(std::move(moved), std::move(faces));
  // The exact solid moves with it, exactly, where the map is affine; a body without one whose
  // faces are exactly planar gets its exact image, pending (made when a Boolean needs it).
  if (t.is_affine()) {
    if (impl_->exact)
      internal::attach_exact_solid(out, internal::transformed(*impl_->exact, t));
    else if (std::shared_ptr<const internal::ExactSolid> image = internal::moved_exactly(*this, t))
      internal::attach_exact_solid(out, std::move(image));
  }
  return out;
}

bool Body::two_sided() const { return impl_->two_sided; }

const std::shared_ptr<const internal::ExactSolid>& Body::exact_solid() const { return impl_->exact; }

std::string Body::exact_solid_bytes() const {
  return impl_->exact ? internal::exact_solid_bytes(*impl_->exact) : std::string();
}

Body Body::with_exact_solid_bytes(std::string_view bytes) const {
  if (bytes.empty()) return *this;
  std::shared_ptr<const internal::ExactSolid> solid = internal::exact_solid_from_bytes(bytes, *this);
  // The same geometry with the solid: a copy of the derived data (the solid is part of a
  // body's value, so a shared impl cannot take it).
  const Impl& from = *impl_;
  auto impl = std::make_shared<Impl>();
  impl->vertices = from.vertices;
  impl->faces = from.faces;
  impl->edges = from.edges;
  impl->planes = from.planes;
  impl->supports = from.supports;
  impl->triangles = from.triangles;
  impl->face_areas = from.face_areas;
  impl->off_plane = from.off_plane;
  impl->matrix = from.matrix;
  impl->bbox = from.bbox;
  impl->scale = from.scale;
  impl->volume = from.volume;
  impl->area = from.area;
  impl->centroid = from.centroid;
  impl->two_sided = from.two_sided;
  impl->exact = std::move(solid);
  impl->convexity.store(from.convexity.load(std::memory_order_relaxed), std::memory_order_relaxed);
  return Body(std::shared_ptr<const Impl>(std::move(impl)));
}

namespace internal {
void attach_exact_solid(Body& body, std::shared_ptr<const ExactSolid> solid) {
  HEDRA_ASSERT(body.impl_.use_count() == 1, "attach_exact_solid: the body is shared");
  const_cast<Body::Impl&>(*body.impl_).exact = std::move(solid);
}
}  // namespace internal

int Body::convexity_memo() const { return impl_->convexity.load(std::memory_order_relaxed); }

void Body::set_convexity_memo(bool convex) const {
  impl_->convexity.store(convex ? 1 : 0, std::memory_order_relaxed);
}

Body Body::two_sided_polygon(std::vector<Vec3> polygon, double planarity_tolerance) {
  const int n = static_cast<int>(polygon.size());
  if (n < 3) throw InvalidInput("a two-sided face needs at least 3 vertices, got " + str(n));
  for (int i = 0; i < n; ++i) {
    const Vec3& p = polygon[static_cast<size_t>(i)];
    if (!p.allFinite()) throw InvalidInput("vertex " + str(i) + " has a non-finite coordinate " + vec(p));
    if (p.cwiseAbs().maxCoeff() > kMaxAbsCoordinate)
      throw InvalidInput("vertex " + str(i) + " has a coordinate beyond ±" + fmt(kMaxAbsCoordinate));
  }
  std::vector<int> outer(static_cast<size_t>(n)), inner(static_cast<size_t>(n));
  std::iota(outer.begin(), outer.end(), 0);
  std::reverse_copy(outer.begin(), outer.end(), inner.begin());
  std::array<int, 3> s{};
  Vec3 outward;
  bool off_plane = false;
  if (const std::string why = convex_face_defect(polygon, outer, planarity_tolerance, &s, &outward, &off_plane);
      !why.empty())
    throw InvalidInput("a two-sided face " + why);
  auto impl = std::make_shared<Impl>();
  impl->two_sided = true;
  if (off_plane) impl->off_plane = {0, 1};
  const double length = outward.norm();
  const Vec3 unit = outward / length;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : polygon) centre += p;
  centre /= static_cast<double>(n);
  impl->faces = {Face(outer), Face(inner)};
  impl->planes = {Plane::through(centre, -unit), Plane::through(centre, unit)};
  impl->supports = {s, {s[2], s[1], s[0]}};
  impl->face_areas = {length / 2, length / 2};
  impl->matrix.resize(4, 2);
  for (int f = 0; f < 2; ++f) {
    impl->planes[static_cast<size_t>(f)].coefficients.array() += 0.0;
    impl->matrix.col(f) = impl->planes[static_cast<size_t>(f)].coefficients;
  }
  for (int i = 0; i < n; ++i) impl->edges.push_back({i, (i + 1) % n, 0, 1});
  // Face 0's triangles first, as two_sided_surface() lists its front side's (outline() reads those).
  for (int i = 1; i + 1 < n; ++i) impl->triangles.push_back({{0, i, i + 1}, 0});
  for (int i = 1; i + 1 < n; ++i) impl->triangles.push_back({{0, i + 1, i}, 1});
  impl->bbox.setEmpty();
  for (const Vec3& p : polygon) impl->bbox.extend(p);
  impl->scale = body_scale(polygon, impl->bbox);
  impl->area = length;
  impl->volume = 0;
  impl->centroid = centre;
  impl->vertices = std::move(polygon);
  return Body(std::shared_ptr<const Impl>(std::move(impl)));
}

Body Body::two_sided_surface(const std::vector<Vec3>& vertices, const std::vector<std::vector<int>>& faces,
                             double planarity_tolerance) {
  const int F = static_cast<int>(faces.size());
  if (F == 0) throw InvalidInput("a two-sided surface needs at least one face");
  // Used vertices, renumbered in their order (bbox, scale and vertices() see only these).
  std::vector<int> renumber(vertices.size(), -1);
  std::vector<Vec3> used;
  std::vector<std::vector<int>> loops(faces.size());
  for (int f = 0; f < F; ++f) {
    const auto& face = faces[static_cast<size_t>(f)];
    for (int v : face) {
      if (v < 0 || static_cast<size_t>(v) >= vertices.size())
        throw InvalidInput("face " + str(f) + " refers to vertex " + str(v) + ", out of range (the surface has " +
                           str(static_cast<int>(vertices.size())) + " vertices)");
      int& r = renumber[static_cast<size_t>(v)];
      if (r < 0) {
        const Vec3& p = vertices[static_cast<size_t>(v)];
        if (!p.allFinite()) throw InvalidInput("vertex " + str(v) + " has a non-finite coordinate " + vec(p));
        if (p.cwiseAbs().maxCoeff() > kMaxAbsCoordinate)
          throw InvalidInput("vertex " + str(v) + " has a coordinate beyond ±" + fmt(kMaxAbsCoordinate));
        r = static_cast<int>(used.size());
        used.push_back(p);
      }
      loops[static_cast<size_t>(f)].push_back(r);
    }
  }
  auto impl = std::make_shared<Impl>();
  impl->two_sided = true;
  impl->faces.resize(2 * static_cast<size_t>(F));
  impl->planes.resize(2 * static_cast<size_t>(F));
  impl->supports.resize(2 * static_cast<size_t>(F));
  impl->face_areas.resize(2 * static_cast<size_t>(F));
  impl->matrix.resize(4, 2 * F);
  // Per face: exact test, plane, support; in parallel chunks (a million faces).
  std::vector<std::string> defect(static_cast<size_t>(F));
  std::vector<char> off_plane(static_cast<size_t>(F));
  std::vector<Vec3> centroid_part(static_cast<size_t>(F));
  parallel_chunks(static_cast<size_t>(F), 8192, [&](size_t, size_t begin, size_t end) {
    for (size_t f = begin; f != end; ++f) {
      const std::vector<int>& loop = loops[f];
      std::array<int, 3> s{};
      Vec3 outward;
      bool off = false;
      defect[f] = convex_face_defect(used, loop, planarity_tolerance, &s, &outward, &off);
      off_plane[f] = off;
      if (!defect[f].empty()) continue;
      const double length = outward.norm();
      const Vec3 unit = outward / length;
      Vec3 centre = Vec3::Zero();
      for (int v : loop) centre += used[static_cast<size_t>(v)];
      centre /= static_cast<double>(loop.size());
      const size_t g = f + static_cast<size_t>(F);
      impl->faces[f] = Face(loop);
      impl->faces[g] = Face(std::vector<int>(loop.rbegin(), loop.rend()));
      impl->planes[f] = Plane::through(centre, -unit);
      impl->planes[g] = Plane::through(centre, unit);
      impl->supports[f] = s;
      impl->supports[g] = {s[2], s[1], s[0]};
      impl->face_areas[f] = impl->face_areas[g] = length / 2;
      impl->matrix.col(static_cast<Eigen::Index>(f)) = impl->planes[f].coefficients;
      impl->matrix.col(static_cast<Eigen::Index>(g)) = impl->planes[g].coefficients;
      centroid_part[f] = centre * length;
    }
  });
  for (int f = 0; f < F; ++f)
    if (!defect[static_cast<size_t>(f)].empty()) throw InvalidInput("face " + str(f) + " " + defect[static_cast<size_t>(f)]);
  // Faces off their planes: each side (face f and its other side f + F), ascending.
  for (int side = 0; side < 2; ++side)
    for (int f = 0; f < F; ++f)
      if (off_plane[static_cast<size_t>(f)]) impl->off_plane.push_back(f + side * F);
  // Edges: each directed edge of a face at most once; a pair a → b, b → a is an interior edge
  // (once on each side), an unpaired one a boundary edge joining a face to its other side.
  // Grouped by the smaller end (a counting sort), each group sorted by (other end, from,
  // face): the order of a sort of all of them, without one (a million faces).
  struct Directed {
    int hi, from, face;
    bool operator<(const Directed& o) const { return std::tie(hi, from, face) < std::tie(o.hi, o.from, o.face); }
  };
  const size_t nv = used.size();
  std::vector<int> start(nv + 1, 0);
  for (const auto& loop : loops)
    for (size_t i = 0; i < loop.size(); ++i) ++start[static_cast<size_t>(std::min(loop[i], loop[(i + 1) % loop.size()])) + 1];
  for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<Directed> directed(static_cast<size_t>(start.back()));
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int f = 0; f < F; ++f) {
      const auto& loop = loops[static_cast<size_t>(f)];
      for (size_t i = 0; i < loop.size(); ++i) {
        const int a = loop[i], b = loop[(i + 1) % loop.size()];
        directed[static_cast<size_t>(fill[static_cast<size_t>(std::min(a, b))]++)] = {std::max(a, b), a, f};
      }
    }
  }
  std::vector<Edge> back_copies;
  impl->edges.reserve(directed.size());
  for (size_t lo = 0; lo < nv; ++lo) {
    const auto first = directed.begin() + start[lo], last = directed.begin() + start[lo + 1];
    std::sort(first, last);
    for (auto it = first; it != last;) {
      auto next = it + 1;
      while (next != last && next->hi == it->hi) ++next;
      const Directed& d = *it;
      const int to = d.from == static_cast<int>(lo) ? d.hi : static_cast<int>(lo);
      if (next - it > 2 || (next - it == 2 && (it + 1)->from == d.from))
        throw InvalidInput("edge " + str(d.from) + "-" + str(to) + " is used twice in one direction or by more than two faces");
      if (next - it == 1) {
        impl->edges.push_back({d.from, to, d.face, d.face + F});
      } else {
        const Directed& e = *(it + 1);  // runs to → from
        impl->edges.push_back({d.from, to, d.face, e.face});
        back_copies.push_back({d.from, to, e.face + F, d.face + F});
      }
      it = next;
    }
  }
  impl->edges.insert(impl->edges.end(), back_copies.begin(), back_copies.end());
  // Triangles: each face's fan, every front face's first (outline() reads only those).
  for (int side = 0; side < 2; ++side)
    for (int f = 0; f < F; ++f) {
      const auto& loop = loops[static_cast<size_t>(f)];
      for (size_t i = 1; i + 1 < loop.size(); ++i) {
        if (side == 0) impl->triangles.push_back({{loop[0], loop[i], loop[i + 1]}, f});
        else impl->triangles.push_back({{loop[0], loop[i + 1], loop[i]}, f + F});
      }
    }
  impl->bbox.setEmpty();
  for (const Vec3& p : used) impl->bbox.extend(p);
  impl->scale = body_scale(used, impl->bbox);
  double area = 0;
  Vec3 centroid = Vec3::Zero();
  for (int f = 0; f < F; ++f) {
    area += impl->face_areas[static_cast<size_t>(f)];
    centroid += centroid_part[static_cast<size_t>(f)];
  }
  impl->area = 2 * area;
  impl->volume = 0;
  impl->centroid = area > 0 ? Vec3(centroid / (2 * area)) : impl->bbox.center();
  impl->vertices = std::move(used);
  return Body(std::shared_ptr<const Impl>(std::move(impl)));
}

int Body::twin_face(int f) const {
  const int half = face_count() / 2;
  return f < half ? f + half : f - half;
}

BodyMatrix sign_by_interior_point(BodyMatrix planes, const Vec3& s) {
  for (Eigen::Index j = 0; j < planes.cols(); ++j)
    if (s.homogeneous().dot(planes.col(j)) < 0) planes.col(j) *= -1;
  return planes;
}

}  // namespace hedra
