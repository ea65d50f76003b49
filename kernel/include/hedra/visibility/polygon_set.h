// Exact 2D Boolean operations on sets of polygons: CGAL's exact 2D Boolean operations
// (Epeck) behind a thin adapter on hedra's own 2D types (hedra/visibility/polygon_union.h).
// Slower than unite_convex; used where generality matters more than speed (differences,
// coverage counts, the chaining fallback of unite_convex) and as test oracles.
#pragma once

#include <optional>
#include <vector>

#include "hedra/visibility/polygon_union.h"

namespace hedra {

/// Exact union of simple polygons (either orientation). Cost O((n + k) log n) for k crossings.
UnionResult cgal_union(const std::vector<Ring2>& polygons, bool want_polygons);

/// Exact (∪ a) \ (∪ b) for two sets of simple polygons (either orientation, possibly
/// overlapping), with its exact area.
UnionResult cgal_difference(const std::vector<Ring2>& a, const std::vector<Ring2>& b);

/// Given L sets, each the union of its simple polygons, the regions covered by exactly k of
/// them for k = 1 … L: result[k − 1], with exact areas.
std::vector<UnionResult> cgal_coverage_levels(const std::vector<std::vector<Ring2>>& sets);

/// A region as unite_convex returns it: polygons with holes whose rings meet only where they
/// touch (at a vertex, or a vertex on an edge).
using Region2 = std::vector<PolygonWithHoles2>;

/// The same two operations on regions (a \ ∪ b, and the coverage counts of several regions): a
/// union of many convex pieces has far fewer vertices than its pieces, and the sweep's cost
/// follows the vertices. Each region is the points inside an odd number of the simple loops its
/// rings split into where they touch themselves. Exact for the rings as given (unite_convex
/// rounded their crossings). None when a loop is not simple (a rounded crossing can make two
/// edges cross): the caller then uses the pieces. Cost: the sweep's O((v + k) log v) for the
/// rings' v vertices and k crossings, plus, for a loop of n vertices that is not simple, a sweep
/// over its edges' x-extents, O(n · a) for a edges active at once, with exact intersections.
/// Measured: the visible shadow on the slab of issue 15's 986 048-triangle mesh scene (241 805
/// shadow pieces minus 280 297 hidden ones, unions of ~3 900 vertices) drops from 42 s to
/// well under a second.
std::optional<UnionResult> cgal_difference(const Region2& a, const std::vector<Region2>& b);
std::optional<std::vector<UnionResult>> cgal_coverage_levels(const std::vector<Region2>& sets);

}  // namespace hedra
