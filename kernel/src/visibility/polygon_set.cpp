// Exact 2D Boolean operations on polygon sets through CGAL (Epeck), behind the thin adapter of
// hedra/visibility/polygon_set.h. The only translation unit of hedra that instantiates CGAL's
// Boolean_set_operations_2 (it is slow to compile).
#include "hedra/visibility/polygon_set.h"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <iterator>

namespace hedra {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Polygon = CGAL::Polygon_2<K>;
using PolygonWithHoles = CGAL::Polygon_with_holes_2<K>;
using PolygonSet = CGAL::Polygon_set_2<K>;

// Simple rings of positive area only (CGAL's preconditions); counter-clockwise.
std::vector<Polygon> to_cgal(const std::vector<Ring2>& rings) {
  std::vector<Polygon> out;
  for (const Ring2& r : rings) {
    Polygon p;
    for (const Vec2& v : r)
      if (p.is_empty() || *(p.vertices_end() - 1) != K::Point_2(v.x(), v.y()))
        p.push_back(K::Point_2(v.x(), v.y()));
    while (p.size() > 1 && *p.vertices_begin() == *(p.vertices_end() - 1))
      p.erase(p.vertices_end() - 1);
    if (p.size() < 3 || !p.is_simple()) continue;
    const CGAL::Orientation o = p.orientation();
    if (o == CGAL::COLLINEAR) continue;
    if (o == CGAL::CLOCKWISE) p.reverse_orientation();
    out.push_back(std::move(p));
  }
  return out;
}

PolygonSet set_of(const std::vector<Ring2>& rings) {
  PolygonSet s;
  const std::vector<Polygon> polys = to_cgal(rings);
  if (!polys.empty()) s.join(polys.begin(), polys.end());
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

std::vector<UnionResult> cgal_coverage_levels(const std::vector<std::vector<Ring2>>& sets) {
  const size_t n = sets.size();
  std::vector<PolygonSet> level(n + 1);  // level[k]: covered by exactly k of the sets so far
  PolygonSet covered;
  for (const std::vector<Ring2>& rings : sets) {
    const PolygonSet s = set_of(rings);
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

}  // namespace hedra
