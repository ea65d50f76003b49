// Exact clipping of segments against a closed, possibly non-convex body directly, without its
// convex decomposition (docs/clipping.md, "Non-convex bodies without decomposition").
//
// The body is its triangulated boundary (Body::triangles(), closed and consistently oriented).
// For the segment P(t) = P1 + (P2 − P1)·t:
//  1. Candidates: a bounding-volume hierarchy over the triangles gives those whose boxes the ray
//     t ≥ 0 meets. Boxes are enlarged by a margin that covers the rounding of P2 − P1 and of the
//     slab test, so no triangle the exact ray meets is missed (culling only, never a decision).
//  2. Events: the triangles that the line crosses (their plane does not contain it) at a point
//     of the closed triangle, t in (0, 1). Exact: orient3d of P1, P2 and each edge (the line's
//     side of the edge) and of the triangle and P1, P2. Their parameters are ordered exactly
//     (compare_ends / compare_crossings); equal ones are one event (a crossing through an edge
//     or a vertex).
//  3. Winding: the line is translated by δ = ε·e_x + ε²·e_y + ε³·e_z, ε → 0 (symbolic
//     perturbation: a zero edge sign takes the sign of the first non-zero term of
//     −δ·((b − a) × (P2 − P1)), exact). The translated line meets no edge or vertex, so its
//     signed crossings after a point count the point's winding number; an open interval between
//     consecutive events lies inside when the crossings at or after its upper event (and
//     beyond P2) sum to non-zero.
//  4. Segments lying in a face plane: a triangle whose plane contains the line makes every
//     interval it overlaps (its own interval on the line, clipped exactly by the three planes
//     through its edges and the axis its normal is largest along) part of the boundary, so
//     inside (the body is closed). Ends of the segment on the boundary are inside.
//  5. Parts: maximal runs of inside intervals, closed (their ends are events or segment ends),
//     and events that bound no inside interval as single points, exactly as clip_segment of
//     the body's convex pieces reports them.
// Ends: an event end is the crossing of the line with the plane of one of its triangles, rounded
// once per coordinate by end_point (crossing_point), like every clipped end: for faces whose
// vertices are exactly coplanar this is the very point the decomposition path reports.
//
// Cost: building O(n log n) for n triangles; per segment O(log n + c + k log k) for c candidate
// triangles and k crossings on the ray (c is about k plus the few neighbours of each crossing
// for rays in general position; a segment lying in a face adds the triangles it runs over), all
// in exact filtered predicates.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "hedra/clip/convex_clipper.h"
#include "hedra/clip/cyrus_beck.h"
#include "hedra/core/body.h"

namespace hedra {

/// A closed body prepared for clipping segments without decomposing it: its triangles and a
/// bounding-volume hierarchy over them. Value type (the body is shared, not copied).
class PolyhedronClipper {
 public:
  /// \throw InvalidInput for a two-sided polygon (it has no interior). Cost O(n log n).
  explicit PolyhedronClipper(const Body& body);

  const Body& body() const { return body_; }
  int triangle_count() const { return static_cast<int>(triangles_.size()); }
  /// Vertex indices of triangle i, counter-clockwise seen from outside.
  const std::array<int, 3>& triangle(int i) const { return triangles_[static_cast<size_t>(i)]; }
  /// The exact plane through triangle i's vertices (inner side positive). Cost O(1).
  ExactPlane plane(int triangle) const;

  /// Appends to `out` every triangle whose box (enlarged by the rounding margin) the ray
  /// p1 + (p2 − p1)·t, t ≥ 0, meets: a superset of the triangles the exact ray meets.
  /// Cost O(log n + output) for rays in general position.
  void ray_candidates(const Vec3& p1, const Vec3& p2, std::vector<int>& out) const;

 private:
  struct Node {
    double lo[3], hi[3];
    int first;  // leaf: first index into order_; inner: index of the right child
    int count;  // leaf: number of triangles (> 0); inner: 0 (the left child follows the node)
  };
  int build(int begin, int end, const std::vector<Vec3>& centroids);

  Body body_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<int> order_;   // triangle indices, leaves' ranges
  std::vector<Node> nodes_;  // nodes_[0] is the root
  double extent_ = 0;        // largest |coordinate| of the body
};

/// The closed segment p1p2 ∩ the closed body, in order along the segment: proper parts and
/// single points where the segment only touches the boundary, exactly as the union of the
/// body's convex pieces gives them (clip_segment(span<ConvexClipper>, …)). An end's plane is
/// the index of a triangle (PolyhedronClipper::plane), its piece 0.
/// \throw InvalidInput if a coordinate is not finite or exceeds kMaxAbsCoordinate.
/// Cost O(log n + c + k log k) (header comment).
std::vector<ClipPart> clip_segment(const PolyhedronClipper& clipper, const Vec3& p1,
                                   const Vec3& p2);

/// Exterior clipping: the closure of the segment minus the body, as the gaps between the
/// proper inside parts (a point segment: whole when outside). Cost as clip_segment.
std::vector<ClipPart> clip_segment_outside(const PolyhedronClipper& clipper, const Vec3& p1,
                                           const Vec3& p2);

/// The point of an end of a part from the two functions above: P1 or P2 itself, or the exact
/// crossing with the end's triangle plane rounded once per coordinate. Cost O(1).
Vec3 end_point(const PolyhedronClipper& clipper, const ClipEnd& end, const Vec3& p1,
               const Vec3& p2);

/// The clipper of `hedra clip` and of the Python module: the union of bodies, each convex one
/// as a ConvexClipper (Cyrus–Beck), each non-convex one as a PolyhedronClipper (no
/// decomposition). Part ends name their source in `piece`: 0 … convex_count() − 1 the convex
/// clippers, then the polyhedra.
class SolidClipper {
 public:
  /// Cost: the exact convexity test of each body, then O(n log n) per non-convex one.
  /// \throw InvalidInput as the clippers' constructors.
  explicit SolidClipper(std::span<const Body> bodies);

  const std::vector<ConvexClipper>& convex() const { return convex_; }
  const std::vector<PolyhedronClipper>& polyhedra() const { return polyhedra_; }
  int convex_count() const { return static_cast<int>(convex_.size()); }

  /// The closed segment ∩ the union of the bodies: the parts of each body, merged exactly
  /// where they touch or overlap (as clip_segment of convex pieces). Cost: the sources' costs
  /// plus O(m log m) for m parts.
  std::vector<ClipPart> clip(const Vec3& p1, const Vec3& p2) const;
  /// The closure of the segment minus the union: the gaps between the proper inside parts.
  std::vector<ClipPart> clip_outside(const Vec3& p1, const Vec3& p2) const;
  /// The point of an end of a part of clip() or clip_outside(). Cost O(1).
  Vec3 end_point(const ClipEnd& end, const Vec3& p1, const Vec3& p2) const;

 private:
  std::vector<ConvexClipper> convex_;
  std::vector<PolyhedronClipper> polyhedra_;
};

}  // namespace hedra
