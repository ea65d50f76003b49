// Exact plane splitting and convex decomposition. Both live in this one translation unit
// because they share the exact machinery (CGAL Epeck points, constrained triangulation of
// caps) and CGAL-heavy code is kept in few translation units.
#include "hedra/decompose/decompose.h"
#include "decompose/decompose_internal.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <list>
#include <map>
#include <numeric>
#include <limits>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "hedra/mesh/convexity.h"
#include "hedra/core/error.h"
#include "hedra/mesh/merge_coplanar.h"
#include "hedra/decompose/split.h"
#include "hedra/core/tolerance.h"

namespace hedra {
namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using P3 = EK::Point_3;
using PL = EK::Plane_3;

// ---- Data --------------------------------------------------------------------------------

// Canonical planes, oriented outwards for input faces: a point strictly outside a face is on
// the plane's positive side.
struct Context {
  std::vector<PL> planes;
  std::vector<Plane> approx;  // unit-normal double planes, same orientation (for the guard)
  double guard = 0;           // rounding guard for input vertices (see side())
  // The floating-point variant: sides from double evaluation with a tolerance, cut points
  // computed in double; no symbolic incidence. Kept for the speed–accuracy comparison.
  bool floating = false;
  double epsilon = 0;  // absolute, in world units
};

struct Point {
  P3 p;
  std::vector<int> on;  // sorted ids of canonical planes the point lies on, by construction
  int origin = -1;      // input vertex id, or −1 for a point made by a cut
  Vec3 input = Vec3::Zero();  // the input's double coordinates (origin >= 0)
};

// A triangle on canonical plane `plane`; sign +1: its outward normal is the plane's normal.
struct Tri {
  std::array<int, 3> v;
  int plane;
  int sign;
};

struct Piece {
  std::vector<Point> pts;
  std::vector<Tri> tris;
};

std::uint64_t key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

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
  const CGAL::Oriented_side s = ctx.planes[id].oriented_side(pt.p);
  if (s == CGAL::ON_ORIENTED_BOUNDARY) return 0;
  if (pt.origin >= 0 && std::abs(ctx.approx[id].value(pt.input)) <= ctx.guard) return 0;
  return s == CGAL::ON_POSITIVE_SIDE ? 1 : -1;
}

void add_on(Point& pt, int id) {
  auto it = std::lower_bound(pt.on.begin(), pt.on.end(), id);
  if (it == pt.on.end() || *it != id) pt.on.insert(it, id);
}

// ---- From a body ---------------------------------------------------------------------------

// Groups the body's faces into canonical planes (coincident within the rounding guard) and
// builds the exact piece of the whole body.
Piece piece_of(const Body& body, Context& ctx) {
  ctx.guard = std::max(ctx.guard, kRoundingPlanarity * body.scale());
  const auto& v = body.vertices();
  std::vector<int> group(body.face_count(), -1), sign(body.face_count(), 1);
  for (int f = 0; f < body.face_count(); ++f) {
    const Plane outward = body.plane(f).flipped();
    for (size_t g = 0; g < ctx.approx.size() && group[f] < 0; ++g) {
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
    }
  }
  Piece piece;
  piece.pts.resize(v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    piece.pts[i].p = P3(v[i].x(), v[i].y(), v[i].z());
    piece.pts[i].origin = static_cast<int>(i);
    piece.pts[i].input = v[i];
  }
  for (int f = 0; f < body.face_count(); ++f)
    for (const auto& loop : body.faces()[f].loops)
      for (int w : loop) add_on(piece.pts[w], group[f]);
  for (const Triangle& t : body.triangles()) piece.tris.push_back({t.v, group[t.face], sign[t.face]});
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

using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, EK>;
using Fb0 = CGAL::Constrained_triangulation_face_base_2<EK>;
using Fb = CGAL::Triangulation_face_base_with_info_2<int, EK, Fb0>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<EK, Tds, CGAL::No_constraint_intersection_requiring_constructions_tag>;

// Triangles (counter-clockwise around the plane's normal) filling the region of the plane
// bounded by the given segments (point ids), by parity of constrained edges crossed.
std::vector<std::array<int, 3>> cap_triangles(const Context& ctx, int plane,
                                              const std::vector<Point>& pts,
                                              const std::vector<std::pair<int, int>>& segments) {
  const EK::Vector_3 n = ctx.planes[plane].orthogonal_vector();
  const Vec3 approx(CGAL::to_double(n.x()), CGAL::to_double(n.y()), CGAL::to_double(n.z()));
  int axis;
  approx.cwiseAbs().maxCoeff(&axis);
  int u = (axis + 1) % 3, w = (axis + 2) % 3;
  if (CGAL::is_negative(n[axis])) std::swap(u, w);
  Cdt cdt;
  std::unordered_map<int, Cdt::Vertex_handle> handle;
  auto vertex = [&](int id) {
    auto it = handle.find(id);
    if (it != handle.end()) return it->second;
    Cdt::Vertex_handle h = cdt.insert(EK::Point_2(pts[id].p[u], pts[id].p[w]));
    h->info() = id;
    handle.emplace(id, h);
    return h;
  };
  try {
    for (const auto& [a, b] : segments) cdt.insert_constraint(vertex(a), vertex(b));
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    throw std::logic_error("split: the cut's boundary crosses itself");
  }
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::list<Cdt::Face_handle> queue{cdt.infinite_face()};
  cdt.infinite_face()->info() = 0;
  while (!queue.empty()) {
    Cdt::Face_handle f = queue.front();
    queue.pop_front();
    for (int i = 0; i < 3; ++i) {
      Cdt::Face_handle g = f->neighbor(i);
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

// ---- Split ---------------------------------------------------------------------------------

struct Sides {
  std::vector<Piece> below, above;
  bool cut = false;  // false when the plane does not pass through the piece's interior
};

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
  for (int i = 0; i < n; ++i)
    if (s[i] == 0) add_on(pts[i], plane);
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
      auto hit = CGAL::intersection(EK::Segment_3(pts[lo].p, pts[hi].p), ctx.planes[plane]);
      const P3* x = hit ? boost::get<P3>(&*hit) : nullptr;
      if (!x) throw std::logic_error("split: an edge with ends on both sides misses the plane");
      q.p = *x;
    }
    std::set_intersection(pts[lo].on.begin(), pts[lo].on.end(), pts[hi].on.begin(),
                          pts[hi].on.end(), std::back_inserter(q.on));
    add_on(q, plane);
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
    for (size_t k = 1; k + 1 < down.size(); ++k) below.push_back({{down[0], down[k], down[k + 1]}, t.plane, t.sign});
    for (size_t k = 1; k + 1 < up.size(); ++k) above.push_back({{up[0], up[k], up[k + 1]}, t.plane, t.sign});
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
    for (const auto& tri : cap_triangles(ctx, plane, pts, boundary)) {
      below.push_back({tri, plane, 1});
      above.push_back({{tri[0], tri[2], tri[1]}, plane, -1});
    }
  }
  result.below = components(pts, below);
  result.above = components(pts, above);
  return result;
}

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
      if (it == owner.end()) throw std::logic_error("decompose: a piece is not closed");
      const Tri& t2 = piece.tris[it->second];
      if (t1.plane == t2.plane && t1.sign == t2.sign) continue;  // flat
      int apex = t2.v[0] + t2.v[1] + t2.v[2] - a - b;
      if (t1.sign * side(ctx, piece.pts[apex], t1.plane) > 0) out.push_back({a, b, t1.plane, t2.plane});
    }
  }
  return out;
}

// The plane on which the most reflex edges lie, then crossing the fewest triangles, then the
// smallest id: decided by exact sides and input order only, so rotating the body changes
// nothing.
int choose_cut(const Context& ctx, const Piece& piece, const std::vector<Reflex>& reflex) {
  std::vector<int> candidates;
  for (const Reflex& r : reflex) {
    candidates.push_back(r.p1);
    candidates.push_back(r.p2);
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  int best = -1, best_resolved = -1, best_crossed = 0;
  std::vector<int> s(piece.pts.size());
  for (int c : candidates) {
    for (size_t i = 0; i < piece.pts.size(); ++i) s[i] = side(ctx, piece.pts[i], c);
    int resolved = 0, crossed = 0;
    for (const Reflex& r : reflex) resolved += s[r.a] == 0 && s[r.b] == 0;
    for (const Tri& t : piece.tris) {
      const int lo = std::min({s[t.v[0]], s[t.v[1]], s[t.v[2]]});
      const int hi = std::max({s[t.v[0]], s[t.v[1]], s[t.v[2]]});
      crossed += lo < 0 && hi > 0;
    }
    if (resolved > best_resolved || (resolved == best_resolved && crossed < best_crossed)) {
      best = c;
      best_resolved = resolved;
      best_crossed = crossed;
    }
  }
  if (best_resolved <= 0) throw std::logic_error("decompose: no cut resolves a reflex edge");
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
      if (!sides.cut) throw std::logic_error("the plane of a reflex edge does not cut its piece");
      if (!ctx.floating && (!closed(sides.below) || !closed(sides.above)))
        throw std::logic_error("decompose: a piece is not closed");
      return sides;
    } catch (const std::logic_error& e) {
      if (first_error.empty()) first_error = e.what();
    }
  }
  throw std::logic_error(first_error);
}

// ---- Back to bodies ----------------------------------------------------------------------

Body body_of(const Piece& piece) {
  PolygonSoup soup;
  for (const Point& p : piece.pts)
    soup.vertices.emplace_back(CGAL::to_double(p.p.x()), CGAL::to_double(p.p.y()),
                               CGAL::to_double(p.p.z()));
  std::vector<int> ids;
  for (const Tri& t : piece.tris) {
    soup.polygons.push_back({t.v[0], t.v[1], t.v[2]});
    ids.push_back(2 * t.plane + (t.sign > 0 ? 0 : 1));
  }
  std::vector<Body> bodies = bodies_from_soup(soup, ids);
  if (bodies.size() != 1) throw std::logic_error("decompose: a piece fell apart");
  return bodies[0];
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
    if (convexity(body).convex) return body;
  } catch (const InvalidInput&) {
  }
  std::vector<P3> coords;
  for (const Point& p : piece.pts)
    coords.emplace_back(CGAL::to_double(p.p.x()), CGAL::to_double(p.p.y()), CGAL::to_double(p.p.z()));
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
    PolygonSoup soup;
    std::map<CGAL::Surface_mesh<P3>::Vertex_index, int> index;
    for (auto v : hull.vertices()) {
      index[v] = static_cast<int>(soup.vertices.size());
      const P3& p = hull.point(v);
      soup.vertices.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
    }
    // Plane of every hull triangle by exact comparison; a flat triangle (a point kept on a
    // hull edge) takes the plane of a neighbour and vanishes in its face.
    std::vector<PL> planes;
    std::vector<int> ids;
    std::map<std::pair<int, int>, size_t> edge_owner;
    for (auto f : hull.faces()) {
      std::vector<int> tri;
      std::vector<P3> pts;
      for (auto v : CGAL::vertices_around_face(hull.halfedge(f), hull)) {
        tri.push_back(index[v]);
        pts.push_back(hull.point(v));
      }
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
      if (bodies.size() == 1 && convexity(bodies[0]).convex) return bodies[0];
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

EK::FT exact_volume6(const Piece& piece) {
  EK::FT v = 0;
  for (const Tri& t : piece.tris) {
    const P3& a = piece.pts[t.v[0]].p;
    const P3& b = piece.pts[t.v[1]].p;
    const P3& c = piece.pts[t.v[2]].p;
    v += CGAL::determinant(a - CGAL::ORIGIN, b - CGAL::ORIGIN, c - CGAL::ORIGIN);
  }
  return v;
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
    if (middle < 0) throw std::logic_error("decompose: a merged hull has a repeated point");
    const std::array<int, 3> t = tris[flat];
    const int m = t[middle], p = t[(middle + 1) % 3], q = t[(middle + 2) % 3];
    size_t u = tris.size();
    int apex = -1;
    for (size_t k = 0; k < tris.size() && u == tris.size(); ++k)
      for (int i = 0; i < 3; ++i)
        if (tris[k][i] == q && tris[k][(i + 1) % 3] == p) u = k, apex = tris[k][(i + 2) % 3];
    if (u == tris.size()) throw std::logic_error("decompose: a merged hull is not closed");
    tris[u] = {q, m, apex};
    tris.push_back({m, p, apex});
    tris.erase(tris.begin() + static_cast<std::ptrdiff_t>(flat));
  }
  const size_t n = tris.size();
  std::vector<std::vector<int>> candidates(n);
  std::vector<int> plane(n, -1);
  std::vector<Vec3> normal(n);
  double scale = 0;
  for (const Point& p : pts)
    scale = std::max(scale, std::abs(CGAL::to_double(p.p.x())) + std::abs(CGAL::to_double(p.p.y())) +
                                std::abs(CGAL::to_double(p.p.z())));
  auto d = [](const P3& p) {
    return Vec3(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  };
  for (size_t t = 0; t < n; ++t) {
    const auto& v = tris[t];
    for (const auto& [id, sgn] : planes)
      if (!side(ctx, pts[v[0]], id) && !side(ctx, pts[v[1]], id) && !side(ctx, pts[v[2]], id))
        candidates[t].push_back(id);
    std::sort(candidates[t].begin(), candidates[t].end());
    candidates[t].erase(std::unique(candidates[t].begin(), candidates[t].end()), candidates[t].end());
    if (candidates[t].empty()) throw std::logic_error("decompose: a merged face lies on no face plane");
    normal[t] = (d(pts[v[1]].p) - d(pts[v[0]].p)).cross(d(pts[v[2]].p) - d(pts[v[0]].p));
    const bool thin = normal[t].norm() <= 1e-6 * scale * scale;
    if (candidates[t].size() == 1) {
      plane[t] = candidates[t][0];
    } else if (!thin) {
      double best = -1;
      for (int id : candidates[t]) {
        const double a = std::abs(normal[t].normalized().dot(ctx.approx[id].normal()));
        if (a > best) best = a, plane[t] = id;
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
  const int id = static_cast<int>(ctx.planes.size()) - 1;
  SplitResult result;
  for (Piece& part : components(piece.pts, piece.tris)) {
    Sides sides = split_piece(ctx, part, id);
    for (const Piece& p : sides.below) result.below.push_back(body_of(p));
    for (const Piece& p : sides.above) result.above.push_back(body_of(p));
  }
  return result;
}

namespace {

Decomposition run(const Body& body, const DecomposeOptions& options, Context& ctx) {
  Piece whole = piece_of(body, ctx);
  std::vector<Piece> open = components(whole.pts, whole.tris);
  std::vector<Piece> done;
  Decomposition out;
  if (open.size() == 1 && reflex_edges(ctx, open[0]).empty()) {
    // Convex input: one piece, the body itself, unchanged.
    out.pieces.push_back(body);
    out.verified = options.verify;
    out.exact_volume = body.volume();
    if (options.verify) out.exact_volume = CGAL::to_double(exact_volume6(whole) / 6);
    return out;
  }
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  while (!open.empty()) {
    // One round: every open piece is either convex (done) or cut once. Pieces are handled
    // independently, in parallel; results are gathered in order, so the outcome does not
    // depend on the number of threads.
    std::vector<std::vector<Piece>> next(open.size());
    std::vector<char> convex(open.size(), 0);
    arena.execute([&] {
      tbb::parallel_for(size_t(0), open.size(), [&](size_t i) {
        std::vector<Reflex> reflex = reflex_edges(ctx, open[i]);
        if (reflex.empty()) {
          convex[i] = 1;
          return;
        }
        Sides sides = split_or_retry(ctx, open[i], reflex);
        for (Piece& p : sides.below) next[i].push_back(std::move(p));
        for (Piece& p : sides.above) next[i].push_back(std::move(p));
      });
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
    EK::FT total = 0;
    bool all_convex = true;
    for (const Piece& p : done) {
      total += exact_volume6(p);
      all_convex = all_convex && reflex_edges(ctx, p).empty();
    }
    const EK::FT input = exact_volume6(whole);
    out.verified = all_convex && total == input;
    out.exact_volume = CGAL::to_double(input / 6);
  }
  // Rounded once, here; a piece thinner than rounding everywhere is left out and counted. The
  // floating-point variant keeps its plain rounding, so its broken pieces still show.
  for (const Piece& p : done) {
    if (ctx.floating) out.pieces.push_back(body_of(p));
    else if (std::optional<Body> b = rounded_piece(p)) out.pieces.push_back(std::move(*b));
    else ++out.degenerate_pieces;
  }
  return out;
}

}  // namespace

Decomposition decompose(const Body& body, const DecomposeOptions& options) {
  Context ctx;
  return run(body, options, ctx);
}

std::vector<Body> merge_convex(const std::vector<Body>& pieces, int* merges) {
  // The pieces share one set of canonical planes (faces of different pieces on one plane
  // within rounding are one plane), so "on the shared plane" is decided consistently.
  Context ctx;
  std::vector<Piece> exact;
  std::vector<Body> out;
  for (const Body& body : pieces) {
    if (convexity(body).convex)
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
