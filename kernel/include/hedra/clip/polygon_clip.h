// Clipping planar polygons against a convex volume: a Sutherland–Hodgman pipeline of planes
// (docs/algorithms.md §3.5), the operation cast shadows are made of.
//
// Representation. A polygon is a ring of 3D points (Polygon3), planar, simple, either
// orientation. The result of clipping is a list of such rings with the input's orientation:
// the closed polygon ∩ closed clipper, as interior-disjoint pieces, one per connected part.
// A convex polygon gives at most one piece, convex; a non-convex one may give several.
// Parts of zero area (the polygon only touching a plane along an edge or at a vertex) are
// dropped; a piece can touch itself at a single point where a vertex lies exactly on a plane
// that cuts the polygon elsewhere.
//
// Exactness. Which vertices lie inside, on or outside each plane is decided exactly
// (side_of_plane on ExactPlane); a vertex on a plane is kept as it is, never replaced by a
// computed intersection, and an edge lying in a plane creates no new point. How the parts
// along a plane are joined into pieces depends on the order of the crossing points along the
// cutting line, which is also decided exactly (compare_crossings_along on the exact crossing
// points). Only new vertices (edge–plane intersections) are rounded, with the bound of
// hedra/clip/cyrus_beck.h on their parameter.
#pragma once

#include <vector>

#include "hedra/clip/convex_clipper.h"

namespace hedra {

using Polygon3 = std::vector<Vec3>;

/// One stage of the pipeline: the polygon ∩ the closed inner half-space of f, as pieces.
/// \pre a simple planar polygon. \throw InvalidInput for fewer than 3 vertices or a
/// non-finite coordinate. Cost O(n log n) for n vertices (the sort of the crossings).
std::vector<Polygon3> clip_polygon(const Polygon3& polygon, const ExactPlane& f);

/// The polygon ∩ the closed clipper: each piece clipped by each plane in turn.
/// \pre and \throw as above. Cost O(planes · n log n).
std::vector<Polygon3> clip_polygon(const Polygon3& polygon, const ConvexClipper& clipper);

/// The course's Sutherland–Hodgman output as written: one ring, clipped plane after plane,
/// whose parts are joined by edges running along the clipping planes when the polygon is not
/// convex. Its (signed) area is the area of the clipped polygon; clip_polygon separates the
/// pieces. Empty when no point is left; zero area when the polygon only touches the clipper.
/// \throw InvalidInput as clip_polygon. Cost O(planes · n).
Polygon3 sutherland_hodgman(const Polygon3& polygon, const ConvexClipper& clipper);

/// Area of a planar polygon: half the length of Newell's vector. Cost O(n).
double polygon_area(const Polygon3& polygon);

/// Newell's vector: normal of the polygon's orientation, twice its area long. Cost O(n).
Vec3 polygon_normal(const Polygon3& polygon);

}  // namespace hedra
