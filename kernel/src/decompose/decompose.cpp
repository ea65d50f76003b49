// Exact convex decomposition: cut every piece by the plane of one of its reflex edges until
// all are convex, then merge pieces whose union is convex. The exact pieces and the cut itself
// are split.cpp's (split_internal.h).
#include "hedra/decompose/decompose.h"
#include "decompose/decompose_internal.h"
#include "decompose/split_internal.h"
#include "core/exact_plane.h"
#include "core/rational_predicates.h"

#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Gmpz.h>
#include <CGAL/Mpzf.h>

#include <algorithm>
#include <list>
#include <map>
#include <numeric>
#include <limits>
#include <optional>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>

#include "hedra/mesh/convexity.h"
#include "hedra/core/error.h"
#include "hedra/core/parallel.h"
#include "hedra/mesh/merge_coplanar.h"
#include "hedra/decompose/split.h"
#include "hedra/core/tolerance.h"

namespace hedra {

using namespace internal;

namespace {

// ---- Reflex edges and the choice of the cut ----------------------------------------------

struct Reflex {
  int a, b;    // edge end points
  int p1, p2;  // canonical planes of the two faces at the edge
};

std::vector<Reflex> reflex_edges(const Context& ctx, const Piece& piece) {
  std::unordered_map<std::uint64_t, int> owner;
  for (size_t t = 0; t < piece.tris.size(); ++t)
    for (int i = 0; i < 3; ++i)
      owner.emplace(key(piece.tris[t].v[i], piece.tris[t].v[(i + 1) % 3]), static_cast<int>(t));
  std::vector<Reflex> out;
  for (size_t t = 0; t < piece.tris.size(); ++t) {
    const Tri& t1 = piece.tris[t];
    for (int i = 0; i < 3; ++i) {
      const int a = t1.v[i], b = t1.v[(i + 1) % 3];
      if (a > b) continue;  // each undirected edge once
      auto it = owner.find(key(b, a));
      HEDRA_ASSERT(it != owner.end(), "decompose: a piece is not closed");
      const Tri& t2 = piece.tris[it->second];
      if (t1.plane == t2.plane && t1.sign == t2.sign) continue;  // flat
      int apex = t2.v[0] + t2.v[1] + t2.v[2] - a - b;
      if (t1.sign * side(ctx, piece.pts[apex], t1.plane) > 0) out.push_back({a, b, t1.plane, t2.plane});
    }
  }
  return out;
}

// Pieces with at most this many candidate planes weigh every candidate (choose_cut).
constexpr size_t kExhaustiveCandidates = 64;
// Otherwise this many are weighed: half the best by symbolic count, half spread over id order.
constexpr size_t kSampledCandidates = 16;

struct CutScore {
  int resolved = -1;  // reflex edges lying on the plane
  int larger = 0;     // reflex edges off the plane on its fuller side (sampled choice only)
  int crossed = 0;    // triangles with corners strictly on both sides
};

CutScore score_cut(const Context& ctx, const Piece& piece, const std::vector<Reflex>& reflex, int c,
                   std::vector<int>& s) {
  for (size_t i = 0; i < piece.pts.size(); ++i) s[i] = side(ctx, piece.pts[i], c);
  CutScore out;
  out.resolved = 0;
  int below = 0, above = 0;
  for (const Reflex& r : reflex) {
    out.resolved += s[r.a] == 0 && s[r.b] == 0;
    below += s[r.a] < 0 || s[r.b] < 0;
    above += s[r.a] > 0 || s[r.b] > 0;
  }
  out.larger = std::max(below, above);
  for (const Tri& t : piece.tris) {
    const int lo = std::min({s[t.v[0]], s[t.v[1]], s[t.v[2]]});
    const int hi = std::max({s[t.v[0]], s[t.v[1]], s[t.v[2]]});
    out.crossed += lo < 0 && hi > 0;
  }
  return out;
}

// The plane on which the most reflex edges lie, then crossing the fewest triangles, then the
// smallest id: decided by exact sides and input order only, so rotating the body changes
// nothing. Cost O(C·(V + T + R)) for C candidate planes. A piece with more than
// kExhaustiveCandidates candidates (a star prism has one per reflex edge) weighs
// kSampledCandidates of them — those lying on the most reflex edges by construction (symbolic,
// O(R)) and others spread over id order — and prefers among equal counts the plane that leaves
// the fewest reflex edges on its fuller side: the cuts halve such pieces, so the rounds are
// O(log R) deep and each costs O(V + T + R) per piece instead of O(R·(V + T)).
int choose_cut(const Context& ctx, const Piece& piece, const std::vector<Reflex>& reflex) {
  std::vector<int> candidates;
  for (const Reflex& r : reflex) {
    candidates.push_back(r.p1);
    candidates.push_back(r.p2);
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  const bool sampled = candidates.size() > kExhaustiveCandidates;
  if (sampled) {
    std::vector<int> count(candidates.size(), 0);
    std::vector<int> common;
    for (const Reflex& r : reflex) {
      const auto &a = piece.pts[r.a].on, &b = piece.pts[r.b].on;
      common.clear();
      std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(common));
      for (int q : common) {
        auto it = std::lower_bound(candidates.begin(), candidates.end(), q);
        if (it != candidates.end() && *it == q) ++count[static_cast<size_t>(it - candidates.begin())];
      }
    }
    std::vector<size_t> order(candidates.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return count[x] > count[y]; });
    std::vector<int> chosen;
    for (size_t k = 0; k < kSampledCandidates / 2; ++k) chosen.push_back(candidates[order[k]]);
    const size_t spread = kSampledCandidates - kSampledCandidates / 2;
    for (size_t k = 0; k < spread; ++k) chosen.push_back(candidates[(2 * k + 1) * candidates.size() / (2 * spread)]);
    std::sort(chosen.begin(), chosen.end());
    chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
    candidates = std::move(chosen);
  }
  int best = -1;
  CutScore top;
  std::vector<int> s(piece.pts.size());
  for (int c : candidates) {
    const CutScore score = score_cut(ctx, piece, reflex, c, s);
    bool better;
    if (score.resolved != top.resolved) better = score.resolved > top.resolved;
    else if (sampled && score.larger != top.larger) better = score.larger < top.larger;
    else better = score.crossed < top.crossed;
    if (better) best = c, top = score;
  }
  HEDRA_ASSERT(top.resolved > 0, "decompose: no cut resolves a reflex edge");
  return best;
}

// Every piece closed: each directed edge has its reverse. Cost O(n).
bool closed(const std::vector<Piece>& pieces) {
  for (const Piece& p : pieces) {
    std::unordered_set<std::uint64_t> directed;
    for (const Tri& t : p.tris)
      for (int i = 0; i < 3; ++i) directed.insert(key(t.v[i], t.v[(i + 1) % 3]));
    for (const Tri& t : p.tris)
      for (int i = 0; i < 3; ++i)
        if (!directed.count(key(t.v[(i + 1) % 3], t.v[i]))) return false;
  }
  return true;
}

// The cut of choose_cut. Exactly, a plane through a reflex edge always has the piece on both
// sides; with an epsilon (the float variant), or with input faces that share a canonical plane
// only within the rounding guard, it may not, or the cap may fail: then the piece's other
// reflex-edge planes are tried, in id order, before giving up (deterministic).
Sides split_or_retry(const Context& ctx, const Piece& piece, const std::vector<Reflex>& reflex) {
  const int best = choose_cut(ctx, piece, reflex);
  std::vector<int> planes{best};
  if (!ctx.floating) {
    for (const Reflex& r : reflex) planes.push_back(r.p1), planes.push_back(r.p2);
    std::sort(planes.begin() + 1, planes.end());
    planes.erase(std::unique(planes.begin() + 1, planes.end()), planes.end());
  }
  std::string first_error;
  for (int plane : planes) {
    if (plane == best && !first_error.empty()) continue;
    try {
      Sides sides = split_piece(ctx, piece, plane);
      if (!sides.cut) throw InternalError("the plane of a reflex edge does not cut its piece");
      if (!ctx.floating && (!closed(sides.below) || !closed(sides.above)))
        throw InternalError("decompose: a piece is not closed");
      return sides;
    } catch (const InternalError& e) {
      if (first_error.empty()) first_error = e.what();
    }
  }
  throw InternalError(first_error);
}

// The body with each face loop starting at its smallest vertex and the faces sorted: the same
// body whatever order its faces were found in (merged coplanar hull triangles start their loop
// at whichever triangle came first).
Body canonical_faces(const Body& body) {
  std::vector<Face> faces = body.faces();
  for (Face& face : faces) {
    for (auto& loop : face.loops) std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
    if (face.loops.size() > 2) std::sort(face.loops.begin() + 1, face.loops.end());  // holes
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.loops < b.loops; });
  return Body(body.vertices(), std::move(faces));
}

// A convex piece with double coordinates, never failing on a valid piece. First the exact
// piece rounded with its faces merged by canonical plane (body_of). Where rounding breaks that
// (a face a few 1e-9 wide is tilted by rounding, a sliver corner thinner than an ulp
// collapses, a face left reflex by a few ulps), the convex hull of the piece's rounded vertices instead: the piece is convex,
// so the hull lies within half an ulp per coordinate of it (no gap or overlap with its
// neighbours beyond rounding); its coplanar hull triangles are merged exactly (orient3d on the
// doubles); a hull corner making a sliver hull face is dropped (about an ulp). nullopt when even the rounded vertices are coplanar: the whole piece is thinner
// than rounding (counted in Decomposition::degenerate_pieces). Cost O(n log n), n points.
std::optional<Body> rounded_piece(const Piece& piece) {
  try {
    Body body = body_of(piece);
    // Rounding can also leave a face a few ulps reflex; consumers (clipping) need exact
    // convexity of the double polyhedron.
    if (is_convex(body)) return body;
  } catch (const InvalidInput&) {
  }
  std::vector<P3> coords;
  for (const Point& p : piece.pts) {
    const Vec3 r = rounded(p.p);
    coords.emplace_back(r.x(), r.y(), r.z());
  }
  std::sort(coords.begin(), coords.end());
  coords.erase(std::unique(coords.begin(), coords.end()), coords.end());
  // A hull face can itself be a sliver (three rounded corners in a line within an ulp) whose
  // area double arithmetic cannot resolve: then the middle corner of the thinnest hull
  // triangle is dropped and the hull taken again. Each drop moves the hull by about an ulp.
  for (int attempt = 0; attempt < 256; ++attempt) {
    if (coords.size() < 4) return std::nullopt;
    size_t i2 = 2;
    while (i2 < coords.size() && CGAL::collinear(coords[0], coords[1], coords[i2])) ++i2;
    if (i2 == coords.size()) return std::nullopt;
    bool solid = false;
    for (size_t i = 2; i < coords.size() && !solid; ++i)
      solid = !CGAL::coplanar(coords[0], coords[1], coords[i2], coords[i]);
    if (!solid) return std::nullopt;
    CGAL::Surface_mesh<P3> hull;
    CGAL::convex_hull_3(coords.begin(), coords.end(), hull);
    // CGAL's quickhull orders its work by vertex addresses (a std::map of handles), so the
    // order of the hull's vertices and triangles, and among exactly coplanar points its
    // triangles themselves, change with the memory layout: with the threads, from run to run.
    // The soup is made canonical: the vertices in exact lexicographic order, each triangle
    // from its smallest vertex, the triangles sorted; and the body's faces likewise below.
    std::vector<P3> corners;
    for (auto v : hull.vertices()) corners.push_back(hull.point(v));
    std::sort(corners.begin(), corners.end());
    PolygonSoup soup;
    for (const P3& p : corners)
      soup.vertices.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
    std::vector<std::array<int, 3>> triangles;
    for (auto f : hull.faces()) {
      std::array<int, 3> tri{};
      int k = 0;
      for (auto v : CGAL::vertices_around_face(hull.halfedge(f), hull))
        tri[static_cast<size_t>(k++)] = static_cast<int>(
            std::lower_bound(corners.begin(), corners.end(), hull.point(v)) - corners.begin());
      std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
      triangles.push_back(tri);
    }
    std::sort(triangles.begin(), triangles.end());
    // Plane of every hull triangle by exact comparison; a flat triangle (a point kept on a
    // hull edge) takes the plane of a neighbour and vanishes in its face.
    std::vector<PL> planes;
    std::vector<int> ids;
    std::map<std::pair<int, int>, size_t> edge_owner;
    for (const std::array<int, 3>& t : triangles) {
      const std::vector<int> tri(t.begin(), t.end());
      const std::vector<P3> pts = {corners[static_cast<size_t>(t[0])], corners[static_cast<size_t>(t[1])],
                                   corners[static_cast<size_t>(t[2])]};
      int id = -1;
      if (!CGAL::collinear(pts[0], pts[1], pts[2])) {
        const PL plane(pts[0], pts[1], pts[2]);
        for (size_t k = 0; k < planes.size() && id < 0; ++k)
          if (planes[k] == plane) id = static_cast<int>(k);
        if (id < 0) {
          id = static_cast<int>(planes.size());
          planes.push_back(plane);
        }
      }
      for (int i = 0; i < 3; ++i) edge_owner[{tri[i], tri[(i + 1) % 3]}] = soup.polygons.size();
      ids.push_back(id);
      soup.polygons.push_back(std::move(tri));
    }
    for (bool progress = true; progress;) {
      progress = false;
      for (size_t t = 0; t < soup.polygons.size(); ++t) {
        if (ids[t] >= 0) continue;
        const auto& tri = soup.polygons[t];
        for (int i = 0; i < 3 && ids[t] < 0; ++i) {
          const size_t u = edge_owner.at({tri[(i + 1) % 3], tri[i]});
          if (ids[u] >= 0) ids[t] = ids[u], progress = true;
        }
      }
    }
    try {
      std::vector<Body> bodies = bodies_from_soup(soup, ids);
      if (bodies.size() == 1 && is_convex(bodies[0])) return canonical_faces(bodies[0]);
    } catch (const InvalidInput&) {
    }
    // The thinnest non-flat hull triangle (area over squared longest edge) loses the corner
    // opposite its longest edge.
    double thinnest = std::numeric_limits<double>::infinity();
    Vec3 drop = Vec3::Zero();
    for (size_t t = 0; t < soup.polygons.size(); ++t) {
      const auto& tri = soup.polygons[t];
      const Vec3 &a = soup.vertices[tri[0]], &b = soup.vertices[tri[1]], &c = soup.vertices[tri[2]];
      const std::array<double, 3> edge = {(c - b).squaredNorm(), (a - c).squaredNorm(), (b - a).squaredNorm()};
      const int longest = static_cast<int>(std::max_element(edge.begin(), edge.end()) - edge.begin());
      const double thin = (b - a).cross(c - a).norm() / edge[longest];
      if (thin < thinnest) thinnest = thin, drop = soup.vertices[tri[longest]];
    }
    const P3 gone(drop.x(), drop.y(), drop.z());
    coords.erase(std::remove(coords.begin(), coords.end(), gone), coords.end());
  }
  return std::nullopt;
}

// Summed in the exact number type, term by term: a lazy sum of every triangle's term built one
// node per term, and evaluating it recursed once per term (a stack overflow for the 16 000
// triangles of a 4000-point star prism under AddressSanitizer).
EK::FT exact_volume6(const Piece& piece) {
  EK::FT::ET v = 0;
  for (const Tri& t : piece.tris) {
    const P3& a = piece.pts[t.v[0]].p;
    const P3& b = piece.pts[t.v[1]].p;
    const P3& c = piece.pts[t.v[2]].p;
    v += CGAL::exact(CGAL::determinant(a - CGAL::ORIGIN, b - CGAL::ORIGIN, c - CGAL::ORIGIN));
  }
  return EK::FT(v);
}

// Canonical order of pieces: by their exact lexicographically smallest point.
P3 smallest_point(const Piece& piece) {
  P3 best = piece.pts[0].p;
  for (const Point& p : piece.pts)
    if (p.p < best) best = p.p;
  return best;
}

// ---- Merge pass ----------------------------------------------------------------------------

// The (plane, sign) pairs of a piece's faces, sorted.
std::vector<std::pair<int, int>> face_planes(const Piece& piece) {
  std::vector<std::pair<int, int>> out;
  for (const Tri& t : piece.tris) out.emplace_back(t.plane, t.sign);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// Every point of `other` in the closed inner half-space of every face plane of `piece` but
// `shared`.
bool inside_planes(const Context& ctx, const std::vector<std::pair<int, int>>& planes, int shared,
                   const Piece& other) {
  for (const auto& [plane, sign] : planes) {
    if (plane == shared) continue;
    for (const Point& q : other.pts)
      if (sign * side(ctx, q, plane) > 0) return false;
  }
  return true;
}

// Convex pieces A and B with faces on one plane c from opposite sides have a convex union iff
// every point of B lies inside A's other face planes and every point of A inside B's: then the
// intersection H of those half-spaces meets c's side of A in A and the other side in B, so
// A ∪ B = H is convex; conversely a convex union is bounded by the planes of A's faces off c.
// Decided by exact sides. Returns the shared plane, or −1.
int mergeable(const Context& ctx, const Piece& a, const std::vector<std::pair<int, int>>& pa,
              const Piece& b, const std::vector<std::pair<int, int>>& pb) {
  for (const auto& [plane, sign] : pa) {
    if (!std::binary_search(pb.begin(), pb.end(), std::make_pair(plane, -sign))) continue;
    if (inside_planes(ctx, pa, plane, b) && inside_planes(ctx, pb, plane, a)) return plane;
  }
  return -1;
}

// The convex hull of two pieces' points (their convex union), with each hull triangle
// assigned the canonical plane it lies on.
Piece merged(const Context& ctx, const Piece& a, const Piece& b,
             const std::vector<std::pair<int, int>>& planes) {
  std::vector<Point> pts = a.pts;
  for (const Point& q : b.pts) {
    auto same = std::find_if(pts.begin(), pts.end(), [&](const Point& p) { return p.p == q.p; });
    if (same == pts.end()) {
      pts.push_back(q);
    } else {
      for (int id : q.on) add_on(*same, id);
      if (same->origin < 0 && q.origin >= 0) same->origin = q.origin, same->input = q.input;
    }
  }
  std::vector<P3> coords;
  for (const Point& p : pts) coords.push_back(p.p);
  CGAL::Surface_mesh<P3> hull;
  CGAL::convex_hull_3(coords.begin(), coords.end(), hull);
  std::map<P3, int> index;
  for (size_t i = 0; i < pts.size(); ++i) index.emplace(pts[i].p, static_cast<int>(i));
  // Each hull triangle lies on one of the two pieces' face planes. Several can contain all
  // three corners (a thin triangle along an edge of a rotated body, whose corners lie on the
  // planes within rounding): then the plane best aligned with the triangle, and for a
  // triangle too thin to have a direction, the plane of a neighbour that contains it.
  std::vector<std::array<int, 3>> tris;
  for (auto f : hull.faces()) {
    std::array<int, 3> v{};
    int k = 0;
    for (auto h : CGAL::halfedges_around_face(hull.halfedge(f), hull))
      v[k++] = index.at(hull.point(hull.target(h)));
    tris.push_back(v);
  }
  // The hull may keep a point in the middle of one of its edges, as the corner of a flat
  // triangle: split the neighbour across that edge at the point and drop the flat triangle.
  for (int guard = 0; guard < 1000; ++guard) {
    size_t flat = tris.size();
    int middle = -1;
    for (size_t t = 0; t < tris.size() && flat == tris.size(); ++t) {
      const auto& v = tris[t];
      if (!CGAL::collinear(pts[v[0]].p, pts[v[1]].p, pts[v[2]].p)) continue;
      flat = t;
      for (int i = 0; i < 3; ++i)
        if (CGAL::collinear_are_strictly_ordered_along_line(pts[v[(i + 2) % 3]].p, pts[v[i]].p,
                                                            pts[v[(i + 1) % 3]].p))
          middle = i;
    }
    if (flat == tris.size()) break;
    HEDRA_ASSERT(middle >= 0, "decompose: a merged hull has a repeated point");
    const std::array<int, 3> t = tris[flat];
    const int m = t[middle], p = t[(middle + 1) % 3], q = t[(middle + 2) % 3];
    size_t u = tris.size();
    int apex = -1;
    for (size_t k = 0; k < tris.size() && u == tris.size(); ++k)
      for (int i = 0; i < 3; ++i)
        if (tris[k][i] == q && tris[k][(i + 1) % 3] == p) u = k, apex = tris[k][(i + 2) % 3];
    HEDRA_ASSERT(u != tris.size(), "decompose: a merged hull is not closed");
    tris[u] = {q, m, apex};
    tris.push_back({m, p, apex});
    tris.erase(tris.begin() + static_cast<std::ptrdiff_t>(flat));
  }
  const size_t n = tris.size();
  std::vector<std::vector<int>> candidates(n);
  std::vector<int> plane(n, -1);
  std::vector<Vec3> normal(n);
  double scale = 0;
  for (const Point& p : pts) scale = std::max(scale, rounded(p.p).cwiseAbs().sum());
  for (size_t t = 0; t < n; ++t) {
    const auto& v = tris[t];
    for (const auto& [id, sgn] : planes)
      if (!side(ctx, pts[v[0]], id) && !side(ctx, pts[v[1]], id) && !side(ctx, pts[v[2]], id))
        candidates[t].push_back(id);
    std::sort(candidates[t].begin(), candidates[t].end());
    candidates[t].erase(std::unique(candidates[t].begin(), candidates[t].end()), candidates[t].end());
    HEDRA_ASSERT(!candidates[t].empty(), "decompose: a merged face lies on no face plane");
    const Vec3 corner = rounded(pts[v[0]].p);
    normal[t] = (rounded(pts[v[1]].p) - corner).cross(rounded(pts[v[2]].p) - corner);
    const bool thin = normal[t].norm() <= 1e-6 * scale * scale;
    if (candidates[t].size() == 1) {
      plane[t] = candidates[t][0];
    } else if (!thin) {
      double best = -1;
      for (int id : candidates[t]) {
        const double along = std::abs(normal[t].normalized().dot(ctx.approx[id].normal()));
        if (along > best) best = along, plane[t] = id;
      }
    }
  }
  std::map<std::uint64_t, size_t> edge_owner;
  for (size_t t = 0; t < n; ++t)
    for (int i = 0; i < 3; ++i) edge_owner[key(tris[t][i], tris[t][(i + 1) % 3])] = t;
  for (bool progress = true; progress;) {
    progress = false;
    for (size_t t = 0; t < n; ++t) {
      if (plane[t] >= 0) continue;
      for (int i = 0; i < 3 && plane[t] < 0; ++i) {
        const size_t u = edge_owner.at(key(tris[t][(i + 1) % 3], tris[t][i]));
        if (plane[u] >= 0 && std::binary_search(candidates[t].begin(), candidates[t].end(), plane[u]))
          plane[t] = plane[u], progress = true;
      }
    }
  }
  Piece out;
  std::vector<int> remap(pts.size(), -1);
  for (size_t t = 0; t < n; ++t) {
    std::array<int, 3> v = tris[t];
    const int id = plane[t] >= 0 ? plane[t] : candidates[t][0];
    const EK::Vector_3 en = CGAL::cross_product(pts[v[1]].p - pts[v[0]].p, pts[v[2]].p - pts[v[0]].p);
    const int sign = CGAL::is_positive(en * ctx.planes[id].orthogonal_vector()) ? 1 : -1;
    for (int& w : v) {
      if (remap[w] < 0) {
        remap[w] = static_cast<int>(out.pts.size());
        out.pts.push_back(pts[w]);
      }
      w = remap[w];
    }
    out.tris.push_back({v, id, sign});
  }
  return out;
}

// Greedy merge of adjacent pieces with a convex union, in canonical order, until none is left:
// deterministic.
std::vector<Piece> merge_pieces(const Context& ctx, std::vector<Piece> pieces, int& merges) {
  std::vector<std::vector<std::pair<int, int>>> planes;
  for (const Piece& p : pieces) planes.push_back(face_planes(p));
  std::vector<char> alive(pieces.size(), 1);
  bool changed = true;
  while (changed) {
    changed = false;
    // Pieces by face plane and sign: candidates share a plane from opposite sides.
    std::map<std::pair<int, int>, std::vector<int>> by_plane;
    for (size_t i = 0; i < pieces.size(); ++i)
      if (alive[i])
        for (const auto& ps : planes[i]) by_plane[ps].push_back(static_cast<int>(i));
    for (size_t i = 0; i < pieces.size(); ++i) {
      if (!alive[i]) continue;
      std::vector<int> candidates;
      for (const auto& [plane, sign] : planes[i]) {
        auto it = by_plane.find({plane, -sign});
        if (it == by_plane.end()) continue;
        for (int j : it->second)
          if (j > static_cast<int>(i) && alive[j]) candidates.push_back(j);
      }
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      for (int j : candidates) {
        if (!alive[j] || mergeable(ctx, pieces[i], planes[i], pieces[j], planes[j]) < 0) continue;
        std::vector<std::pair<int, int>> both = planes[i];
        both.insert(both.end(), planes[j].begin(), planes[j].end());
        Piece joined = merged(ctx, pieces[i], pieces[j], both);
        // Faces that are one plane only within rounding (a rotated input) can leave the
        // union with faces double coordinates cannot represent: then the pair stays apart.
        try {
          body_of(joined);
        } catch (const InvalidInput&) {
          continue;
        }
        pieces[i] = std::move(joined);
        planes[i] = face_planes(pieces[i]);
        alive[j] = 0;
        ++merges;
        changed = true;
      }
    }
  }
  std::vector<Piece> out;
  for (size_t i = 0; i < pieces.size(); ++i)
    if (alive[i]) out.push_back(std::move(pieces[i]));
  return out;
}

}  // namespace

namespace {

// ---- The exact pieces as planes (Decomposition::exact_pieces) -----------------------------

static_assert(std::is_same_v<EK::FT::ET, mpq_class>, "Epeck's exact numbers are expected to be mpq_class");

// An exact point as homogeneous integers (X, Y, Z, W), W > 0: its rational coordinates over
// their least common denominator.
std::array<mpz_class, 4> homogeneous(const P3& p) {
  const mpq_class x = CGAL::exact(p.x()), y = CGAL::exact(p.y()), z = CGAL::exact(p.z());
  std::array<mpz_class, 4> h;
  mpz_lcm(h[3].get_mpz_t(), x.get_den_mpz_t(), y.get_den_mpz_t());
  mpz_lcm(h[3].get_mpz_t(), h[3].get_mpz_t(), z.get_den_mpz_t());
  const mpq_class* c[3] = {&x, &y, &z};
  for (size_t i = 0; i < 3; ++i) {
    mpz_divexact(h[i].get_mpz_t(), h[3].get_mpz_t(), c[i]->get_den_mpz_t());
    h[i] *= c[i]->get_num();
  }
  return h;
}

// An integer as Mpzf. CGAL 5.5's Mpzf constructor from an mpz drops its sign (and cannot take
// zero): built from the magnitude, then negated.
CGAL::Mpzf mpzf_of(const mpz_class& z) {
  if (sgn(z) == 0) return CGAL::Mpzf(0);
  const mpz_class magnitude = abs(z);
  const CGAL::Mpzf m(magnitude);
  return sgn(z) < 0 ? CGAL::Mpzf(0) - m : m;
}

// The plane through three exact points as integer coefficients (the 3 × 3 minors of their
// homogeneous coordinates: no rational arithmetic, so no gcd), Positive on the side of
// `inner`, an exact point off the plane. Kept as Mpzf.
ExactPlane plane_through_exact(const P3& a, const P3& b, const P3& c, const P3& inner) {
  const std::array<mpz_class, 4> p = homogeneous(a), q = homogeneous(b), r = homogeneous(c);
  // det of columns (i, j, k) over the three rows.
  const auto det = [&](size_t i, size_t j, size_t k) -> mpz_class {
    return p[i] * (q[j] * r[k] - q[k] * r[j]) - p[j] * (q[i] * r[k] - q[k] * r[i]) +
           p[k] * (q[i] * r[j] - q[j] * r[i]);
  };
  std::array<mpz_class, 4> h = {det(1, 2, 3), -det(0, 2, 3), det(0, 1, 3), -det(0, 1, 2)};
  const std::array<mpz_class, 4> s = homogeneous(inner);
  const mpz_class at = h[0] * s[0] + h[1] * s[1] + h[2] * s[2] + h[3] * s[3];
  if (sgn(at) == 0) throw InternalError("decompose: an exact piece is flat (a face through its inner point)");
  std::array<CGAL::Mpzf, 4> out;
  for (size_t i = 0; i < 4; ++i) out[i] = mpzf_of(sgn(at) < 0 ? mpz_class(-h[i]) : h[i]);
  return internal::plane_from_exact(out);
}

// A lazy exact plane as integer coefficients (over their least common denominator), Mpzf;
// negated when `flip`.
ExactPlane plane_of_lazy(const PL& plane, bool flip) {
  const mpq_class c[4] = {CGAL::exact(plane.a()), CGAL::exact(plane.b()), CGAL::exact(plane.c()), CGAL::exact(plane.d())};
  mpz_class w = 1;
  for (const mpq_class& x : c) mpz_lcm(w.get_mpz_t(), w.get_mpz_t(), x.get_den_mpz_t());
  std::array<CGAL::Mpzf, 4> out;
  for (size_t i = 0; i < 4; ++i) {
    mpz_class h;
    mpz_divexact(h.get_mpz_t(), w.get_mpz_t(), c[i].get_den_mpz_t());
    h *= c[i].get_num();
    out[i] = mpzf_of(flip ? mpz_class(-h) : h);
  }
  return internal::plane_from_exact(out);
}

// The exact piece as planes, when it is exactly convex. A face is a set of the piece's
// triangles on one plane: those exactly on their canonical plane (every corner on it exactly,
// by construction or by the exact test) are one face with that plane, through the canonical
// plane's three input vertices; the others (a corner on it only within the rounding guard)
// are grouped by exact coplanarity and get the plane of three exact corners. The guarded run
// decides convexity in its model, where input vertices within the guard of a plane lie on it;
// the exact piece can then fold by an ulp across such a face. So the piece is checked: an
// inner point strictly inside every face plane, and every edge convex (the triangles on one
// side of it inside the face plane of the other). A connected closed surface convex at every
// edge bounds a convex body. nullopt when a check fails (the caller keeps the rounded piece).
// Cost O(T) for T triangles, with a few exact orientations each.
std::optional<ExactConvex> exact_convex(const Context& ctx, const InputPlanes& model, const Piece& piece) {
  ExactConvex out;
  const auto point = [&](int v) -> const P3& { return piece.pts[static_cast<size_t>(v)].p; };
  // Side of corner v of canonical plane c, in orient3d's convention (Positive on the plane's
  // positive side): zero by construction when the corner lies on c exactly (not only within
  // the guard); for an input vertex orient3d on the plane's support triple (doubles, hedra's
  // filter and Mpzf: much cheaper than the lazy plane's exact evaluation when it is close);
  // else the exact point against the lazy plane.
  const auto canonical_side = [&](int c, int v) {
    const Point& q = piece.pts[static_cast<size_t>(v)];
    if (std::binary_search(q.on.begin(), q.on.end(), c) && !std::binary_search(q.loose.begin(), q.loose.end(), c))
      return Sign::Zero;
    if (q.origin >= 0) {
      const auto& sp = model.support[static_cast<size_t>(c)];
      return orient3d(sp[0], sp[1], sp[2], q.input);
    }
    const CGAL::Oriented_side o = oriented_side_3(ctx.planes[static_cast<size_t>(c)], q.p);
    return o == CGAL::ON_ORIENTED_BOUNDARY ? Sign::Zero : (o == CGAL::ON_POSITIVE_SIDE ? Sign::Positive : Sign::Negative);
  };
  const auto exactly_on = [&](int v, int c) { return canonical_side(c, v) == Sign::Zero; };
  // A point strictly inside the piece, if it is convex: the centroid of four corners not on
  // one plane (exact).
  std::optional<P3> inside;
  {
    std::vector<int> used;
    for (const Tri& t : piece.tris) used.insert(used.end(), t.v.begin(), t.v.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    // Four corners far from coplanar, chosen in double (the first corners of a piece often lie
    // on one face, where the exact test of a rotated body's cut points is the slow case): the
    // farthest from the first, from their line, from their plane. One exact test confirms.
    std::vector<Vec3> r(used.size());
    for (size_t i = 0; i < used.size(); ++i) r[i] = rounded(point(used[i]));
    const auto farthest = [&](auto&& distance) {
      size_t best = 0;
      double d = -1;
      for (size_t i = 0; i < r.size(); ++i)
        if (const double x = distance(r[i]); x > d) d = x, best = i;
      return best;
    };
    const size_t i0 = 0;
    const size_t i1 = farthest([&](const Vec3& p) { return (p - r[i0]).squaredNorm(); });
    const size_t i2 = farthest([&](const Vec3& p) { return (p - r[i0]).cross(r[i1] - r[i0]).squaredNorm(); });
    const Vec3 n = (r[i1] - r[i0]).cross(r[i2] - r[i0]);
    const size_t i3 = farthest([&](const Vec3& p) { return std::abs((p - r[i0]).dot(n)); });
    const auto at = [&](size_t i) -> const P3& { return point(used[i]); };
    if (CGAL::orientation(at(i0), at(i1), at(i2), at(i3)) == CGAL::COPLANAR) return std::nullopt;
    inside = CGAL::centroid(at(i0), at(i1), at(i2), at(i3));
  }
  // Orientation of four corners: on their doubles (hedra's filtered orient3d, CGAL's
  // convention) when all four are input vertices, which is fast also when they are coplanar;
  // else on the exact points.
  const auto orientation = [&](int i, int j, int k, int l) {
    const Point &a = piece.pts[static_cast<size_t>(i)], &b = piece.pts[static_cast<size_t>(j)],
                &c = piece.pts[static_cast<size_t>(k)], &d = piece.pts[static_cast<size_t>(l)];
    if (a.origin >= 0 && b.origin >= 0 && c.origin >= 0 && d.origin >= 0)
      return static_cast<CGAL::Orientation>(static_cast<int>(orient3d(a.input, b.input, c.input, d.input)));
    return CGAL::orientation(a.p, b.p, c.p, d.p);
  };
  // Per face, how to decide a corner's side (+1 inside, 0 on, −1 outside): its canonical plane
  // and sign, or three corners and the orientation of `inside`.
  struct FaceRef {
    int plane = -1, sign = 0;  // a face exactly on canonical plane `plane`
    int canonical = -1, canonical_sign = 0;  // else the canonical plane its triangles round to
    std::array<int, 3> v{};
    CGAL::Orientation inner = CGAL::COPLANAR;
    // Where the face is the parts of one triangle off its canonical plane (Tri::own): that
    // triangle's plane, whose exact coefficients are small (three input doubles, or a cap's
    // three corners), and the side of it the piece lies on.
    const PL* own = nullptr;
    CGAL::Oriented_side own_inner = CGAL::ON_ORIENTED_BOUNDARY;
  };
  std::vector<FaceRef> refs;
  const auto side = [&](int face, int v) {
    const FaceRef& r = refs[static_cast<size_t>(face)];
    if (r.plane >= 0) {
      // Sign +1: the piece lies on the canonical plane's negative side.
      const Sign o = canonical_side(r.plane, v);
      return o == Sign::Zero ? 0 : ((o == Sign::Negative) == (r.sign > 0) ? 1 : -1);
    }
    if (std::find(r.v.begin(), r.v.end(), v) != r.v.end()) return 0;
    if (r.own) {
      const CGAL::Oriented_side o = oriented_side_3(*r.own, point(v));
      return o == CGAL::ON_ORIENTED_BOUNDARY ? 0 : (o == r.own_inner ? 1 : -1);
    }
    const CGAL::Orientation o = orientation(r.v[0], r.v[1], r.v[2], v);
    return o == CGAL::COPLANAR ? 0 : (o == r.inner ? 1 : -1);
  };
  std::map<std::pair<int, int>, int> on_canonical;  // (plane, sign) → face
  std::unordered_map<const PL*, int> own_face;      // Tri::own → face
  std::vector<int> face_of(piece.tris.size());
  for (size_t t = 0; t < piece.tris.size(); ++t) {
    const Tri& tri = piece.tris[t];
    const bool exact = ctx.exact_planes || (exactly_on(tri.v[0], tri.plane) && exactly_on(tri.v[1], tri.plane) &&
                                            exactly_on(tri.v[2], tri.plane));
    if (exact) {
      const auto [it, fresh] = on_canonical.emplace(std::make_pair(tri.plane, tri.sign), static_cast<int>(out.faces.size()));
      if (fresh) {
        const auto& sp = model.support[static_cast<size_t>(tri.plane)];
        // Sign +1: the piece lies on the plane's negative side, which is through()'s positive.
        // A plane through no three input vertices (the faces of an exact solid) from its
        // exact coefficients, negated where the piece lies on its negative side.
        const size_t c = static_cast<size_t>(tri.plane);
        if (sp[0] == sp[1] && c < model.exact.size() && model.exact[c].by_exact()) {
          // Made once per plane for the model (run()): shared by every piece on it.
          out.faces.push_back(tri.sign > 0 ? model.exact[c].flipped() : model.exact[c]);
        } else if (sp[0] == sp[1]) {
          out.faces.push_back(plane_of_lazy(ctx.planes[c], tri.sign > 0));
        } else {
          const ExactPlane f = ExactPlane::through(sp[0], sp[1], sp[2]);
          out.faces.push_back(tri.sign > 0 ? f : f.flipped());
        }
        refs.push_back({tri.plane, tri.sign, -1, 0, {}, CGAL::COPLANAR});
        // The inner point strictly inside (Sign +1: on the plane's negative side).
        const CGAL::Oriented_side o = ctx.planes[static_cast<size_t>(tri.plane)].oriented_side(*inside);
        if (o == CGAL::ON_ORIENTED_BOUNDARY || (o == CGAL::ON_NEGATIVE_SIDE) != (tri.sign > 0)) return std::nullopt;
      }
      face_of[t] = it->second;
      continue;
    }
    // A triangle of collinear exact corners (a cap's zero-area sliver) spans no plane: its
    // edges only join the faces around it (below).
    const Vec3 r0 = rounded(point(tri.v[0])), r1 = rounded(point(tri.v[1])), r2 = rounded(point(tri.v[2]));
    const double span = std::max({(r1 - r0).squaredNorm(), (r2 - r0).squaredNorm(), (r2 - r1).squaredNorm()});
    const bool wide = (r1 - r0).cross(r2 - r0).squaredNorm() > 1e-20 * span * span;  // far from collinear
    if (!wide && CGAL::collinear(point(tri.v[0]), point(tri.v[1]), point(tri.v[2]))) {
      face_of[t] = -1;
      continue;
    }
    int face = -1;
    // The parts of one triangle lie on its plane by construction.
    if (tri.own)
      if (auto it = own_face.find(tri.own); it != own_face.end() && refs[static_cast<size_t>(it->second)].canonical_sign == tri.sign)
        face = it->second;
    for (size_t f = 0; f < refs.size() && face < 0; ++f) {
      const FaceRef& r = refs[f];
      if (r.plane >= 0 || r.canonical != tri.plane || r.canonical_sign != tri.sign) continue;
      if (side(static_cast<int>(f), tri.v[0]) == 0 && side(static_cast<int>(f), tri.v[1]) == 0 &&
          side(static_cast<int>(f), tri.v[2]) == 0)
        face = static_cast<int>(f);
    }
    if (face < 0) {
      FaceRef r;
      r.canonical = tri.plane;
      r.canonical_sign = tri.sign;
      r.v = tri.v;
      r.inner = CGAL::orientation(point(tri.v[0]), point(tri.v[1]), point(tri.v[2]), *inside);
      if (r.inner == CGAL::COPLANAR) return std::nullopt;
      if (tri.own) {
        r.own = tri.own;
        r.own_inner = r.own->oriented_side(*inside);
        if (r.own_inner == CGAL::ON_ORIENTED_BOUNDARY) return std::nullopt;
      }
      face = static_cast<int>(out.faces.size());
      if (tri.own) own_face.emplace(tri.own, face);
      refs.push_back(r);
      out.faces.emplace_back();  // its plane once the piece is known to be convex (below)
    }
    face_of[t] = face;
  }
  // Faces meeting at an edge: the faces of the triangles on each edge, where they differ. The
  // edges of a zero-area triangle lie on one segment: they are one group, whose faces all meet
  // along it.
  std::unordered_map<std::uint64_t, int> edge_id;
  edge_id.reserve(piece.tris.size() * 3);
  std::vector<int> parent;
  std::vector<std::pair<int, int>> edge_tris;  // (edge group, triangle)
  const auto find = [&](int x) {
    while (parent[static_cast<size_t>(x)] != x)
      x = parent[static_cast<size_t>(x)] = parent[static_cast<size_t>(parent[static_cast<size_t>(x)])];
    return x;
  };
  for (size_t t = 0; t < piece.tris.size(); ++t) {
    const auto& v = piece.tris[t].v;
    int ids[3];
    for (int i = 0; i < 3; ++i) {
      const int a = std::min(v[static_cast<size_t>(i)], v[static_cast<size_t>((i + 1) % 3)]);
      const int b = std::max(v[static_cast<size_t>(i)], v[static_cast<size_t>((i + 1) % 3)]);
      const auto [it, fresh] = edge_id.emplace(key(a, b), static_cast<int>(parent.size()));
      if (fresh) parent.push_back(it->second);
      ids[i] = it->second;
      if (face_of[t] >= 0) edge_tris.emplace_back(it->second, static_cast<int>(t));
    }
    if (face_of[t] < 0)
      for (int i = 1; i < 3; ++i) parent[static_cast<size_t>(find(ids[i]))] = find(ids[0]);
  }
  for (auto& [e, t] : edge_tris) e = find(e);
  std::sort(edge_tris.begin(), edge_tris.end());
  for (size_t i = 0; i < edge_tris.size();) {
    size_t j = i;
    while (j < edge_tris.size() && edge_tris[j].first == edge_tris[i].first) ++j;
    for (size_t x = i; x < j; ++x)
      for (size_t y = i; y < j; ++y) {
        const int tx = edge_tris[x].second, ty = edge_tris[y].second;
        const int fx = face_of[static_cast<size_t>(tx)], fy = face_of[static_cast<size_t>(ty)];
        if (fx == fy) continue;
        // Convex at this edge: y's corners inside x's face plane (or on it). Corners on it by
        // construction are not asked (an exact test of a point on a plane is the slow case).
        const auto& vx = piece.tris[static_cast<size_t>(tx)].v;
        for (int v : piece.tris[static_cast<size_t>(ty)].v)
          if (std::find(vx.begin(), vx.end(), v) == vx.end() && side(fx, v) < 0) return std::nullopt;
        if (fx < fy) out.edges.emplace_back(fx, fy);
      }
    i = j;
  }
  std::sort(out.edges.begin(), out.edges.end());
  out.edges.erase(std::unique(out.edges.begin(), out.edges.end()), out.edges.end());
  // Convex: the planes of the faces off their canonical planes. Built last, since a plane
  // through cut points needs their exact coordinates, which most pieces of a rotated double
  // body (not convex exactly) never need.
  for (size_t f = 0; f < refs.size(); ++f) {
    const FaceRef& r = refs[f];
    if (r.plane >= 0) continue;
    const Point &a = piece.pts[static_cast<size_t>(r.v[0])], &b = piece.pts[static_cast<size_t>(r.v[1])],
                &c = piece.pts[static_cast<size_t>(r.v[2])];
    if (a.origin >= 0 && b.origin >= 0 && c.origin >= 0) {
      // Three input vertices (doubles): their plane exactly, without multiprecision
      // coefficients. through()'s positive side is where orientation is NEGATIVE.
      const ExactPlane g = ExactPlane::through(a.input, b.input, c.input);
      out.faces[f] = r.inner == CGAL::NEGATIVE ? g : g.flipped();
      continue;
    }
    if (r.own) {
      out.faces[f] = plane_of_lazy(*r.own, r.own_inner == CGAL::ON_NEGATIVE_SIDE);
      continue;
    }
    // Oriented by a corner on the inner point's side (the inner point itself is a centroid,
    // whose exact value costs rational sums).
    const P3* corner = nullptr;
    for (const Tri& u : piece.tris) {
      for (int v : u.v)
        if (CGAL::orientation(a.p, b.p, c.p, point(v)) == r.inner) {
          corner = &point(v);
          break;
        }
      if (corner) break;
    }
    if (!corner) return std::nullopt;
    out.faces[f] = plane_through_exact(a.p, b.p, c.p, *corner);
  }
  out.canonical.reserve(refs.size());
  for (const FaceRef& r : refs) out.canonical.push_back(r.plane);
  return out;
}

// The exact solid a run decomposes instead of the rounded body, with what ties it to the body:
// `whole`, its exact piece (piece_of(const ExactSolid&, …)); `body_vertex`, per point of the
// solid the body vertex it rounds to (−1: none); `face_plane`, per body face the
// (canonical plane, sign) of the solid's triangles that round into it.
struct SolidInput {
  Piece whole;
  std::vector<int> body_vertex;
  std::vector<std::pair<int, int>> face_plane;
};

// `solid`: decomposed instead of the rounded body. The model (Decomposition::planes,
// piece_planes) is then the solid's face planes, with the body's vertices and faces on them by
// construction through `solid`'s maps.
Decomposition run(const Body& body, const DecomposeOptions& options, Context& ctx,
                  std::optional<SolidInput> solid = std::nullopt) {
  const bool from_solid = solid.has_value();
  if (!from_solid && !options.verify && is_convex(body)) {
    // Convex input returns at once: O(V + E) (mesh/convexity.h), before the exact pieces.
    Decomposition out;
    out.pieces.push_back(body);
    out.exact_volume = body.volume();
    return out;
  }
  Piece whole = from_solid ? std::move(solid->whole) : piece_of(body, ctx);
  std::vector<Piece> open = components(whole.pts, whole.tris);
  std::vector<Piece> done;
  Decomposition out;
  if (!ctx.exact_planes && open.size() == 1 && reflex_edges(ctx, open[0]).empty()) {
    // Convex input: one piece, the body itself, unchanged. No reflex edge under the rounding
    // guard is not convexity: a fold within the guard (a nearly flat triangle soup) is hidden
    // by it, and the body is not convex by the exact test. Then the guard's model of the input
    // is wrong and the input itself is decomposed (decompose()).
    if (!is_convex(body))
      throw InternalError("decompose: no reflex edge within the rounding guard, but not convex");
    out.pieces.push_back(body);
    out.verified = options.verify;
    out.exact_volume = body.volume();
    if (options.verify) out.exact_volume = CGAL::to_double(exact_volume6(whole) / 6);
    return out;
  }
  while (!open.empty()) {
    // One round: every open piece is either convex (done) or cut once. Pieces are handled
    // independently, in parallel; results are gathered in order, so the outcome does not
    // depend on the number of threads.
    std::vector<std::vector<Piece>> next(open.size());
    std::vector<char> convex(open.size(), 0);
    parallel_for(open.size(), options.threads, [&](size_t i) {
      std::vector<Reflex> reflex = reflex_edges(ctx, open[i]);
      if (reflex.empty()) {
        convex[i] = 1;
        return;
      }
      Sides sides = split_or_retry(ctx, open[i], reflex);
      // The exact pieces drop the points the cut left on straight runs and inside faces, so
      // that a piece's size stays its own complexity rather than its ancestors' cuts'.
      for (Piece& p : sides.below) {
        if (!ctx.floating && ctx.simplify) simplify(ctx, p);
        next[i].push_back(std::move(p));
      }
      for (Piece& p : sides.above) {
        if (!ctx.floating && ctx.simplify) simplify(ctx, p);
        next[i].push_back(std::move(p));
      }
    });
    std::vector<Piece> still_open;
    for (size_t i = 0; i < open.size(); ++i) {
      if (convex[i]) {
        done.push_back(std::move(open[i]));
      } else {
        ++out.cuts;
        for (Piece& p : next[i]) still_open.push_back(std::move(p));
      }
    }
    open = std::move(still_open);
    const int total = static_cast<int>(done.size() + open.size());
    if (total > options.max_pieces)
      throw InvalidInput("decompose: more than " + std::to_string(options.max_pieces) +
                         " pieces needed (" + std::to_string(total) + " so far)");
    if (options.progress &&
        !options.progress(static_cast<int>(done.size()), static_cast<int>(open.size())))
      throw DecompositionCancelled();
  }
  for (const Piece& p : done)
    HEDRA_EXPENSIVE_ASSERT(reflex_edges(ctx, p).empty(), "decompose: a finished piece is not convex");
  auto canonical = [&] {
    std::sort(done.begin(), done.end(), [](const Piece& a, const Piece& b) {
      return smallest_point(a) < smallest_point(b);
    });
  };
  canonical();
  if (options.merge) {
    done = merge_pieces(ctx, std::move(done), out.merges);
    canonical();
  }
  if (options.verify) {
    EK::FT::ET total = 0;  // exact sum, not a lazy chain (see exact_volume6)
    bool all_convex = true;
    for (const Piece& p : done) {
      total += CGAL::exact(exact_volume6(p));
      all_convex = all_convex && reflex_edges(ctx, p).empty();
    }
    const EK::FT input = exact_volume6(whole);
    out.verified = all_convex && total == CGAL::exact(input);
    out.exact_volume = CGAL::to_double(input / 6);
  }
  // Rounded once, here; a piece thinner than rounding everywhere is left out and counted. The
  // floating-point variant keeps its plain rounding, so its broken pieces still show.
  std::vector<const Piece*> kept;
  for (const Piece& p : done) {
    if (ctx.floating) {
      out.pieces.push_back(body_of(p));
    } else if (std::optional<Body> b = rounded_piece(p)) {
      out.piece_planes.push_back(face_planes(p));
      out.pieces.push_back(std::move(*b));
      kept.push_back(&p);
    } else {
      ++out.degenerate_pieces;
    }
  }
  // The model the cuts were decided in, for exact incidence with the pieces' faces.
  if (!ctx.floating) {
    InputPlanes& m = out.planes;
    m.support = ctx.support;
    // Stored in the order whose orient3d agrees with the CGAL plane's side (checked on a point
    // far off it, so the check is not close).
    for (size_t c = 0; c < m.support.size(); ++c) {
      auto& t = m.support[c];
      const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
      if (!(n.squaredNorm() > 0)) continue;  // split()'s plane by coefficients: never here
      const Vec3 off = t[0] + n.normalized() * ((t[1] - t[0]).norm() + (t[2] - t[0]).norm());
      const bool positive = ctx.planes[c].oriented_side(P3(off.x(), off.y(), off.z())) == CGAL::ON_POSITIVE_SIDE;
      if (positive != (orient3d(t[0], t[1], t[2], off) == Sign::Positive)) std::swap(t[1], t[2]);
    }
    m.approx = ctx.approx;
    m.guard = ctx.guard;
    if (!from_solid) {
      for (const Point& pt : whole.pts) m.vertex_planes.push_back(pt.on);
      m.face_planes.resize(static_cast<size_t>(body.face_count()));
      const auto& triangles = body.triangles();
      for (size_t t = 0; t < triangles.size(); ++t) {
        auto& fp = m.face_planes[static_cast<size_t>(triangles[t].face)];
        const std::pair<int, int> c(whole.tris[t].plane, whole.tris[t].sign);
        if (!std::binary_search(fp.begin(), fp.end(), c)) fp.insert(std::upper_bound(fp.begin(), fp.end(), c), c);
      }
    } else if (solid->body_vertex.empty() && whole.pts.size() != static_cast<size_t>(body.vertex_count())) {
      // Not tied to the body's vertices (never by ExactSolid's contract): no model, and the
      // consumers decide incidence within rounding (as for a decomposition that gave none).
      m = InputPlanes{};
      out.piece_planes.clear();
    } else {
      // The solid's model of the rounded body: a vertex on the planes of the corner it rounds,
      // a face on the plane of the triangles that round into it. The planes no three doubles
      // support get their exact coefficients (once each: the pieces share them).
      m.vertex_planes.assign(static_cast<size_t>(body.vertex_count()), {});
      for (size_t w = 0; w < whole.pts.size(); ++w) {
        const int v = solid->body_vertex.empty() ? static_cast<int>(w) : solid->body_vertex[w];
        if (v >= 0 && v < body.vertex_count()) m.vertex_planes[static_cast<size_t>(v)] = whole.pts[w].on;
      }
      m.face_planes.assign(static_cast<size_t>(body.face_count()), {});
      for (size_t f = 0; f < solid->face_plane.size() && f < m.face_planes.size(); ++f)
        if (solid->face_plane[f].first >= 0) m.face_planes[f].push_back(solid->face_plane[f]);
      m.exact.resize(m.support.size());
      parallel_chunks(m.support.size(), 64, [&](size_t, size_t lo, size_t hi) {
        for (size_t c = lo; c != hi; ++c) {
          const auto& t = m.support[c];
          if ((t[1] - t[0]).cross(t[2] - t[0]).squaredNorm() > 0) continue;
          m.exact[c] = plane_of_lazy(ctx.planes[c], false);
        }
      });
    }
    // The exact pieces as planes, in parallel (independent pieces; exact arithmetic only). A
    // piece that is not exactly convex (an ulp fold of the guarded run) gets none: its
    // consumers keep the rounded piece.
    if (options.exact_pieces) out.exact_pieces.resize(kept.size());
    if (options.exact_pieces) parallel_chunks(kept.size(), 16, [&](size_t, size_t lo, size_t hi) {
      for (size_t i = lo; i != hi; ++i)
        if (std::optional<ExactConvex> e = exact_convex(ctx, m, *kept[i])) out.exact_pieces[i] = std::move(*e);
    });
  }
  return out;
}

}  // namespace

bool InputPlanes::on(int c, int v, const Vec3& p) const {
  const std::vector<int>& by_construction = vertex_planes[static_cast<size_t>(v)];
  if (std::binary_search(by_construction.begin(), by_construction.end(), c)) return true;
  if (side(c, p) == Sign::Zero) return true;
  // decompose's side(): an input vertex within the guard of a plane is on it.
  return guard > 0 && std::abs(approx[static_cast<size_t>(c)].value(p)) <= guard;
}

Sign InputPlanes::side(int c, const Vec3& p) const {
  if (static_cast<size_t>(c) < exact.size() && exact[static_cast<size_t>(c)].by_exact())
    return side_of_plane(exact[static_cast<size_t>(c)], p);
  const std::array<Vec3, 3>& s = support[static_cast<size_t>(c)];
  return orient3d(s[0], s[1], s[2], p);
}

Sign InputPlanes::side_along(int c, const Vec3& d) const {
  if (static_cast<size_t>(c) < exact.size() && exact[static_cast<size_t>(c)].by_exact())
    return direction_sign(exact[static_cast<size_t>(c)], d);
  const std::array<Vec3, 3>& s = support[static_cast<size_t>(c)];
  return orient_direction(s[0], s[1], s[2], d);
}

Decomposition decompose(const Body& body, const DecomposeOptions& options) {
  // First with the rounding guard: faces coplanar within rounding (a rotated body) share one
  // plane and input vertices within rounding of a plane count as on it, which keeps the piece
  // count of a rotated body its aligned twin's. Those coincidences are a model of the input,
  // not the input: when the input has real features at the guard's scale (a triangle soup
  // perturbed by ~1e-13 of its size), the model can contradict itself — a reflex edge whose
  // plane has the piece's other vertices below it only within the guard, so no cut exists
  // ("the plane of a reflex edge does not cut its piece"). Then the input itself is
  // decomposed: exact planes of its triangles, every side the exact predicate, which cannot
  // contradict itself and so never fails on a valid body.
  // Before both, the same with pieces simplified after every cut (simplify(): what makes
  // inputs with many reflex edges near-linear). Where that run fails (so far only on
  // self-touching slivers of rotated float32 soups), the two runs without it follow, so the
  // outcome is never worse than without simplification.
  // A Boolean's result keeps the exact solid it rounds: where that solid's faces are exactly
  // planar, it is what is decomposed (exact planes, nothing rounded before the pieces); where
  // they are planar only within rounding (a tessellated sphere's share), the rounded body, as
  // any other. A convex body comes back as it is (run()), not as its solid's rounded piece.
  // Where the Boolean rounded no corner (ExactSolid::rounded), its body is the solid exactly,
  // and a move of it a moved double body like any other (the rounding guard below): only what
  // the Boolean rounded needs the solid, and lazy exact corners everywhere cost 3–4× the
  // guarded run on a rotated body's doubles.
  // A moved body's exact image (a pending solid) is the fallback of a guarded run that makes
  // more than 2·V + 1024 exact cut points for V vertices. A large face folded by the rounding
  // of the move (the cap of a rotated star prism) is many triangles with planes of their own
  // there, which every cut crosses: the cut points grew quadratically (a rotated 200-point
  // star prism: 38 869 of them, 6.5 s), where the image, whose faces are exactly planar, makes
  // 1392 (0.22 s). On the benchmark's rotated shapes the guarded run stays under the budget
  // (at most 563 cut points, the rotated plate with 10 × 10 holes), and stays the faster.
  // A body read from a file whose faces are planar only within rounding (a rotated part) has no
  // solid of its own: its plane solid (core/exact_solid.h, the guarded model made exact) stands in
  // for it where a moved body's exact image would be used — first where exact pieces are
  // preferred, else past the guarded run's cut budget — made at most once.
  std::shared_ptr<const ExactSolid> exact_solid = body.exact_solid();
  const bool convex = is_convex(body);
  const bool stands_in = !exact_solid && options.from_exact_solid && !body.faces_off_plane().empty() &&
                         !body.two_sided() && !convex;
  bool tried = false;
  const auto usable = [&] {
    if (stands_in && !tried) {
      exact_solid = plane_solid(body);
      tried = true;
    }
    return exact_solid && options.from_exact_solid && !convex;
  };
  auto from_solid = [&]() -> std::optional<Decomposition> {
    if (!usable()) return std::nullopt;
    for (bool simplified : {true, false}) {
      try {
        Context ctx;
        ctx.exact_planes = true;
        ctx.simplify = simplified;
        const ExactSolid& made = materialized(*exact_solid);
        SolidInput input;
        std::optional<Piece> whole = piece_of(made, body.scale(), ctx, &input.face_plane);
        if (!whole) return std::nullopt;
        input.whole = std::move(*whole);
        input.body_vertex = made.body_vertex;
        Decomposition out = run(body, options, ctx, std::move(input));
        out.from_exact_solid = true;
        if (!options.verify || out.verified) return out;
      } catch (const InternalError&) {
      }
    }
    return std::nullopt;
  };
  if (options.prefer_exact_solid || (exact_solid && exact_solid->rounded))
    if (std::optional<Decomposition> out = from_solid()) return std::move(*out);
  // The plane solid's corners are deeper than an image's (three planes meet in each), so its
  // cuts cost more: a larger budget (the rotated plate with 10 × 10 holes read back, 2608
  // vertices: the guarded run in 1.4 s, the plane solid after the smaller budget 2.8 s; a
  // 400-point star prism read back: the guarded run 112 s, the plane solid after this budget
  // 3.5 s).
  const size_t v = body.vertices().size();
  size_t budget = stands_in ? 8 * v + 4096
                  : exact_solid && !exact_solid->rounded && options.from_exact_solid && !convex ? 2 * v + 1024
                                                                                                : 0;
  for (bool simplified : {true, false}) {
    for (bool again = true; again;) {
      again = false;
      try {
        Context ctx;
        ctx.simplify = simplified;
        ctx.cut_budget = budget;
        Decomposition out = run(body, options, ctx);
        if (!options.verify || out.verified) return out;
      } catch (const CutBudgetExceeded&) {
        if (std::optional<Decomposition> out = from_solid()) return std::move(*out);
        budget = 0;
        again = true;  // the same run without the budget
      } catch (const InternalError&) {
      }
    }
  }
  Context ctx;
  ctx.exact_planes = true;
  ctx.simplify = false;
  return run(body, options, ctx);
}

std::vector<Body> merge_convex(const std::vector<Body>& pieces, int* merges) {
  // The pieces share one set of canonical planes (faces of different pieces on one plane
  // within rounding are one plane), so "on the shared plane" is decided consistently.
  Context ctx;
  std::vector<Piece> exact;
  std::vector<Body> out;
  for (const Body& body : pieces) {
    if (is_convex(body))
      exact.push_back(piece_of(body, ctx));
    else
      out.push_back(body);  // not convex after rounding (CGAL's slivers): left as it is
  }
  int count = 0;
  exact = merge_pieces(ctx, std::move(exact), count);
  if (merges) *merges = count;
  std::sort(exact.begin(), exact.end(), [](const Piece& a, const Piece& b) {
    return smallest_point(a) < smallest_point(b);
  });
  for (const Piece& p : exact)
    if (std::optional<Body> b = rounded_piece(p)) out.push_back(std::move(*b));
  return out;
}

namespace internal {

Decomposition decompose_with_epsilon(const Body& body, double epsilon, const DecomposeOptions& options) {
  Context ctx;
  ctx.floating = true;
  ctx.epsilon = epsilon * body.scale();
  return run(body, options, ctx);
}

}  // namespace internal

}  // namespace hedra
