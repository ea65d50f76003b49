// Union of convex polygons in the plane with exact decisions: the core of cast shadows, where
// every shadow piece on a face is a convex polygon (a convex part of the face clipped against
// a convex occlusion volume).
//
// Method (Green's theorem on the union's boundary). An edge of piece i lies on the boundary of
// the union except where it runs strictly inside another piece j, or along an edge of j that
// coincides with it: in the same direction the piece with the smaller index keeps it, in
// opposite directions both lose it (the pieces meet there, the union goes on across). The
// remaining parts of all edges are exactly the union's boundary with the union on their
// left, so the area is Σ (P × Q) / 2 over them and chaining them end to end gives its rings.
// Decisions are exact for the double input: side of a line (orient2d), order of two crossings
// along an edge (a degree-4 polynomial sign, filtered then exact with CGAL::Mpzf), coincidence
// and direction of edges. Crossing points are rounded, each computed from its two edges in a
// canonical order so both edges get the same point. Cost O(e·m) for e edges that meet m other
// pieces (a uniform grid, each piece listed in the cells its polygon meets, finds them; an
// edge stops at the first piece that covers all of it), plus exact arithmetic only for
// near-degenerate configurations.
#pragma once

#include <vector>

#include "hedra/core/predicates.h"

namespace hedra {

using Ring2 = std::vector<Vec2>;

/// A polygon with holes in the plane: outer ring counter-clockwise, holes clockwise.
struct PolygonWithHoles2 {
  Ring2 outer;
  std::vector<Ring2> holes;
  double area = 0;
};

struct UnionResult {
  double area = 0;                          // of the union
  std::vector<PolygonWithHoles2> polygons;  // when asked for; disjoint
  /// False when the boundary parts could not be chained into rings (a point where three or
  /// more edges cross exactly, so rounded crossings differ): polygons then come from the exact
  /// CGAL union (area is unaffected: it never needs the chaining).
  bool chained = true;
};

/// The union of convex polygons, each counter-clockwise with positive area (consecutive
/// collinear vertices allowed, repeated consecutive vertices not).
/// \pre every piece convex and counter-clockwise. Cost as above.
UnionResult unite_convex(const std::vector<Ring2>& pieces, bool want_polygons);

/// Area of a polygon with holes (double shoelace, relative to the first vertex).
double polygon_area(const PolygonWithHoles2& polygon);
double ring_area(const Ring2& ring);

}  // namespace hedra

// The exact general operations (cgal_union, cgal_difference, cgal_coverage_levels).
#include "hedra/visibility/polygon_set.h"
