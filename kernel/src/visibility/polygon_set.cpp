// Exact 2D Boolean operations on polygon sets through CGAL (Epeck), behind the thin adapter of
// hedra/visibility/polygon_set.h. The only translation unit of hedra that instantiates CGAL's
// Boolean_set_operations_2 (it is slow to compile).
#include "hedra/visibility/polygon_set.h"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <algorithm>
#include <iterator>
#include <map>
#include <optional>

#include <boost/variant/get.hpp>

namespace hedra {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Polygon = CGAL::Polygon_2<K>;
using PolygonWithHoles = CGAL::Polygon_with_holes_2<K>;
using PolygonSet = CGAL::Polygon_set_2<K>;

// One ring as a CGAL polygon, counter-clockwise: false when it is not simple; an empty polygon
// when it has no area (fewer than three distinct vertices, or all on one line).
bool simple_polygon(const Ring2& r, Polygon& p) {
  p.clear();
  for (const Vec2& v : r)
    if (p.is_empty() || *(p.vertices_end() - 1) != K::Point_2(v.x(), v.y()))
      p.push_back(K::Point_2(v.x(), v.y()));
  while (p.size() > 1 && *p.vertices_begin() == *(p.vertices_end() - 1))
    p.erase(p.vertices_end() - 1);
  if (p.size() < 3) {
    p.clear();
    return true;
  }
  if (!p.is_simple()) return false;
  const CGAL::Orientation o = p.orientation();
  if (o == CGAL::COLLINEAR) p.clear();
  if (o == CGAL::CLOCKWISE) p.reverse_orientation();
  return true;
}

// Simple rings of positive area only (CGAL's preconditions); counter-clockwise.
std::vector<Polygon> to_cgal(const std::vector<Ring2>& rings) {
  std::vector<Polygon> out;
  Polygon p;
  for (const Ring2& r : rings)
    if (simple_polygon(r, p) && !p.is_empty()) out.push_back(p);
  return out;
}

PolygonSet set_of(const std::vector<Ring2>& rings) {
  PolygonSet s;
  const std::vector<Polygon> polys = to_cgal(rings);
  if (!polys.empty()) s.join(polys.begin(), polys.end());
  return s;
}

// A ring cut into loops where it passes a vertex twice. Loops of fewer than three vertices (a
// spike there and back) are dropped; the loops' odd-coverage region is the ring's.
template <class Point, class Less>
void pinch_loops(const std::vector<Point>& ring, std::vector<std::vector<Point>>& loops) {
  std::vector<Point> stack;
  std::map<Point, size_t, Less> at;  // vertex → its place in stack
  for (const Point& v : ring) {
    const auto it = at.find(v);
    if (it == at.end()) {
      at.emplace(v, stack.size());
      stack.push_back(v);
      continue;
    }
    const size_t j = it->second;
    std::vector<Point> loop(stack.begin() + static_cast<std::ptrdiff_t>(j), stack.end());
    for (size_t k = j + 1; k < stack.size(); ++k) at.erase(stack[k]);
    stack.resize(j + 1);
    if (loop.size() >= 3) loops.push_back(std::move(loop));
  }
  if (stack.size() >= 3) loops.push_back(std::move(stack));
}

struct LessVec2 {
  bool operator()(const Vec2& a, const Vec2& b) const {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  }
};
struct LessPoint {
  bool operator()(const K::Point_2& a, const K::Point_2& b) const {
    return CGAL::compare_xy(a, b) == CGAL::SMALLER;
  }
};

// A closed chain that crosses or touches itself (rounded crossings can make two of its edges
// cross by an ulp) made into simple loops: every point where two of its edges meet, other than
// their shared end, becomes a vertex of both (exact, not rounded), then the chain is cut where
// it passes a vertex twice. Candidate pairs come from a sweep over the edges' x-extents. False
// when a loop is still not simple (edges of the same chain overlapping in the same direction).
bool resolve_loop(const Ring2& ring, std::vector<Polygon>& out) {
  const size_t n = ring.size();
  std::vector<K::Segment_2> edges(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec2& a = ring[i];
    const Vec2& b = ring[(i + 1) % n];
    edges[i] = K::Segment_2(K::Point_2(a.x(), a.y()), K::Point_2(b.x(), b.y()));
  }
  std::vector<std::vector<K::Point_2>> on(n);  // points to insert into each edge
  const auto add = [&](size_t i, const K::Point_2& p) {
    if (p != edges[i].source() && p != edges[i].target()) on[i].push_back(p);
  };
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = i;
  const auto lo = [&](size_t i) { return std::min(ring[i].x(), ring[(i + 1) % n].x()); };
  const auto hi = [&](size_t i) { return std::max(ring[i].x(), ring[(i + 1) % n].x()); };
  std::sort(order.begin(), order.end(), [&](size_t i, size_t j) { return lo(i) < lo(j); });
  std::vector<size_t> active;
  for (size_t i : order) {
    const double x = lo(i);
    active.erase(std::remove_if(active.begin(), active.end(), [&](size_t j) { return hi(j) < x; }),
                 active.end());
    for (size_t j : active) {
      if (!CGAL::do_intersect(edges[i], edges[j])) continue;
      const auto hit = CGAL::intersection(edges[i], edges[j]);
      if (const K::Point_2* p = boost::get<K::Point_2>(&*hit)) {
        add(i, *p);
        add(j, *p);
      } else if (const K::Segment_2* sg = boost::get<K::Segment_2>(&*hit)) {
        for (const K::Point_2& end : {sg->source(), sg->target()}) {
          add(i, end);
          add(j, end);
        }
      }
    }
    active.push_back(i);
  }
  std::vector<K::Point_2> chain;
  for (size_t i = 0; i < n; ++i) {
    chain.push_back(edges[i].source());
    std::vector<K::Point_2>& pts = on[i];
    const K::Point_2& s = edges[i].source();
    std::sort(pts.begin(), pts.end(), [&](const K::Point_2& p, const K::Point_2& q) {
      return CGAL::compare_distance_to_point(s, p, q) == CGAL::SMALLER;
    });
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    chain.insert(chain.end(), pts.begin(), pts.end());
  }
  std::vector<std::vector<K::Point_2>> loops;
  pinch_loops<K::Point_2, LessPoint>(chain, loops);
  for (const std::vector<K::Point_2>& loop : loops) {
    Polygon p(loop.begin(), loop.end());
    if (!p.is_simple()) return false;
    const CGAL::Orientation o = p.orientation();
    if (o == CGAL::COLLINEAR) continue;
    if (o == CGAL::CLOCKWISE) p.reverse_orientation();
    out.push_back(std::move(p));
  }
  return true;
}

// The loops of one ring as simple polygons whose odd-coverage region is the ring's.
bool simple_loops(const Ring2& ring, std::vector<Polygon>& out) {
  std::vector<Ring2> loops;
  pinch_loops<Vec2, LessVec2>(ring, loops);
  Polygon p;
  for (const Ring2& loop : loops) {
    if (simple_polygon(loop, p)) {
      if (!p.is_empty()) out.push_back(p);
    } else if (!resolve_loop(loop, out)) {
      return false;
    }
  }
  return true;
}

// The region bounded by the rings of one union (its polygons' outer rings and holes, which meet
// only where they touch): the points inside an odd number of their simple loops, so one
// aggregated symmetric difference of the loops. None when a loop is not simple.
std::optional<PolygonSet> set_of(const std::vector<PolygonWithHoles2>& region) {
  std::vector<Polygon> loops;
  for (const PolygonWithHoles2& q : region) {
    if (!simple_loops(q.outer, loops)) return std::nullopt;
    for (const Ring2& h : q.holes)
      if (!simple_loops(h, loops)) return std::nullopt;
  }
  PolygonSet s;
  if (!loops.empty()) s.symmetric_difference(loops.begin(), loops.end());
  return s;
}

// The union of several regions.
std::optional<PolygonSet> set_of(const std::vector<std::vector<PolygonWithHoles2>>& regions) {
  PolygonSet s;
  for (const std::vector<PolygonWithHoles2>& r : regions) {
    std::optional<PolygonSet> one = set_of(r);
    if (!one) return std::nullopt;
    s.join(*one);
  }
  return s;
}

Ring2 to_ring(const Polygon& p) {
  Ring2 r;
  r.reserve(p.size());
  for (auto it = p.vertices_begin(); it != p.vertices_end(); ++it)
    r.emplace_back(CGAL::to_double(it->x()), CGAL::to_double(it->y()));
  return r;
}

UnionResult result_of(const PolygonSet& s, bool want_polygons) {
  UnionResult out;
  std::vector<PolygonWithHoles> pwh;
  s.polygons_with_holes(std::back_inserter(pwh));
  // Sums in the exact number type (a lazy sum over many polygons is a chain one node per term,
  // and its evaluation recurses once per term).
  K::FT::ET total = 0;
  for (const PolygonWithHoles& p : pwh) {
    K::FT::ET a = CGAL::exact(p.outer_boundary().area());
    for (auto h = p.holes_begin(); h != p.holes_end(); ++h) a += CGAL::exact(h->area());  // clockwise: < 0
    total += a;
    if (!want_polygons) continue;
    PolygonWithHoles2 q;
    q.outer = to_ring(p.outer_boundary());
    for (auto h = p.holes_begin(); h != p.holes_end(); ++h) q.holes.push_back(to_ring(*h));
    q.area = CGAL::to_double(a);
    out.polygons.push_back(std::move(q));
  }
  out.area = CGAL::to_double(total);
  return out;
}

}  // namespace

UnionResult cgal_union(const std::vector<Ring2>& polygons, bool want_polygons) {
  return result_of(set_of(polygons), want_polygons);
}

UnionResult cgal_difference(const std::vector<Ring2>& a, const std::vector<Ring2>& b) {
  PolygonSet s = set_of(a);
  if (!b.empty()) s.difference(set_of(b));
  return result_of(s, true);
}

std::optional<UnionResult> cgal_difference(const Region2& a, const std::vector<Region2>& b) {
  std::optional<PolygonSet> s = set_of(a);
  if (!s) return std::nullopt;
  if (!b.empty()) {
    const std::optional<PolygonSet> t = set_of(b);
    if (!t) return std::nullopt;
    s->difference(*t);
  }
  return result_of(*s, true);
}

namespace {

std::vector<UnionResult> coverage_levels(const std::vector<PolygonSet>& sets) {
  const size_t n = sets.size();
  std::vector<PolygonSet> level(n + 1);  // level[k]: covered by exactly k of the sets so far
  PolygonSet covered;
  for (const PolygonSet& s : sets) {
    for (size_t k = n; k >= 1; --k) {
      PolygonSet keep = level[k];
      keep.difference(s);
      if (k >= 2) {
        PolygonSet up = level[k - 1];
        up.intersection(s);
        keep.join(up);
      } else {
        PolygonSet fresh = s;
        fresh.difference(covered);
        keep.join(fresh);
      }
      level[k] = std::move(keep);
    }
    covered.join(s);
  }
  std::vector<UnionResult> out;
  for (size_t k = 1; k <= n; ++k) out.push_back(result_of(level[k], true));
  return out;
}

}  // namespace

std::vector<UnionResult> cgal_coverage_levels(const std::vector<std::vector<Ring2>>& sets) {
  std::vector<PolygonSet> s;
  for (const std::vector<Ring2>& rings : sets) s.push_back(set_of(rings));
  return coverage_levels(s);
}

std::optional<std::vector<UnionResult>> cgal_coverage_levels(const std::vector<Region2>& sets) {
  std::vector<PolygonSet> s;
  for (const Region2& polygons : sets) {
    std::optional<PolygonSet> one = set_of(polygons);
    if (!one) return std::nullopt;
    s.push_back(std::move(*one));
  }
  return coverage_levels(s);
}

}  // namespace hedra
