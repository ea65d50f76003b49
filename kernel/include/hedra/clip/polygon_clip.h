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
// Exactness. clip_polygon: which vertices lie inside, on or outside each plane is decided
// exactly (side_of_plane on ExactPlane); a vertex on a plane is kept as it is, never replaced
// by a computed intersection, and an edge lying in a plane creates no new point. How the parts
// along a plane are joined into pieces depends on the order of the crossing points along the
// cutting line, which is also decided exactly (compare_crossings_along on the exact crossing
// points). Only new vertices (edge–plane intersections) are rounded, with the bound of
// hedra/clip/cyrus_beck.h on their parameter; a later plane decides on those rounded points.
// clip_convex_polygon_open (what shadows use) keeps every vertex it makes as the planes it lies
// on and decides every plane on the exact polygon: rounding never decides.
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

namespace internal {
/// How a vertex of a clipped polygon is made, exactly: an input vertex (lifted onto the plane),
/// or where the line `on` crosses the clipper's plane `cut`; `after` is the line of the edge to
/// the next vertex. A line is the input's edge from vertex l to the next (l ≥ 0) or the trace
/// of the clipper's plane −1 − l.
struct ClipVertex {
  int input = -1;
  int on = 0, cut = 0, after = 0;
  int exact = -1;  // its exact point, once a decision has needed it (index in one clipping)
};
}  // namespace internal

/// Work space of clip_convex_polygon_open, reused across calls (one per thread).
struct PolygonClipScratch {
  Polygon3 ring;
  std::vector<Sign> side;
  std::vector<double> error, ring_error;  // per vertex: max-norm distance to its exact point
  std::vector<internal::ClipVertex> made, ring_made;
};

/// A convex polygon ∩ the open clipper (the interior of an occlusion volume), by
/// Sutherland–Hodgman: true and the clipped convex polygon in `out`, or false when nothing of
/// positive area is strictly inside (a polygon with no vertex strictly inside a plane, one
/// lying in a plane included).
///
/// Exact on the polygon the cuts make, not on rounded vertices. The polygon is taken as its
/// projection along the coordinate axis `axis` lifted onto `plane` (its own points where it
/// lies on the plane; a face planar only within rounding, as a rotated body's, is that lifted
/// polygon, which is what its 2D projection shows). Every vertex the clipping makes is kept as
/// the planes it lies on (the plane, the line of the edge it was made on, the cutting plane),
/// and a later plane decides its side on that exact point: a filter on the rounded vertex with
/// its tracked error bound, else the sign of a 4 × 4 determinant of the planes' exact
/// coefficients. So a vertex exactly on a later plane (clipper planes meeting in a point of
/// the polygon's plane) is on it, and no rounding of an earlier cut decides a later one.
/// Output vertices are rounded once per cut, from the rounded ends of the edge cut, within
/// the tracked bound of their exact points (PolygonClipScratch::error); where that bound
/// would exceed 2^-36 of the coordinates (an edge cut at a grazing angle), the vertex is its
/// exact point rounded instead, within 8u of its coordinates. Crossing points are
/// canonical: computed from the edge's ends in lexicographic order, and on a plane
/// perpendicular to a coordinate axis given that plane's coordinate exactly, so that polygons
/// sharing an edge (convex parts of one face) or cut by one such plane (walls, floors,
/// decomposition cuts) get the very same points.
/// \pre a convex polygon with finite coordinates whose projection along `axis` is a convex
/// ring, `plane` with a non-zero `axis` component. \throw InvalidInput when that component
/// is zero. Cost O(planes · n); a decision the filter leaves open costs a few dozen
/// multiprecision operations.
/// `planar`: the caller knows every vertex lies exactly on `plane` (a face whose vertices
/// all do: its own lifts), so they are decided by side_of_plane on their doubles.
bool clip_convex_polygon_open(const Polygon3& polygon, const ExactPlane& plane, int axis,
                              bool planar, const ConvexClipper& clipper, Polygon3& out,
                              PolygonClipScratch& scratch);

/// Area of a planar polygon: half the length of Newell's vector. Cost O(n).
double polygon_area(const Polygon3& polygon);

/// Newell's vector: normal of the polygon's orientation, twice its area long. Cost O(n).
Vec3 polygon_normal(const Polygon3& polygon);

}  // namespace hedra
