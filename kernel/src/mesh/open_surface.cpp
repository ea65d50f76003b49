#include "hedra/mesh/open_surface.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include "hedra/core/error.h"
#include "hedra/core/face_geometry.h"
#include "hedra/core/predicates.h"
#include "hedra/core/tolerance.h"
#include "hedra/core/triangulate.h"

namespace hedra {
namespace {

using Loop = std::vector<int>;

std::pair<int, int> key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// Whether a loop is a two-sided face: planar (exactly, or within `planarity` when positive)
// and strictly convex (Body::two_sided_polygon's test, without building the body).
bool convex_face_of(const std::vector<Vec3>& vertices, const Loop& loop, double planarity) {
  return convex_face_defect(vertices, loop, planarity).empty();
}

// Whether every corner of q lies exactly on the plane of p's first three corners (not collinear:
// p is a strictly convex loop). Cost O(|q|).
bool coplanar_loops(const std::vector<Vec3>& v, const Loop& p, const Loop& q) {
  const Vec3 &a = v[static_cast<size_t>(p[0])], &b = v[static_cast<size_t>(p[1])], &c = v[static_cast<size_t>(p[2])];
  for (int x : q)
    if (orient3d(a, b, c, v[static_cast<size_t>(x)]) != Sign::Zero) return false;
  return true;
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

namespace {

// The soup's directed edges grouped by their first vertex (a counting sort: O(V + E), no
// comparisons; a million-face surface spent a third of its loading sorting edge pairs):
// the ends of the edges from vertex a are to[start[a] … start[a + 1]).
struct DirectedEdges {
  std::vector<int> start, to;
  explicit DirectedEdges(const PolygonSoup& soup) : start(soup.vertices.size() + 1, 0) {
    for (const auto& poly : soup.polygons)
      for (int v : poly) ++start[static_cast<size_t>(v) + 1];
    for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
    to.resize(static_cast<size_t>(start.back()));
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (const auto& poly : soup.polygons)
      for (size_t i = 0; i < poly.size(); ++i)
        to[static_cast<size_t>(fill[static_cast<size_t>(poly[i])]++)] = poly[(i + 1) % poly.size()];
    // Each list sorted: a vertex of high degree (a fan's apex) costs O(d log d), not O(d²).
    for (size_t a = 0; a + 1 < start.size(); ++a) std::sort(to.begin() + start[a], to.begin() + start[a + 1]);
  }
  bool has(int a, int b) const {
    return std::binary_search(to.begin() + start[static_cast<size_t>(a)], to.begin() + start[static_cast<size_t>(a) + 1], b);
  }
  // Whether some edge a → b is listed twice.
  bool repeated() const {
    for (size_t a = 0; a + 1 < start.size(); ++a)
      if (std::adjacent_find(to.begin() + start[a], to.begin() + start[a + 1]) != to.begin() + start[a + 1]) return true;
    return false;
  }
};

SurfaceBoundary boundary_of(const PolygonSoup& soup, const DirectedEdges& directed) {
  SurfaceBoundary out;
  // Undirected edges: each counted from its first directed copy from the smaller end, or from
  // the larger end when there is none from the smaller.
  for (size_t a = 0; a + 1 < directed.start.size(); ++a)
    for (int i = directed.start[a]; i < directed.start[a + 1]; ++i) {
      const int b = directed.to[static_cast<size_t>(i)];
      const bool first = i == directed.start[a] || directed.to[static_cast<size_t>(i) - 1] != b;  // sorted
      if (first && (static_cast<int>(a) <= b || !directed.has(b, static_cast<int>(a)))) ++out.edges;
    }
  // In soup order, so that the first boundary edge is the file's first.
  for (const auto& poly : soup.polygons)
    for (size_t i = 0; i < poly.size(); ++i) {
      const int a = poly[i], b = poly[(i + 1) % poly.size()];
      if (directed.has(b, a)) continue;
      if (out.boundary_edges++ == 0) out.first_from = a, out.first_to = b;
    }
  return out;
}

}  // namespace

SurfaceBoundary surface_boundary(const PolygonSoup& soup) { return boundary_of(soup, DirectedEdges(soup)); }

bool is_open_surface(const PolygonSoup& soup) {
  for (const auto& poly : soup.polygons)
    for (int v : poly)
      if (v < 0 || static_cast<size_t>(v) >= soup.vertices.size()) return false;
  const DirectedEdges directed(soup);
  if (directed.to.empty() || directed.repeated()) return false;
  for (const auto& poly : soup.polygons)
    for (size_t i = 0; i < poly.size(); ++i)
      if (!directed.has(poly[(i + 1) % poly.size()], poly[i])) return true;
  return false;
}

SurfaceSummary summarize_surface(const PolygonSoup& soup) {
  SurfaceSummary out;
  out.boundary = surface_boundary(soup);
  out.edges = out.boundary.edges;
  out.faces = static_cast<int>(soup.polygons.size());
  std::vector<char> used(soup.vertices.size(), 0);
  for (const auto& poly : soup.polygons) {
    for (int v : poly) used[static_cast<size_t>(v)] = 1;
    Vec3 n = Vec3::Zero();  // Newell's area vector
    for (size_t i = 0; i < poly.size(); ++i)
      n += soup.vertices[static_cast<size_t>(poly[i])].cross(
          soup.vertices[static_cast<size_t>(poly[(i + 1) % poly.size()])]);
    out.area += n.norm() / 2;
  }
  out.vertices = static_cast<int>(std::count(used.begin(), used.end(), 1));
  return out;
}

namespace {

// The convex faces of an open surface (two_sided_faces): loops of indices into `vertices`,
// each planar within `planarity` (0: exactly) and strictly convex.
struct ConvexLoops {
  std::vector<Vec3> vertices;
  std::vector<Loop> loops;
  double planarity = 0;
};

// The convex loops of polygons of `soup` (see two_sided_faces), planar exactly or, when
// `planarity` is positive, within it.
ConvexLoops faces_of_loops(const PolygonSoup& soup, double planarity) {
  const auto convex_face = [&](const PolygonSoup& s, const Loop& loop) {
    return convex_face_of(s.vertices, loop, planarity);
  };
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
  // Stage: merge coplanar neighbours (exactly, or within `planarity`) while the union stays
  // strictly convex (greedy, in soup order: deterministic).
  // The loops at each undirected edge {a < b}, listed under a (a counting sort: O(n), and a
  // lookup reads one short list, where a sorted table's binary searches took a fifth of the
  // loading of a million triangles); a loop merged into another resolves to it (union-find),
  // so the lists never change.
  const size_t nv = soup.vertices.size();
  std::vector<int> start(nv + 1, 0);
  for (const Loop& l : loops)
    for (size_t k = 0; k < l.size(); ++k) ++start[static_cast<size_t>(std::min(l[k], l[(k + 1) % l.size()])) + 1];
  for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<std::pair<int, int>> at_edge(static_cast<size_t>(start.back()));  // (b, loop)
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (size_t i = 0; i < loops.size(); ++i)
      for (size_t k = 0; k < loops[i].size(); ++k) {
        const auto [a, b] = key(loops[i][k], loops[i][(k + 1) % loops[i].size()]);
        at_edge[static_cast<size_t>(fill[static_cast<size_t>(a)]++)] = {b, static_cast<int>(i)};
      }
    // Each list sorted (a fan's apex: O(d log d), not O(d²) lookups).
    for (size_t a = 0; a < nv; ++a) std::sort(at_edge.begin() + start[a], at_edge.begin() + start[a + 1]);
  }
  std::vector<int> into(loops.size());
  std::iota(into.begin(), into.end(), 0);
  const auto root = [&](int j) {
    while (into[static_cast<size_t>(j)] != j) j = into[static_cast<size_t>(j)] = into[static_cast<size_t>(into[static_cast<size_t>(j)])];
    return j;
  };
  std::vector<bool> alive(loops.size(), true);
  for (size_t i = 0; i < loops.size(); ++i) {
    if (!alive[i]) continue;
    bool merged = true;
    while (merged) {
      merged = false;
      const Loop& p = loops[i];
      for (size_t k = 0; k < p.size() && !merged; ++k) {
        const int a = p[k], b = p[(k + 1) % p.size()];
        const auto [lo, hi] = key(a, b);
        const auto first = at_edge.begin() + start[static_cast<size_t>(lo)], last = at_edge.begin() + start[static_cast<size_t>(lo) + 1];
        for (auto it = std::lower_bound(first, last, std::make_pair(hi, -1)); it != last && it->first == hi && !merged; ++it) {
          const int j = root(it->second);
          if (j == static_cast<int>(i) || !alive[static_cast<size_t>(j)]) continue;
          // Exactly: a neighbour off p's plane (the first three corners of a strictly convex
          // loop are not collinear) cannot merge; settled without building the union (whose
          // refusal is an exception: a curved surface of 80 000 triangles spent a second in them).
          if (planarity == 0 && !coplanar_loops(soup.vertices, p, loops[static_cast<size_t>(j)])) continue;
          Loop u = joined(p, loops[static_cast<size_t>(j)], a, b);
          if (u.empty() || !convex_face(soup, u)) continue;
          into[static_cast<size_t>(j)] = static_cast<int>(i);
          alive[static_cast<size_t>(j)] = false;
          loops[i] = std::move(u);
          merged = true;
        }
      }
    }
  }
  ConvexLoops out;
  out.vertices = soup.vertices;
  out.planarity = planarity;
  for (size_t i = 0; i < loops.size(); ++i)
    if (alive[i]) out.loops.push_back(std::move(loops[i]));
  if (out.loops.empty()) throw InvalidInput("the surface has no face of non-zero area");
  return out;
}

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double dd = d.squaredNorm();
  const double t = dd > 0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

// `--tolerance D` on an open surface (see two_sided_faces). Throws InvalidInput where the
// snapped surface gives no valid faces; the caller then takes the exact faces.
ConvexLoops snapped_faces(const PolygonSoup& soup, double tolerance) {
  // Polygons without repeated consecutive points; those of fewer than 3 or of zero area are
  // left out, as the exact faces leave them out.
  PolygonSoup clean;
  clean.vertices = soup.vertices;
  const auto& v = soup.vertices;
  for (const auto& poly : soup.polygons) {
    Loop loop;
    for (int w : poly)
      if (loop.empty() || v[static_cast<size_t>(w)] != v[static_cast<size_t>(loop.back())]) loop.push_back(w);
    while (loop.size() > 1 && v[static_cast<size_t>(loop.front())] == v[static_cast<size_t>(loop.back())])
      loop.pop_back();
    if (loop.size() < 3) continue;
    const Vec3 normal = newell_normal(v, loop);
    if (!(normal.norm() > 0)) continue;
    const std::array<int, 3> t = support_triple(v, loop, normal);
    if (t[2] < 0 || collinear(v[static_cast<size_t>(t[0])], v[static_cast<size_t>(t[1])], v[static_cast<size_t>(t[2])]))
      continue;
    clean.polygons.push_back(std::move(loop));
  }
  const SnappedSurface snapped = snap_surface(clean, tolerance);
  const std::vector<Vec3>& mv = snapped.vertices;
  const auto& polys = clean.polygons;
  const int n = static_cast<int>(polys.size());
  int regions = 0;
  for (int r : snapped.region) regions = std::max(regions, r + 1);
  std::vector<std::vector<int>> members(static_cast<size_t>(regions));
  for (int p = 0; p < n; ++p) members[static_cast<size_t>(snapped.region[static_cast<size_t>(p)])].push_back(p);
  // Per vertex: the regions using it (the first two; `many` for three or more) and whether
  // it is on the surface's boundary; per directed edge, its polygon.
  std::vector<int> first(v.size(), -1), second(v.size(), -1);
  std::vector<char> many(v.size(), 0), on_boundary(v.size(), 0);
  std::map<std::pair<int, int>, int> owner;
  for (int p = 0; p < n; ++p) {
    const auto& poly = polys[static_cast<size_t>(p)];
    const int r = snapped.region[static_cast<size_t>(p)];
    for (size_t i = 0; i < poly.size(); ++i) {
      const auto w = static_cast<size_t>(poly[i]);
      if (first[w] < 0) first[w] = r;
      else if (first[w] != r && second[w] < 0) second[w] = r;
      else if (first[w] != r && second[w] != r) many[w] = 1;
      owner[{poly[i], poly[(i + 1) % poly.size()]}] = p;
    }
  }
  for (const auto& [edge, p] : owner)
    if (!owner.count({edge.second, edge.first}))
      on_boundary[static_cast<size_t>(edge.first)] = on_boundary[static_cast<size_t>(edge.second)] = 1;
  // Each region's boundary, when it is one simple loop (in the polygons' orientation).
  std::vector<Loop> loop_of(static_cast<size_t>(regions));
  for (int r = 0; r < regions; ++r) {
    std::map<int, int> next;
    std::vector<int> starts;
    bool pinched = false;
    for (int p : members[static_cast<size_t>(r)]) {
      const auto& poly = polys[static_cast<size_t>(p)];
      for (size_t i = 0; i < poly.size(); ++i) {
        const int a = poly[i], b = poly[(i + 1) % poly.size()];
        const auto twin = owner.find({b, a});
        if (twin != owner.end() && snapped.region[static_cast<size_t>(twin->second)] == r) continue;
        pinched = pinched || !next.emplace(a, b).second;
        starts.push_back(a);
      }
    }
    if (pinched || starts.empty()) continue;
    Loop loop;
    int a = starts[0];
    do {
      loop.push_back(a);
      const auto it = next.find(a);
      if (it == next.end()) break;
      a = it->second;
    } while (a != starts[0] && loop.size() <= next.size());
    if (a == starts[0] && loop.size() == next.size() && loop.size() >= 3)  // one loop: no holes
      loop_of[static_cast<size_t>(r)] = std::move(loop);
  }
  // Which vertices of region r's loop may be left out, by the run they belong to: `r` for one
  // used by r only (on the surface's boundary), `other` for one on a crease shared with one
  // other region whose boundary is one loop too (then both loops leave it out, the same way),
  // −1 for one that stays.
  const auto run_class = [&](int w, int r) {
    const auto u = static_cast<size_t>(w);
    if (many[u]) return -1;
    if (second[u] < 0) return first[u] == r ? r : -1;
    if (on_boundary[u]) return -1;
    const int other = first[u] == r ? second[u] : first[u];
    return loop_of[static_cast<size_t>(other)].empty() ? -1 : other;
  };
  // Greedy along seq = a, x1 … xk, b: x_t is left out when it and the x's left out since the
  // last vertex kept lie within D (input positions) of the chord from that vertex to the next
  // (snapped positions). Returns the x's kept.
  const auto simplify = [&](const std::vector<int>& seq) {
    std::vector<int> kept;
    size_t anchor = 0;
    for (size_t t = 1; t + 1 < seq.size(); ++t) {
      const Vec3& from = mv[static_cast<size_t>(seq[anchor])];
      const Vec3& to = mv[static_cast<size_t>(seq[t + 1])];
      bool drop = true;
      for (size_t j = anchor + 1; j <= t && drop; ++j)
        drop = distance_to_segment(v[static_cast<size_t>(seq[j])], from, to) <= tolerance;
      if (drop) continue;
      kept.push_back(seq[t]);
      anchor = t;
    }
    return kept;
  };
  PolygonSoup merged;
  merged.vertices = mv;
  for (int r = 0; r < regions; ++r) {
    Loop loop = loop_of[static_cast<size_t>(r)];
    if (loop.empty()) {  // not one loop: the region's polygons, snapped
      for (int p : members[static_cast<size_t>(r)]) merged.polygons.push_back(polys[static_cast<size_t>(p)]);
      continue;
    }
    // Start at a vertex that stays; with none (the region is a whole component, its loop on
    // the surface's boundary), at the vertex farthest from the loop's centre.
    const size_t m = loop.size();
    size_t start = m;
    for (size_t k = 0; k < m && start == m; ++k)
      if (run_class(loop[k], r) < 0) start = k;
    if (start == m) {
      Vec3 centre = Vec3::Zero();
      for (int w : loop) centre += mv[static_cast<size_t>(w)];
      centre /= static_cast<double>(m);
      double far = -1;
      for (size_t k = 0; k < m; ++k)
        if (const double d = (mv[static_cast<size_t>(loop[k])] - centre).norm(); d > far) far = d, start = k;
    }
    std::rotate(loop.begin(), loop.begin() + static_cast<long>(start), loop.end());
    Loop kept{loop[0]};
    for (size_t i = 0; i < m;) {
      // The run after loop[i]: vertices of one class up to the next vertex that stays.
      size_t j = i + 1;
      const int cls = j < m ? run_class(loop[j], r) : -1;
      while (j < m && run_class(loop[j], r) >= 0 && run_class(loop[j], r) == cls) ++j;
      std::vector<int> seq(loop.begin() + static_cast<long>(i), loop.begin() + static_cast<long>(j));
      seq.push_back(loop[j % m]);
      std::vector<int> stay;
      if (seq.size() > 2 && cls == r) {
        stay = simplify(seq);
      } else if (seq.size() > 2 && seq.front() != seq.back()) {
        // A crease: simplified from its end of smaller number, so that the loop of the region
        // on its other side, which runs it the other way, leaves out the same vertices.
        const bool flip = seq.front() > seq.back();
        if (flip) std::reverse(seq.begin(), seq.end());
        stay = simplify(seq);
        if (flip) std::reverse(stay.begin(), stay.end());
      } else {
        stay.assign(seq.begin() + 1, seq.end() - 1);
      }
      kept.insert(kept.end(), stay.begin(), stay.end());
      if (j < m) kept.push_back(loop[j]);
      i = j;
    }
    // Too few corners left (a sliver within D): the exact faces instead (the caller).
    if (kept.size() < 3) throw InvalidInput("a merged region collapses");
    merged.polygons.push_back(std::move(kept));
  }
  // Merged faces are planar within the rounding of the snapped coordinates, as the faces of a
  // body read with --tolerance are (BodyOptions).
  Eigen::AlignedBox3d box;
  double largest = 0;
  for (const Vec3& p : mv) {
    box.extend(p);
    largest = std::max(largest, p.cwiseAbs().maxCoeff());
  }
  return faces_of_loops(merged, kRoundingPlanarity * std::max(largest, box.diagonal().norm()));
}

}  // namespace

namespace {

ConvexLoops convex_loops(const PolygonSoup& soup, double tolerance) {
  if (tolerance > 0) {
    try {
      return snapped_faces(soup, tolerance);
    } catch (const InvalidInput&) {
      // As for closed meshes (MergeOptions): where snapping gives no valid faces, the surface
      // is taken exactly.
    }
  }
  return faces_of_loops(soup, 0);
}

}  // namespace

std::vector<Body> two_sided_faces(const PolygonSoup& soup, double tolerance) {
  const ConvexLoops faces = convex_loops(soup, tolerance);
  std::vector<Body> out;
  out.reserve(faces.loops.size());
  for (const Loop& loop : faces.loops) {
    std::vector<Vec3> corners;
    for (int v : loop) corners.push_back(faces.vertices[static_cast<size_t>(v)]);
    out.push_back(Body::two_sided_polygon(std::move(corners), faces.planarity));
  }
  return out;
}

Body two_sided_surface(const PolygonSoup& soup, double tolerance) {
  // Vertices of equal coordinates are one (a soup need not share them: its faces then meet
  // along edges all the same, and exactly coplanar neighbours merge across them).
  const size_t n = soup.vertices.size();
  const auto& v = soup.vertices;
  // Not joined when a coordinate is not finite (no order to sort by): the body names the vertex.
  const bool finite = std::all_of(v.begin(), v.end(), [](const Vec3& p) { return p.allFinite(); });
  std::vector<int> order(finite ? n : 0);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const Vec3 &p = v[static_cast<size_t>(a)], &q = v[static_cast<size_t>(b)];
    return std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3) || (p == q && a < b);
  });
  std::vector<int> first(n);
  bool any = false;
  for (size_t k = 0; k < order.size(); ++k) {
    const auto i = static_cast<size_t>(order[k]);
    const bool same = k > 0 && v[static_cast<size_t>(order[k - 1])] == v[i];
    first[i] = same ? first[static_cast<size_t>(order[k - 1])] : order[k];
    any = any || same;
  }
  const auto surface_of = [&](const PolygonSoup& s) {
    const ConvexLoops faces = convex_loops(s, tolerance);
    if (tolerance > 0 && faces.planarity > 0) {
      try {
        return Body::two_sided_surface(faces.vertices, faces.loops, faces.planarity);
      } catch (const InvalidInput&) {
        // The snapped faces do not make one surface (snapping joined or split an edge): the
        // surface exactly, as where snapping gives no valid faces.
      }
      const ConvexLoops exact = convex_loops(s, 0);
      return Body::two_sided_surface(exact.vertices, exact.loops, exact.planarity);
    }
    return Body::two_sided_surface(faces.vertices, faces.loops, faces.planarity);
  };
  if (any) {
    PolygonSoup joined;
    joined.vertices = soup.vertices;
    joined.polygons = soup.polygons;
    for (auto& poly : joined.polygons)
      for (int& x : poly) x = first[static_cast<size_t>(x)];
    try {
      return surface_of(joined);
    } catch (const InvalidInput&) {
      // Joined, an edge is used twice one way (faces that only touch there): as given.
    }
  }
  return surface_of(soup);
}

}  // namespace hedra
