#include "hedra/mesh/open_surface.h"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "hedra/core/error.h"
#include "hedra/core/face_geometry.h"
#include "hedra/core/triangulate.h"

namespace hedra {
namespace {

using Loop = std::vector<int>;

std::pair<int, int> key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

std::vector<Vec3> points(const PolygonSoup& soup, const Loop& loop) {
  std::vector<Vec3> out;
  for (int v : loop) out.push_back(soup.vertices[static_cast<size_t>(v)]);
  return out;
}

// The two-sided face of a loop, or none when it is not exactly planar and strictly convex.
std::optional<Body> convex_face(const PolygonSoup& soup, const Loop& loop) {
  try {
    return Body::two_sided_polygon(points(soup, loop));
  } catch (const InvalidInput&) {
    return std::nullopt;
  }
}

// The loop of P ∪ Q across their shared edge a → b of P (b → a of Q): P from b round to a,
// then Q's vertices strictly between a and b. Empty when Q does not run b → a.
Loop joined(const Loop& p, const Loop& q, int a, int b) {
  const auto ia = std::find(q.begin(), q.end(), a) - q.begin();
  const auto n = static_cast<long>(q.size());
  if (ia == n || q[static_cast<size_t>((ia + n - 1) % n)] != b) return {};
  const auto ib = std::find(p.begin(), p.end(), b) - p.begin();
  const auto m = static_cast<long>(p.size());
  Loop out;
  for (long k = 0; k < m; ++k) out.push_back(p[static_cast<size_t>((ib + k) % m)]);  // b … a
  for (long k = 1; k + 1 < n; ++k) out.push_back(q[static_cast<size_t>((ia + k) % n)]);
  return out;
}

}  // namespace

SurfaceBoundary surface_boundary(const PolygonSoup& soup) {
  std::set<std::pair<int, int>> directed, undirected;
  for (const auto& poly : soup.polygons)
    for (size_t i = 0; i < poly.size(); ++i) {
      const int a = poly[i], b = poly[(i + 1) % poly.size()];
      directed.emplace(a, b);
      undirected.insert(key(a, b));
    }
  SurfaceBoundary out;
  out.edges = static_cast<int>(undirected.size());
  for (const auto& poly : soup.polygons)
    for (size_t i = 0; i < poly.size(); ++i) {
      const int a = poly[i], b = poly[(i + 1) % poly.size()];
      if (directed.count({b, a})) continue;
      if (out.boundary_edges++ == 0) out.first_from = a, out.first_to = b;
    }
  return out;
}

bool is_open_surface(const PolygonSoup& soup) {
  std::set<std::pair<int, int>> directed;
  for (const auto& poly : soup.polygons)
    for (size_t i = 0; i < poly.size(); ++i) {
      const int a = poly[i], b = poly[(i + 1) % poly.size()];
      if (a < 0 || b < 0 || static_cast<size_t>(std::max(a, b)) >= soup.vertices.size()) return false;
      if (!directed.emplace(a, b).second) return false;
    }
  return !directed.empty() && surface_boundary(soup).boundary_edges > 0;
}

SurfaceSummary summarize_surface(const PolygonSoup& soup) {
  SurfaceSummary out;
  out.boundary = surface_boundary(soup);
  out.edges = out.boundary.edges;
  out.faces = static_cast<int>(soup.polygons.size());
  std::set<int> used;
  for (const auto& poly : soup.polygons) {
    used.insert(poly.begin(), poly.end());
    Vec3 n = Vec3::Zero();  // Newell's area vector
    for (size_t i = 0; i < poly.size(); ++i)
      n += soup.vertices[static_cast<size_t>(poly[i])].cross(
          soup.vertices[static_cast<size_t>(poly[(i + 1) % poly.size()])]);
    out.area += n.norm() / 2;
  }
  out.vertices = static_cast<int>(used.size());
  return out;
}

std::vector<Body> two_sided_faces(const PolygonSoup& soup) {
  // Stage: convex loops, each polygon whole or as its triangles.
  std::vector<Loop> loops;
  for (size_t f = 0; f < soup.polygons.size(); ++f) {
    Loop loop;
    for (int v : soup.polygons[f])
      if (loop.empty() || soup.vertices[static_cast<size_t>(v)] != soup.vertices[static_cast<size_t>(loop.back())])
        loop.push_back(v);
    while (loop.size() > 1 && soup.vertices[static_cast<size_t>(loop.front())] == soup.vertices[static_cast<size_t>(loop.back())])
      loop.pop_back();
    if (loop.size() < 3) continue;
    if (convex_face(soup, loop)) {
      loops.push_back(loop);
      continue;
    }
    const Vec3 normal = newell_normal(soup.vertices, loop);
    if (!(normal.norm() > 0)) continue;  // no area
    std::vector<std::array<int, 3>> triangles;
    try {
      triangles = triangulate_polygon(soup.vertices, {loop}, normal);
    } catch (const InvalidInput& e) {
      throw InvalidInput("face " + std::to_string(f) + " is not a simple polygon: " + e.what());
    }
    for (const auto& t : triangles)
      if (convex_face(soup, {t[0], t[1], t[2]})) loops.push_back({t[0], t[1], t[2]});
  }
  // Stage: merge exactly coplanar neighbours while the union stays strictly convex (greedy,
  // in soup order: deterministic).
  std::map<std::pair<int, int>, std::vector<int>> by_edge;
  for (size_t i = 0; i < loops.size(); ++i)
    for (size_t k = 0; k < loops[i].size(); ++k)
      by_edge[key(loops[i][k], loops[i][(k + 1) % loops[i].size()])].push_back(static_cast<int>(i));
  std::vector<bool> alive(loops.size(), true);
  for (size_t i = 0; i < loops.size(); ++i) {
    if (!alive[i]) continue;
    bool merged = true;
    while (merged) {
      merged = false;
      const Loop& p = loops[i];
      for (size_t k = 0; k < p.size() && !merged; ++k) {
        const int a = p[k], b = p[(k + 1) % p.size()];
        for (int j : by_edge[key(a, b)]) {
          if (j == static_cast<int>(i) || !alive[static_cast<size_t>(j)]) continue;
          Loop u = joined(p, loops[static_cast<size_t>(j)], a, b);
          if (u.empty() || !convex_face(soup, u)) continue;
          for (size_t m = 0; m < loops[static_cast<size_t>(j)].size(); ++m) {
            const Loop& q = loops[static_cast<size_t>(j)];
            by_edge[key(q[m], q[(m + 1) % q.size()])].push_back(static_cast<int>(i));
          }
          alive[static_cast<size_t>(j)] = false;
          loops[i] = std::move(u);
          merged = true;
          break;
        }
      }
    }
  }
  std::vector<Body> out;
  for (size_t i = 0; i < loops.size(); ++i)
    if (alive[i]) out.push_back(*convex_face(soup, loops[i]));
  if (out.empty()) throw InvalidInput("the surface has no face of non-zero area");
  return out;
}

}  // namespace hedra
