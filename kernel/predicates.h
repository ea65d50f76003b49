// The one exact predicate layer. Every geometric decision in hedra (side of plane,
// orientation, convexity, inside/outside) is a sign computed here, exactly for the double
// inputs given: CGAL's filtered predicates (interval arithmetic first, exact multiprecision
// only when the interval cannot decide). Constructions (intersection points, areas, t
// values) are separate and live with the algorithms that need them.
#pragma once

#include <array>

#include <Eigen/Core>

#include "kernel/plane.h"

namespace hedra {

using Vec2 = Eigen::Vector2d;

/// Sign of an exact determinant: −1, 0 or +1.
enum class Sign : int { Negative = -1, Zero = 0, Positive = 1 };

inline Sign operator-(Sign s) { return static_cast<Sign>(-static_cast<int>(s)); }

/// Sign of det[b − a, c − a, d − a] = (b − a)·((c − a) × (d − a)) … in the convention of
/// CGAL::orientation: Positive when d lies on the side of plane (a, b, c) towards which
/// (b − a) × (c − a) points. For a face whose loop runs counter-clockwise seen from outside
/// (hedra's convention), Positive means "outside the face plane". Cost O(1).
Sign orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Sign of the 2D orientation of (a, b, c): Positive for a left turn. Cost O(1).
Sign orient2d(const Vec2& a, const Vec2& b, const Vec2& c);

/// Exact sign of a·x + b·y + c·z + d for the stored double coefficients. Cost O(1).
Sign side_of_plane(const Plane& plane, const Vec3& p);

/// True when a, b, c lie on one line (exactly). Cost O(1).
bool collinear(const Vec3& a, const Vec3& b, const Vec3& c);

/// Relation of segment [p, q] and triangle (a, b, c), exactly.
enum class SegmentTriangle {
  Disjoint,    // no common point
  Crossing,    // one common point, interior to both (a proper crossing)
  Degenerate,  // touches an edge or vertex, an end point lies on the triangle, or coplanar
};
SegmentTriangle segment_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                 const Vec3& c);

/// Whether p lies on the closed triangle (a, b, c) (coplanar and inside or on its edges).
/// The triangle must not be degenerate. Cost O(1).
bool on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace hedra
