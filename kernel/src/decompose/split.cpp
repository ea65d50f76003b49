// Exact plane splitting (hedra/decompose/split.h) and the exact-piece machinery the convex
// decomposition shares (split_internal.h): canonical planes, pieces from bodies, connected
// components, caps triangulated by a constrained Delaunay triangulation, and back to bodies.
#include "hedra/decompose/split.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <type_traits>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "core/rational_predicates.h"
#include "decompose/split_internal.h"
#include "hedra/core/error.h"
#include "hedra/core/predicates.h"
#include "hedra/core/tolerance.h"
#include "hedra/mesh/merge_coplanar.h"

namespace hedra {
namespace internal {

namespace {

// The point's coordinates, where they are doubles (their intervals are points).
bool as_doubles(const P3& p, Vec3& out) {
  const auto& a = p.approx();
  if (a.x().inf() != a.x().sup() || a.y().inf() != a.y().sup() || a.z().inf() != a.z().sup()) return false;
  out = Vec3(a.x().inf(), a.y().inf(), a.z().inf());
  return true;
}

}  // namespace

// Side of a point with respect to canonical plane `id`: +1 outside (positive side), −1, or 0.
// Zero when the point lies on the plane by construction (symbolic), when the exact predicate
// says so, or — for input vertices only — when rounded input coordinates put it within the
// rounding guard of the plane (a rotated body's coplanar faces).
int side(const Context& ctx, const Point& pt, int id) {
  if (ctx.floating) {
    const Vec3 p(CGAL::to_double(pt.p.x()), CGAL::to_double(pt.p.y()), CGAL::to_double(pt.p.z()));
    const double v = ctx.approx[id].value(p);
    return v > ctx.epsilon ? 1 : (v < -ctx.epsilon ? -1 : 0);
  }
  if (std::binary_search(pt.on.begin(), pt.on.end(), id)) return 0;
  // A point with double coordinates (an input vertex, most cut points of an axis-aligned body)
  // and a plane through three input vertices: orient3d on doubles (a static filter, exact
  // after), the same sign as the exact plane's, without the interval stage's rounding-mode
  // switches or rational arithmetic.
  const auto& sp = ctx.support[id];
  Vec3 x;
  int s;
  if (sp[0] != sp[1] && (pt.origin >= 0 || as_doubles(pt.p, x)))
    s = static_cast<int>(orient3d(sp[0], sp[1], sp[2], pt.origin >= 0 ? pt.input : x));
  else
    s = static_cast<int>(oriented_side_3(ctx.planes[id], pt.p));  // integers, no gcd
  if (s == 0) return 0;
  if (ctx.guard > 0 && pt.origin >= 0 && std::abs(ctx.approx[id].value(pt.input)) <= ctx.guard) return 0;
  return s;
}

void add_on_sorted(std::vector<int>& ids, int id) {
  auto it = std::lower_bound(ids.begin(), ids.end(), id);
  if (it == ids.end() || *it != id) ids.insert(it, id);
}

void add_on(Point& pt, int id) { add_on_sorted(pt.on, id); }

namespace {

// Tri::own of a triangle with corners v on canonical plane `plane`: null when every corner lies
// on it exactly, else the exact plane of the corners.
const PL* own_plane(const Context& ctx, const std::vector<Point>& pts, const std::array<int, 3>& v, int plane) {
  for (int w : v)
    if (std::binary_search(pts[w].loose.begin(), pts[w].loose.end(), plane))
      return ctx.keep_own_plane(pts[v[0]].p, pts[v[1]].p, pts[v[2]].p);
  return nullptr;
}

}  // namespace

// ---- From a body ---------------------------------------------------------------------------

namespace {

// The planes met before whose unit normal lies within `eps` (per component) of n or −n,
// ascending; every plane when eps is not small against the cells (NormalIndex).
std::vector<int> planes_near(Context& ctx, const Vec3& n, double eps) {
  while (static_cast<size_t>(ctx.normals.size()) < ctx.approx.size())
    ctx.normals.add(ctx.approx[static_cast<size_t>(ctx.normals.size())].normal());
  return ctx.normals.near(n, eps, true);
}

P3 exact(const Vec3& p) { return P3(p.x(), p.y(), p.z()); }

// The canonical plane of the exact-planes runs through corners a, b, c (counter-clockwise seen
// from outside; `r` their doubles, rounded where they are not): a plane met before that holds
// all three exactly (either orientation; the normal index proposes candidates within `radius`
// of the corners' scale), else a new one, supported by `r` where `supported` (the corners are
// doubles) and by no triple otherwise. Returns (plane id, sign): sign +1 when the corners' outward
// normal is the plane's. Cost O(candidates) exact orientation tests.
std::pair<int, int> exact_plane_through(Context& ctx, const P3& a, const P3& b, const P3& c,
                                        const std::array<Vec3, 3>& r, double radius, bool supported) {
  const Vec3 n = (r[1] - r[0]).cross(r[2] - r[0]);
  const double longest = std::max({(r[1] - r[0]).norm(), (r[2] - r[1]).norm(), (r[0] - r[2]).norm()});
  const double height = n.norm() / longest;
  for (int g : planes_near(ctx, n.normalized(), 8 * radius / height + 1e-9)) {
    const PL& plane = ctx.planes[static_cast<size_t>(g)];
    if (plane.oriented_side(a) == CGAL::ON_ORIENTED_BOUNDARY && plane.oriented_side(b) == CGAL::ON_ORIENTED_BOUNDARY &&
        plane.oriented_side(c) == CGAL::ON_ORIENTED_BOUNDARY)
      return {g, CGAL::is_positive(CGAL::cross_product(b - a, c - a) * plane.orthogonal_vector()) ? 1 : -1};
  }
  const int group = static_cast<int>(ctx.planes.size());
  ctx.planes.emplace_back(a, b, c);
  ctx.approx.push_back(Plane::through(r[0], n.normalized()));
  ctx.support.push_back(supported ? r : std::array<Vec3, 3>{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  return {group, 1};
}

// Context::exact_planes: the body's triangles, each on the exact plane through its corners;
// triangles share a canonical plane only when all their corners lie exactly on it (both
// orientations: pieces may meet a plane from either side). The normal index only proposes
// candidates (radius as in piece_of, never a decision); a missed candidate would give the
// same plane a second id, which changes no side. Cost O(T) exact orientation tests.
Piece exact_piece_of(const Body& body, Context& ctx) {
  const auto& v = body.vertices();
  Piece piece;
  piece.pts.resize(v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    piece.pts[i].p = exact(v[i]);
    piece.pts[i].origin = static_cast<int>(i);
    piece.pts[i].input = v[i];
  }
  const double radius = kRoundingPlanarity * body.scale();
  std::vector<size_t> flat;  // triangles with collinear corners (a straight run of a face)
  for (const Triangle& t : body.triangles()) {
    const P3 a = exact(v[t.v[0]]), b = exact(v[t.v[1]]), c = exact(v[t.v[2]]);
    if (CGAL::collinear(a, b, c)) {
      flat.push_back(piece.tris.size());
      piece.tris.push_back({t.v, -1, 1});
      continue;
    }
    const auto [group, sign] =
        exact_plane_through(ctx, a, b, c, {v[t.v[0]], v[t.v[1]], v[t.v[2]]}, radius, true);
    for (int w : t.v) add_on(piece.pts[static_cast<size_t>(w)], group);
    piece.tris.push_back({t.v, group, sign});
  }
  // A flat triangle lies on any plane through its line: it takes the plane (and side) of a
  // triangle of the same face whose plane holds its corners exactly.
  const auto& tris = body.triangles();
  for (size_t f : flat) {
    Tri& t = piece.tris[f];
    for (size_t u = 0; u < tris.size() && t.plane < 0; ++u) {
      if (tris[u].face != tris[f].face || piece.tris[u].plane < 0) continue;
      const PL& plane = ctx.planes[static_cast<size_t>(piece.tris[u].plane)];
      bool on = true;
      for (int w : t.v) on = on && plane.oriented_side(piece.pts[static_cast<size_t>(w)].p) == CGAL::ON_ORIENTED_BOUNDARY;
      if (on) t.plane = piece.tris[u].plane, t.sign = piece.tris[u].sign;
    }
    HEDRA_ASSERT(t.plane >= 0, "decompose: a flat triangle lies on no plane of its face");
    for (int w : t.v) add_on(piece.pts[static_cast<size_t>(w)], t.plane);
  }
  return piece;
}

}  // namespace

std::optional<Piece> piece_of(const ExactSolid& solid, double scale, Context& ctx,
                              std::vector<std::pair<int, int>>* face_plane) {
  Piece piece;
  piece.pts.resize(solid.points.size());
  std::vector<Vec3> r(solid.points.size());  // rounded, for the normal index only
  for (size_t i = 0; i < solid.points.size(); ++i) {
    Point& pt = piece.pts[i];
    pt.p = solid.points[i];
    pt.depth = as_doubles(pt.p, r[i]) ? 0 : 1;
    if (pt.depth) r[i] = rounded(pt.p);
  }
  std::map<int, std::vector<size_t>> by_face;  // face → its triangles, in order
  for (size_t t = 0; t < solid.triangles.size(); ++t) by_face[solid.triangles[t].face].push_back(t);
  const double radius = kRoundingPlanarity * scale;
  for (const auto& [face, tris] : by_face) {
    // The face's plane: through the corners of its first triangle that spans one.
    const ExactSolid::Tri* span = nullptr;
    for (size_t t : tris) {
      const auto& v = solid.triangles[t].v;
      if (!CGAL::collinear(solid.points[v[0]], solid.points[v[1]], solid.points[v[2]])) {
        span = &solid.triangles[t];
        break;
      }
    }
    if (!span) return std::nullopt;
    const P3 &a = solid.points[span->v[0]], &b = solid.points[span->v[1]], &c = solid.points[span->v[2]];
    const PL plane(a, b, c);  // oriented outwards: the triangle runs counter-clockwise outside
    for (size_t t : tris)
      for (int w : solid.triangles[t].v)
        if (plane.oriented_side(solid.points[w]) != CGAL::ON_ORIENTED_BOUNDARY) return std::nullopt;
    // Three corners with double coordinates support the plane as an input face's do (sides of
    // double points by orient3d, side()); else none, and sides are the lazy plane's.
    const bool doubles = !piece.pts[span->v[0]].depth && !piece.pts[span->v[1]].depth && !piece.pts[span->v[2]].depth;
    const auto [group, sign] =
        exact_plane_through(ctx, a, b, c, {r[span->v[0]], r[span->v[1]], r[span->v[2]]}, radius, doubles);
    if (face_plane && face >= 0) {
      if (face_plane->size() <= static_cast<size_t>(face)) face_plane->resize(static_cast<size_t>(face) + 1, {-1, 0});
      (*face_plane)[static_cast<size_t>(face)] = {group, sign};
    }
    for (size_t t : tris) {
      const auto& v = solid.triangles[t].v;
      for (int w : v) add_on(piece.pts[static_cast<size_t>(w)], group);
      piece.tris.push_back({v, group, sign});
    }
  }
  return piece;
}

// Groups the body's faces into canonical planes (coincident within the rounding guard) and
// builds the exact piece of the whole body.
Piece piece_of(const Body& body, Context& ctx) {
  if (ctx.exact_planes) return exact_piece_of(body, ctx);
  ctx.guard = std::max(ctx.guard, kRoundingPlanarity * body.scale());
  const auto& v = body.vertices();
  std::vector<int> group(body.face_count(), -1), sign(body.face_count(), 1);
  std::unordered_map<int, int> creator;  // canonical plane made here -> the face it came from
  for (int f = 0; f < body.face_count(); ++f) {
    const Plane outward = body.plane(f).flipped();
    // A plane that has the face's support triangle within the guard turns from the face's
    // normal by at most about 2·guard over the triangle's smallest height (4× for the face's
    // Newell normal and rounding): only planes with such normals can match. O(F) candidates
    // in all instead of O(F²) for bodies with many plane directions.
    const auto& t = body.support(f);
    const Vec3 &ta = v[t[0]], &tb = v[t[1]], &tc = v[t[2]];
    const double longest = std::max({(tb - ta).norm(), (tc - tb).norm(), (ta - tc).norm()});
    const double height = (tb - ta).cross(tc - ta).norm() / longest;
    const double eps = 8 * ctx.guard / height + 1e-9;
    for (int g : planes_near(ctx, outward.normal(), eps)) {
      if (group[f] >= 0) break;
      // A plane met before, from either side (pieces of merge_convex meet from both).
      const double dot = ctx.approx[g].normal().dot(outward.normal());
      if (std::abs(dot) < 0.5) continue;
      bool same = true;
      for (const auto& loop : body.faces()[f].loops)
        for (int w : loop) same = same && std::abs(ctx.approx[g].value(v[w])) <= ctx.guard;
      if (same) {
        group[f] = static_cast<int>(g);
        sign[f] = dot > 0 ? 1 : -1;
      }
    }
    if (group[f] < 0) {
      group[f] = static_cast<int>(ctx.planes.size());
      const auto& s = body.support(f);
      ctx.planes.emplace_back(P3(v[s[0]].x(), v[s[0]].y(), v[s[0]].z()),
                              P3(v[s[1]].x(), v[s[1]].y(), v[s[1]].z()),
                              P3(v[s[2]].x(), v[s[2]].y(), v[s[2]].z()));
      ctx.approx.push_back(outward);
      ctx.support.push_back({v[s[0]], v[s[1]], v[s[2]]});
      creator.emplace(group[f], f);
    }
  }
  Piece piece;
  piece.pts.resize(v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    piece.pts[i].p = P3(v[i].x(), v[i].y(), v[i].z());
    piece.pts[i].origin = static_cast<int>(i);
    piece.pts[i].input = v[i];
  }
  for (int f = 0; f < body.face_count(); ++f) {
    // Exactly on the canonical plane: the plane is its creator face's support plane and the
    // exact orient3d of the support triple and the vertex is zero. Otherwise only within the
    // guard (a coplanar-within-rounding face), recorded as loose.
    auto it = creator.find(group[f]);
    for (const auto& loop : body.faces()[f].loops)
      for (int w : loop) {
        Point& pt = piece.pts[w];
        if (std::binary_search(pt.on.begin(), pt.on.end(), group[f])) continue;
        add_on(pt, group[f]);
        bool exact_on;
        if (it != creator.end()) {
          const auto& s = body.support(it->second);
          exact_on = orient3d(v[s[0]], v[s[1]], v[s[2]], v[w]) == Sign::Zero;
        } else {
          exact_on = ctx.planes[group[f]].oriented_side(pt.p) == CGAL::ON_ORIENTED_BOUNDARY;
        }
        if (!exact_on) add_on_sorted(pt.loose, group[f]);
      }
  }
  for (const Triangle& t : body.triangles()) {
    const int g = group[t.face];
    piece.tris.push_back({t.v, g, sign[t.face], own_plane(ctx, piece.pts, t.v, g)});
  }
  return piece;
}

// ---- Components --------------------------------------------------------------------------

std::vector<Piece> components(const std::vector<Point>& pts, const std::vector<Tri>& tris) {
  const int n = static_cast<int>(tris.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::unordered_map<std::uint64_t, int> first;  // undirected edge -> triangle
  for (int t = 0; t < n; ++t)
    for (int i = 0; i < 3; ++i) {
      int a = tris[t].v[i], b = tris[t].v[(i + 1) % 3];
      auto [it, inserted] = first.emplace(key(std::min(a, b), std::max(a, b)), t);
      if (!inserted) {
        int x = find(t), y = find(it->second);
        if (x != y) parent[std::max(x, y)] = std::min(x, y);
      }
    }
  std::map<int, int> index;  // root -> component (in order of first triangle)
  std::vector<Piece> out;
  std::vector<std::vector<int>> remap;
  for (int t = 0; t < n; ++t) {
    int r = find(t);
    auto [it, inserted] = index.emplace(r, static_cast<int>(out.size()));
    if (inserted) {
      out.emplace_back();
      remap.emplace_back(pts.size(), -1);
    }
    Piece& piece = out[it->second];
    std::vector<int>& m = remap[it->second];
    Tri tri = tris[t];
    for (int& w : tri.v) {
      if (m[w] < 0) {
        m[w] = static_cast<int>(piece.pts.size());
        piece.pts.push_back(pts[w]);
      }
      w = m[w];
    }
    piece.tris.push_back(tri);
  }
  return out;
}

// ---- Caps --------------------------------------------------------------------------------

// Epeck with orientation and in-circle tests whose exact stage is in integers (no gcd per
// operation): core/rational_predicates.h.
using Gt = RationalTriangulationTraits;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, Gt>;
using Fb0 = CGAL::Constrained_triangulation_face_base_2<Gt>;
using Fb = CGAL::Triangulation_face_base_with_info_2<int, Gt, Fb0>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Gt, Tds, CGAL::No_constraint_intersection_requiring_constructions_tag>;

using Ct = CGAL::Constrained_triangulation_2<Gt, Tds, CGAL::No_constraint_intersection_requiring_constructions_tag>;

// The boundary segments (point ids) as closed loops, each starting at its smallest start (the
// same loops every run); nullopt where they are not simple closed loops (a point with two
// outgoing segments, or a walk that does not come back to its start). Cost O(n log n).
std::optional<std::vector<std::vector<int>>> simple_loops(const std::vector<std::pair<int, int>>& segments) {
  std::unordered_map<int, int> next;
  for (const auto& [a, b] : segments)
    if (!next.emplace(a, b).second) return std::nullopt;
  std::vector<int> starts;
  for (const auto& [a, b] : segments) starts.push_back(a);
  std::sort(starts.begin(), starts.end());
  std::unordered_set<int> seen;
  std::vector<std::vector<int>> loops;
  for (int s0 : starts) {
    if (seen.count(s0)) continue;
    std::vector<int> loop;
    for (int a = s0; !seen.count(a);) {
      seen.insert(a);
      loop.push_back(a);
      auto it = next.find(a);
      if (it == next.end()) return std::nullopt;
      a = it->second;
    }
    if (next.at(loop.back()) != s0) return std::nullopt;
    loops.push_back(std::move(loop));
  }
  return loops;
}

// Zero-area triangles closing boundary loops whose points all lie on one line: a fan of each
// loop, oriented so that it holds every boundary edge reversed (as fill_region's triangles do).
std::vector<std::array<int, 3>> flat_fan(const std::vector<std::pair<int, int>>& segments) {
  const auto loops = simple_loops(segments);
  if (!loops) HEDRA_UNREACHABLE("split: a cap of no area is not simple closed loops");
  std::vector<std::array<int, 3>> out;
  for (const std::vector<int>& loop : *loops) {
    if (loop.size() < 3) HEDRA_UNREACHABLE("split: a cap of no area has a loop of two points");
    for (size_t i = 1; i + 1 < loop.size(); ++i) out.push_back({loop[0], loop[i + 1], loop[i]});
  }
  return out;
}

// Triangles (counter-clockwise around the plane's normal) filling the region of the plane
// bounded by the given segments (point ids), by parity of constrained edges crossed. Tr is the
// constrained Delaunay triangulation (caps) or the plain constrained one (re-triangulated
// faces: orientation tests only, no in-circle tests on nearly cocircular corners).
template <class Tr>
std::vector<std::array<int, 3>> fill_region(const Context& ctx, int plane, const std::vector<Point>& pts,
                                            const std::vector<std::pair<int, int>>& segments) {
  const EK::Vector_3 n = ctx.planes[plane].orthogonal_vector();
  const Vec3 approx = Vec3(rounded(n.x()), rounded(n.y()), rounded(n.z()));  // the same axis every run
  int axis;
  approx.cwiseAbs().maxCoeff(&axis);
  int u = (axis + 1) % 3, w = (axis + 2) % 3;
  if (CGAL::is_negative(n[axis])) std::swap(u, w);
  Tr cdt;
  std::unordered_map<int, typename Tr::Vertex_handle> handle;
  auto vertex = [&](int id) {
    auto it = handle.find(id);
    if (it != handle.end()) return it->second;
    typename Tr::Vertex_handle h = cdt.insert(EK::Point_2(pts[id].p[u], pts[id].p[w]));
    h->info() = id;
    handle.emplace(id, h);
    return h;
  };
  if constexpr (std::is_same_v<Tr, Cdt>) {
    // All corners first, in CGAL's spatial order (Delaunay insertion in O(n log n) expected
    // flips), then the constraints: inserted one by one along the boundary, a run of nearly
    // collinear cut points made every insertion flip its way through the earlier ones, with
    // exact in-circle tests on nearly cocircular corners (a rotated star prism's caps).
    std::vector<std::pair<EK::Point_2, int>> corners;
    std::unordered_set<int> listed;
    for (const auto& [a, b] : segments)
      for (int id : {a, b})
        if (listed.insert(id).second) corners.emplace_back(EK::Point_2(pts[id].p[u], pts[id].p[w]), id);
    cdt.insert(corners.begin(), corners.end());
    for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) handle.emplace(v->info(), v);
  }
  try {
    for (const auto& [a, b] : segments) {
      const typename Tr::Vertex_handle va = vertex(a), vb = vertex(b);
      // Only the floating-point variant's rounded cut points can coincide (exact points made
      // by a cut are strictly inside their edge): a zero-length boundary edge, on which CGAL's
      // constraint insertion would crash.
      if (va == vb) HEDRA_UNREACHABLE("split: the cut's boundary has a zero-length edge");
      cdt.insert_constraint(va, vb);
    }
  } catch (const typename Tr::Intersection_of_constraints_exception&) {
    HEDRA_UNREACHABLE("split: the cut's boundary crosses itself");
  }
  // Corners all on one line: the cut meets the piece in a segment only, where the piece has
  // no thickness (a sliver of a rotated float32 soup whose faces coincide exactly there). The
  // boundary loops are closed by zero-area triangles, which keep the pieces closed and add no
  // volume (exact_convex() and body_of() treat them as joins only).
  if (cdt.dimension() < 2) return flat_fan(segments);
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::list<typename Tr::Face_handle> queue{cdt.infinite_face()};
  cdt.infinite_face()->info() = 0;
  while (!queue.empty()) {
    typename Tr::Face_handle f = queue.front();
    queue.pop_front();
    for (int i = 0; i < 3; ++i) {
      typename Tr::Face_handle g = f->neighbor(i);
      if (g->info() != -1) continue;
      g->info() = cdt.is_constrained({f, i}) ? 1 - f->info() : f->info();
      queue.push_back(g);
    }
  }
  std::vector<std::array<int, 3>> out;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->info() == 1)
      out.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  return out;
}

std::vector<std::array<int, 3>> cap_triangles(const Context& ctx, int plane, const std::vector<Point>& pts,
                                              const std::vector<std::pair<int, int>>& segments) {
  return fill_region<Cdt>(ctx, plane, pts, segments);
}

// Planes a and b are parallel (or the same). Exact.
bool parallel_planes(const Context& ctx, int a, int b) {
  return CGAL::cross_product(ctx.planes[a].orthogonal_vector(), ctx.planes[b].orthogonal_vector()) ==
         CGAL::NULL_VECTOR;
}

// Whether b lies strictly between a and c on a straight run of a cap on `plane`: all three lie
// exactly on `plane` and, by construction and exactly (not loose), on another canonical plane
// not parallel to it — so on one line — and b is strictly between a and c along it.
bool inside_run(const Context& ctx, int plane, const Point& a, const Point& b, const Point& c) {
  auto exact_on = [](const Point& p, int q) {
    return std::binary_search(p.on.begin(), p.on.end(), q) && !std::binary_search(p.loose.begin(), p.loose.end(), q);
  };
  if (!exact_on(a, plane) || !exact_on(b, plane) || !exact_on(c, plane)) return false;
  for (int q : b.on) {
    if (q == plane || !exact_on(a, q) || !exact_on(b, q) || !exact_on(c, q)) continue;
    if (!parallel_planes(ctx, plane, q)) return CGAL::collinear_are_strictly_ordered_along_line(a.p, b.p, c.p);
  }
  return false;
}

// The cap of an exact cut. Where the cut crosses a face made of many triangles, its boundary
// has long straight runs of cut points (all on the line where the cut meets that face's
// plane, known symbolically); triangulating them point by point costs exact in-circle and
// orientation tests on collinear points. Instead the loops are reduced to their corners, the
// corners triangulated (constrained Delaunay), and each run fanned into the cap triangle on
// its edge: from the opposite corner when it is that triangle's only edge with a run, else
// from the triangle's centroid (a point inside the cap face, which simplify() removes
// again). Falls back to cap_triangles() where the boundary is not simple loops. Appends
// centroids to pts.
std::vector<std::array<int, 3>> chained_cap(const Context& ctx, int plane, std::vector<Point>& pts,
                                            const std::vector<std::pair<int, int>>& segments) {
  // Closed walks from every start also rule out a point with two incoming segments.
  const auto loops = simple_loops(segments);
  if (!loops) return cap_triangles(ctx, plane, pts, segments);
  std::vector<std::pair<int, int>> corners;              // reduced segments
  std::unordered_map<std::uint64_t, std::vector<int>> run;  // corner segment -> points inside
  size_t inside = 0;
  for (const std::vector<int>& loop : *loops) {
    const size_t k = loop.size();
    std::vector<char> corner(k);
    int count = 0;
    for (size_t i = 0; i < k; ++i) {
      corner[i] = k < 4 || !inside_run(ctx, plane, pts[loop[(i + k - 1) % k]], pts[loop[i]], pts[loop[(i + 1) % k]]);
      count += corner[i];
    }
    if (count < 3) return cap_triangles(ctx, plane, pts, segments);
    size_t first = 0;
    while (!corner[first]) ++first;
    int from = loop[first];
    std::vector<int> between;
    for (size_t j = 1; j <= k; ++j) {
      const size_t i = (first + j) % k;
      if (!corner[i]) {
        between.push_back(loop[i]);
        continue;
      }
      corners.emplace_back(from, loop[i]);
      if (!between.empty()) {
        inside += between.size();
        run.emplace(key(from, loop[i]), std::move(between));
        between.clear();
      }
      from = loop[i];
    }
  }
  if (run.empty()) return cap_triangles(ctx, plane, pts, segments);  // as given: same insertion order
  std::vector<std::array<int, 3>> tris = cap_triangles(ctx, plane, pts, corners);
  std::vector<std::array<int, 3>> out;
  size_t used = 0;
  const size_t first_new = pts.size();
  for (const auto& t : tris) {
    // A cap triangle (counter-clockwise) meets the part below along the reverse of its edges:
    // its edge u -> w is the boundary segment w -> u, whose run goes from w to u.
    std::array<std::vector<int>, 3> edge;
    int with_run = 0, which = -1;
    for (int i = 0; i < 3; ++i) {
      const int u = t[i], w = t[(i + 1) % 3];
      edge[i].push_back(u);
      auto it = run.find(key(w, u));
      if (it != run.end()) {
        edge[i].insert(edge[i].end(), it->second.rbegin(), it->second.rend());
        used += it->second.size();
        ++with_run;
        which = i;
      }
    }
    if (with_run == 0) {
      out.push_back(t);
    } else if (with_run == 1) {
      std::vector<int> e = edge[which];
      e.push_back(t[(which + 1) % 3]);
      const int apex = t[(which + 2) % 3];
      for (size_t j = 0; j + 1 < e.size(); ++j) out.push_back({e[j], e[j + 1], apex});
    } else {
      Point m;
      m.p = CGAL::centroid(pts[t[0]].p, pts[t[1]].p, pts[t[2]].p);
      m.on = {plane};
      const int mid = static_cast<int>(pts.size());
      pts.push_back(std::move(m));
      std::vector<int> e;
      for (int i = 0; i < 3; ++i) e.insert(e.end(), edge[i].begin(), edge[i].end());
      e.push_back(t[0]);
      for (size_t j = 0; j + 1 < e.size(); ++j) out.push_back({e[j], e[j + 1], mid});
    }
  }
  if (used != inside) {  // a corner split a reduced segment: runs not all placed
    pts.resize(first_new);
    return cap_triangles(ctx, plane, pts, segments);
  }
  return out;
}

// ---- Split ---------------------------------------------------------------------------------

namespace {

// The exact point where edge ab crosses canonical plane `plane`, and its construction depth
// (Point::depth): the segment's intersection with the plane, kept as plain doubles (depth 0)
// where the interval of that construction is a point (most cut points of an axis-aligned
// body). Building such points as the intersection of three planes where the ends were made by
// chains of cuts was tried: it made no measurable difference once simplify() re-triangulates
// folded faces (Tri::own), and cost more than the segment on shallow ends.
std::pair<P3, int> cut_point_of(const Context& ctx, const Point& a, const Point& b, int plane) {
  auto hit = CGAL::intersection(EK::Segment_3(a.p, b.p), ctx.planes[plane]);
  const P3* x = hit ? boost::get<P3>(&*hit) : nullptr;
  HEDRA_ASSERT(x, "split: an edge with ends on both sides misses the plane");
  if (Vec3 d; as_doubles(*x, d)) return {P3(d.x(), d.y(), d.z()), 0};
  return {*x, std::max(a.depth, b.depth) + 1};
}

}  // namespace

Sides split_piece(const Context& ctx, const Piece& in, int plane) {
  Sides result;
  const int n = static_cast<int>(in.pts.size());
  std::vector<int> s(n);
  bool any_below = false, any_above = false;
  for (int i = 0; i < n; ++i) {
    s[i] = side(ctx, in.pts[i], plane);
    any_below |= s[i] < 0;
    any_above |= s[i] > 0;
  }
  if (!any_below || !any_above) {
    (any_above ? result.above : result.below).push_back(in);
    return result;
  }
  result.cut = true;
  std::vector<Point> pts = in.pts;
  for (int i = 0; i < n; ++i) {
    if (s[i] != 0 || std::binary_search(pts[i].on.begin(), pts[i].on.end(), plane)) continue;
    add_on(pts[i], plane);
    // Only an input vertex can be on the plane within the guard alone.
    if (!ctx.floating && ctx.guard > 0 && pts[i].origin >= 0 &&
        ctx.planes[plane].oriented_side(pts[i].p) != CGAL::ON_ORIENTED_BOUNDARY)
      add_on_sorted(pts[i].loose, plane);
  }
  std::unordered_map<std::uint64_t, int> cut_point;  // undirected edge -> new point
  auto crossing = [&](int a, int b) {
    const std::uint64_t k = key(std::min(a, b), std::max(a, b));
    auto it = cut_point.find(k);
    if (it != cut_point.end()) return it->second;
    const int lo = std::min(a, b), hi = std::max(a, b);  // same construction from both sides
    Point q;
    if (ctx.floating) {
      auto d = [](const P3& p) {
        return Vec3(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
      };
      const Vec3 pa = d(pts[lo].p), pb = d(pts[hi].p);
      const double va = ctx.approx[plane].value(pa), vb = ctx.approx[plane].value(pb);
      const Vec3 x = pa + (va / (va - vb)) * (pb - pa);
      q.p = P3(x.x(), x.y(), x.z());
    } else {
      std::tie(q.p, q.depth) = cut_point_of(ctx, pts[lo], pts[hi], plane);
      if (ctx.cut_budget && ctx.cut_points.fetch_add(1, std::memory_order_relaxed) >= ctx.cut_budget)
        throw CutBudgetExceeded{};
    }
    std::set_intersection(pts[lo].on.begin(), pts[lo].on.end(), pts[hi].on.begin(),
                          pts[hi].on.end(), std::back_inserter(q.on));
    add_on(q, plane);
    for (const std::vector<int>* loose : {&pts[lo].loose, &pts[hi].loose})
      for (int id : *loose)
        if (std::binary_search(q.on.begin(), q.on.end(), id)) add_on_sorted(q.loose, id);
    const int id = static_cast<int>(pts.size());
    pts.push_back(std::move(q));
    cut_point.emplace(k, id);
    return id;
  };

  std::vector<Tri> below, above;
  const EK::Vector_3 normal = ctx.planes[plane].orthogonal_vector();
  for (const Tri& t : in.tris) {
    const int a = s[t.v[0]], b = s[t.v[1]], c = s[t.v[2]];
    const int lo = std::min({a, b, c}), hi = std::max({a, b, c});
    if (hi <= 0 && lo < 0) { below.push_back(t); continue; }
    if (lo >= 0 && hi > 0) { above.push_back(t); continue; }
    if (lo == 0 && hi == 0) {
      // In the plane: with the solid below when the face looks the plane's way.
      bool looks_up;
      if (t.plane == plane) {
        looks_up = t.sign > 0;
      } else {
        const EK::Vector_3 tn = CGAL::cross_product(pts[t.v[1]].p - pts[t.v[0]].p,
                                                    pts[t.v[2]].p - pts[t.v[0]].p);
        looks_up = CGAL::is_positive(tn * normal);
      }
      (looks_up ? below : above).push_back(t);
      continue;
    }
    // Crossing: the parts on each side are convex polygons, fanned into triangles.
    std::vector<int> down, up;
    for (int i = 0; i < 3; ++i) {
      const int p = t.v[i], q = t.v[(i + 1) % 3];
      const int sp = s[p], sq = s[q];
      if (sp <= 0) down.push_back(p);
      if (sp >= 0) up.push_back(p);
      if ((sp < 0 && sq > 0) || (sp > 0 && sq < 0)) {
        const int x = crossing(p, q);
        down.push_back(x);
        up.push_back(x);
      }
    }
    for (size_t k = 1; k + 1 < down.size(); ++k) below.push_back({{down[0], down[k], down[k + 1]}, t.plane, t.sign, t.own});
    for (size_t k = 1; k + 1 < up.size(); ++k) above.push_back({{up[0], up[k], up[k + 1]}, t.plane, t.sign, t.own});
  }

  // Cap: the boundary of the part below lies in the plane; fill it.
  std::unordered_set<std::uint64_t> directed;
  for (const Tri& t : below)
    for (int i = 0; i < 3; ++i) directed.insert(key(t.v[i], t.v[(i + 1) % 3]));
  std::vector<std::pair<int, int>> boundary;
  for (const Tri& t : below)
    for (int i = 0; i < 3; ++i) {
      const int a = t.v[i], b = t.v[(i + 1) % 3];
      if (!directed.count(key(b, a))) boundary.emplace_back(a, b);
    }
  if (!boundary.empty()) {
    const auto cap = ctx.floating || !ctx.simplify ? cap_triangles(ctx, plane, pts, boundary)
                                                   : chained_cap(ctx, plane, pts, boundary);
    // A cap through an input vertex that is on the plane only within the guard is off the
    // plane near it. Where the cap already holds points made by chains of cuts (depth ≥ 2), its
    // triangles there get their own planes (Tri::own), so that simplify() can remove the
    // points later cuts leave on them; elsewhere the cap is one face that is never
    // re-triangulated, which is cheaper (own planes on every such cap made the rotated suite
    // shapes' decompositions 13–23 % slower).
    bool deep = false;
    for (const auto& [a, b] : boundary) deep = deep || pts[a].depth >= 2;
    for (const auto& tri : cap) {
      const PL* own = ctx.floating || !deep ? nullptr : own_plane(ctx, pts, tri, plane);
      below.push_back({tri, plane, 1, own});
      above.push_back({{tri[0], tri[2], tri[1]}, plane, -1, own});
    }
  }
  result.below = components(pts, below);
  result.above = components(pts, above);
  return result;
}

// ---- Simplification ----------------------------------------------------------------------

void simplify(const Context& ctx, Piece& piece) {
  const int n = static_cast<int>(piece.pts.size());
  const int nt = static_cast<int>(piece.tris.size());
  // A face: its plane, side and, for the parts of a triangle not exactly on its plane, that
  // triangle's plane (Tri::own; numbered from 1 here).
  using Code = std::int64_t;
  std::unordered_map<const PL*, int> own_id;
  std::vector<const PL*> owns{nullptr};
  for (const Tri& t : piece.tris)
    if (t.own && own_id.emplace(t.own, static_cast<int>(owns.size())).second) owns.push_back(t.own);
  auto code = [&](const Tri& t) {
    return (static_cast<Code>(2 * t.plane + (t.sign > 0 ? 0 : 1)) << 32) | static_cast<Code>(t.own ? own_id.at(t.own) : 0);
  };
  auto plane_of = [](Code g) { return static_cast<int>((g >> 32) / 2); };
  // Up to two faces around each vertex, and whether there are more.
  std::vector<std::array<Code, 2>> groups(n, {-1, -1});
  std::vector<char> many(n, 0);
  for (const Tri& t : piece.tris)
    for (int v : t.v) {
      const Code g = code(t);
      auto& gv = groups[v];
      if (gv[0] < 0 || gv[0] == g) gv[0] = g;
      else if (gv[1] < 0 || gv[1] == g) gv[1] = g;
      else many[v] = 1;
    }
  std::vector<char> removable(n, 0);
  std::map<std::pair<int, int>, bool> parallel;  // per pair of planes met at a vertex
  bool any = false;
  for (int v = 0; v < n; ++v) {
    if (many[v] || groups[v][0] < 0) continue;
    if (groups[v][1] >= 0) {
      const int a = plane_of(groups[v][0]), b = plane_of(groups[v][1]);
      if (a == b) continue;
      auto [it, fresh] = parallel.try_emplace({std::min(a, b), std::max(a, b)}, false);
      if (fresh) it->second = parallel_planes(ctx, a, b);
      if (it->second) continue;
    }
    // On the parts of a triangle off its plane, only points made by a chain of cuts: removing
    // the others costs more re-triangulation than it saves (rotated suite shapes 15–20 %
    // slower), and a point cut again is removed then.
    const auto folded = [&](Code g) { return g >= 0 && (g & 0xffffffff) != 0; };
    if ((folded(groups[v][0]) || folded(groups[v][1])) && piece.pts[v].depth < 2) continue;
    removable[v] = 1;
    any = true;
  }
  if (!any) return;
  // The triangles around a removable vertex must form one cycle (a manifold vertex) crossing
  // between its two faces exactly twice (one straight edge through it).
  struct Link {
    int v, x, y;
    Code g;
  };
  std::vector<Link> links;
  for (const Tri& t : piece.tris)
    for (int i = 0; i < 3; ++i)
      if (removable[t.v[i]]) links.push_back({t.v[i], t.v[(i + 1) % 3], t.v[(i + 2) % 3], code(t)});
  std::sort(links.begin(), links.end(), [](const Link& a, const Link& b) { return std::tie(a.v, a.x) < std::tie(b.v, b.x); });
  for (size_t lo = 0; lo < links.size();) {
    size_t hi = lo;
    while (hi < links.size() && links[hi].v == links[lo].v) ++hi;
    const int v = links[lo].v;
    bool ok = true;
    for (size_t i = lo + 1; i < hi && ok; ++i) ok = links[i].x != links[i - 1].x;
    size_t steps = 0, at = lo;
    int changes = 0;
    std::array<int, 2> ends{-1, -1};  // the two edges through v where the faces change
    while (ok) {
      const int y = links[at].y;
      const Code g = links[at].g;
      auto it = std::lower_bound(links.begin() + static_cast<std::ptrdiff_t>(lo), links.begin() + static_cast<std::ptrdiff_t>(hi), y,
                                 [](const Link& l, int x) { return l.x < x; });
      if (it == links.begin() + static_cast<std::ptrdiff_t>(hi) || it->x != y) ok = false;
      else {
        at = static_cast<size_t>(it - links.begin());
        if (links[at].g != g && changes < 2) ends[static_cast<size_t>(changes)] = y;
        changes += links[at].g != g;
        if (++steps > hi - lo) ok = false;
        if (at == lo) break;
      }
    }
    ok = ok && steps == hi - lo && changes == (groups[v][1] >= 0 ? 2 : 0);
    // On a straight edge, v lies strictly between its two neighbours along it (not the tip of
    // a fold of two faces that meet at a sliver's edge).
    if (ok && changes == 2)
      ok = CGAL::collinear_are_strictly_ordered_along_line(piece.pts[ends[0]].p, piece.pts[v].p, piece.pts[ends[1]].p);
    if (!ok) removable[v] = 0;
    lo = hi;
  }
  // Faces to re-triangulate: those with a removable vertex. Each must lie exactly on its plane
  // (no loose vertex) and have a simple boundary (one outgoing boundary edge per vertex);
  // otherwise its vertices stay, which can leave other faces with nothing to do: repeat.
  std::map<Code, std::vector<int>> face_tris;  // group -> triangles
  for (int t = 0; t < nt; ++t) face_tris[code(piece.tris[t])].push_back(t);
  std::map<Code, std::unordered_map<int, int>> boundary;  // group -> next along its loops
  std::set<Code> bad;
  for (bool again = true; again;) {
    again = false;
    std::set<Code> affected;
    for (int v = 0; v < n; ++v)
      if (removable[v])
        for (Code g : groups[v])
          if (g >= 0) affected.insert(g);
    for (Code g : affected) {
      if (bad.count(g) || boundary.count(g)) continue;
      bool good = true;
      std::unordered_set<std::uint64_t> directed;
      for (int t : face_tris[g]) {
        const Tri& tri = piece.tris[t];
        for (int i = 0; i < 3; ++i) {
          directed.insert(key(tri.v[i], tri.v[(i + 1) % 3]));
          const Point& p = piece.pts[tri.v[i]];
          if (!tri.own && std::binary_search(p.loose.begin(), p.loose.end(), tri.plane)) good = false;
        }
      }
      std::unordered_map<int, int> next;
      for (int t : face_tris[g]) {
        const Tri& tri = piece.tris[t];
        for (int i = 0; i < 3 && good; ++i) {
          const int a = tri.v[i], b = tri.v[(i + 1) % 3];
          if (!directed.count(key(b, a))) good = next.emplace(a, b).second;
        }
      }
      if (good) boundary.emplace(g, std::move(next));
      else bad.insert(g);
    }
    for (int v = 0; v < n; ++v)
      if (removable[v])
        for (Code g : groups[v])
          if (g >= 0 && bad.count(g)) removable[v] = 0, again = true;
  }
  std::set<Code> affected;
  for (int v = 0; v < n; ++v)
    if (removable[v])
      for (Code g : groups[v])
        if (g >= 0) affected.insert(g);
  if (affected.empty()) return;
  std::vector<Tri> tris;
  std::vector<char> replaced(nt, 0);
  std::vector<std::pair<int, int>> segments;
  for (Code g : affected) {
    const auto& next = boundary.at(g);
    std::vector<int> starts;
    for (const auto& [a, b] : next) starts.push_back(a);
    std::sort(starts.begin(), starts.end());
    std::unordered_set<int> seen;
    segments.clear();
    for (int s0 : starts) {
      if (seen.count(s0)) continue;
      std::vector<int> loop;
      for (int a = s0; !seen.count(a);) {
        seen.insert(a);
        if (!removable[a]) loop.push_back(a);
        auto it = next.find(a);
        if (it == next.end()) return;  // not a closed loop: leave the piece as it is
        a = it->second;
      }
      if (loop.size() < 3) return;
      for (size_t i = 0; i < loop.size(); ++i) segments.emplace_back(loop[i], loop[(i + 1) % loop.size()]);
    }
    const int plane = plane_of(g), sign = (g >> 32) % 2 ? -1 : 1;
    const PL* own = owns[static_cast<size_t>(g & 0xffffffff)];
    std::vector<std::array<int, 3>> filled;
    try {
      filled = fill_region<Ct>(ctx, plane, piece.pts, segments);
    } catch (const InternalError&) {
      return;
    }
    for (auto t : filled) {
      if (sign < 0) std::swap(t[1], t[2]);
      tris.push_back({t, plane, sign, own});
    }
    for (int t : face_tris[g]) replaced[t] = 1;
  }
  for (int t = 0; t < nt; ++t)
    if (!replaced[t]) tris.push_back(piece.tris[t]);
  // Still closed (each directed edge has its reverse) and every edge between two triangles
  // only (a new edge x–y must not join an edge x–y elsewhere), else left as it was.
  std::unordered_set<std::uint64_t> directed;
  for (const Tri& t : tris)
    for (int i = 0; i < 3; ++i)
      if (!directed.insert(key(t.v[i], t.v[(i + 1) % 3])).second) return;
  for (const Tri& t : tris)
    for (int i = 0; i < 3; ++i)
      if (!directed.count(key(t.v[(i + 1) % 3], t.v[i]))) return;
  Piece out;
  std::vector<int> remap(n, -1);
  for (Tri& t : tris)
    for (int& w : t.v) {
      if (remap[w] < 0) {
        remap[w] = static_cast<int>(out.pts.size());
        out.pts.push_back(std::move(piece.pts[w]));
      }
      w = remap[w];
    }
  out.tris = std::move(tris);
  piece = std::move(out);
}

// ---- Back to bodies ----------------------------------------------------------------------

Body body_of(const Piece& piece) {
  PolygonSoup soup;
  for (const Point& p : piece.pts) soup.vertices.push_back(rounded(p.p));
  std::vector<int> ids;
  for (const Tri& t : piece.tris) {
    soup.polygons.push_back({t.v[0], t.v[1], t.v[2]});
    ids.push_back(2 * t.plane + (t.sign > 0 ? 0 : 1));
  }
  std::vector<Body> bodies = bodies_from_soup(soup, ids);
  HEDRA_ASSERT(bodies.size() == 1, "decompose: a piece fell apart");
  return bodies[0];
}

}  // namespace internal

using namespace internal;

SplitResult split(const Body& body, const Plane& plane) {
  if (plane.normal().norm() == 0 || !plane.coefficients.allFinite())
    throw InvalidInput("split: the plane needs a finite, non-zero normal");
  Context ctx;
  Piece piece = piece_of(body, ctx);
  // The cutting plane as one more canonical plane, oriented so that "above" (value > 0) is
  // its positive side.
  const Vec4& k = plane.coefficients;
  ctx.planes.emplace_back(k[0], k[1], k[2], k[3]);
  ctx.approx.push_back(plane.normalized());
  ctx.support.push_back({Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  const int id = static_cast<int>(ctx.planes.size()) - 1;
  SplitResult result;
  for (Piece& part : components(piece.pts, piece.tris)) {
    Sides sides = split_piece(ctx, part, id);
    for (Piece& p : sides.below) simplify(ctx, p), result.below.push_back(body_of(p));
    for (Piece& p : sides.above) simplify(ctx, p), result.above.push_back(body_of(p));
  }
  return result;
}

}  // namespace hedra
