// Triangulation of planar polygons (possibly non-convex, possibly with holes).
#pragma once

#include <array>
#include <vector>

#include "hedra/core/plane.h"

namespace hedra {

/// Triangulates the planar polygon whose boundary loops (outer first, then holes) are lists
/// of indices into `vertices`. `normal` is the polygon's normal (any length, the loops run
/// counter-clockwise around it); output triangles are index triples into `vertices`, also
/// counter-clockwise around `normal`, with no zero-area triangles. Convex single loops are
/// fanned; everything else goes through CGAL's exact-predicate constrained Delaunay
/// triangulation. Cost O(k) for convex loops, O(k log k) otherwise.
/// \throw InvalidInput when the loops cross or touch each other, a hole lies outside the
///   outer loop, or the loops do not bound a region (the message has no face context; the
///   caller adds it).
std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Vec3>& vertices,
                                                    const std::vector<std::vector<int>>& loops,
                                                    const Vec3& normal);

}  // namespace hedra
