// Exact 2D Boolean operations on sets of polygons: CGAL's exact 2D Boolean operations
// (Epeck) behind a thin adapter on hedra's own 2D types (hedra/visibility/polygon_union.h).
// Slower than unite_convex; used where generality matters more than speed (differences,
// coverage counts, the chaining fallback of unite_convex) and as test oracles.
#pragma once

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

}  // namespace hedra
