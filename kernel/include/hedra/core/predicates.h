// The one exact predicate layer. Every geometric decision in hedra (side of plane,
// orientation, convexity, inside/outside) is a sign computed here, exactly for the double
// inputs given. Each predicate is filtered: a static floating-point filter with a proven error
// bound first (Shewchuk's for the 3×3 determinants, ExactPlane's own bound for planes), then
// interval arithmetic, then exact multiprecision (CGAL's filtered predicates, CGAL::Mpzf) only
// when neither can decide. Constructions (intersection points, areas, t
// values) are separate and live with the algorithms that need them.
#pragma once

#include <array>
#include <memory>

#include <Eigen/Core>

#include "hedra/core/plane.h"

namespace hedra {

using Vec2 = Eigen::Vector2d;

/// Sign of an exact determinant: −1, 0 or +1.
enum class Sign : int { Negative = -1, Zero = 0, Positive = 1 };

inline Sign operator-(Sign s) { return static_cast<Sign>(-static_cast<int>(s)); }

/// Sign of det[b − a, c − a, d − a] = (b − a)·((c − a) × (d − a)) … in the convention of
/// CGAL::orientation: Positive when d lies on the side of plane (a, b, c) towards which
/// (b − a) × (c − a) points. For a face whose loop runs counter-clockwise seen from outside
/// (hedra's convention), Positive means "outside the face plane". Stages: Shewchuk's static
/// filter; equal points; an exact floating-point expansion where the differences are exact
/// in double (an exactly zero determinant, which no filter decides, costs about sixty double
/// operations); intervals, then Mpzf. Cost O(1).
Sign orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// orient3d(a, b, c, x) for one plane (a, b, c) and many points x: the cross product
/// (b − a) × (c − a) and the sums of absolute products for Shewchuk's static bound are computed
/// once, so that the filtered test of a point is three products and a bound (the determinant
/// expanded along x's row, the same bound as orient3d's filter). When that cannot decide, the
/// sign is orient3d's, so the result is always orient3d(a, b, c, x). Cost O(1) per point.
class PlaneOrientation {
 public:
  PlaneOrientation(const Vec3& a, const Vec3& b, const Vec3& c);
  Sign operator()(const Vec3& x) const;

 private:
  Vec3 a_, b_, c_, cross_, absolute_;
};

/// orient3d with the direction d in place of d − a: the exact sign of det[b − a, c − a, d]
/// (which side of plane (a, b, c) moving along d goes to). Cost O(1).
Sign orient_direction(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// True when d is parallel to b − a, exactly (d ≠ 0). Cost O(1).
bool parallel_to(const Vec3& a, const Vec3& b, const Vec3& d);

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

// ---- Oriented planes for clipping (hedra/clip/cyrus_beck.h, batch_clip.h, polygon_clip.h) ----

namespace internal {
struct ExactCoefficients;  // kernel/src/core/exact_plane.h: four exact (CGAL::Mpzf) coefficients
}

/// An oriented plane as an exact affine function f(p), Positive on its inner side, together
/// with a double form n·p + k whose evaluation error is bounded, so that callers can decide a
/// sign in floating point whenever |value| exceeds the bound and call the exact predicates
/// below otherwise. f is either
///  - the plane of three points a, b, c: f(p) = −det[b − a, c − a, p − a], Positive where
///    orient3d(a, b, c, p) is Negative (a Body face through its support triple, so exactly
///    Body::face_side), or
///  - the plane of four double coefficients taken as exact: f(p) = a·x + b·y + c·z + d (the
///    convention of side_of_plane and of a body-matrix column), or
///  - the plane of four exact multiprecision coefficients (by_exact(): a face of an exact
///    piece whose corners are not doubles, a pencil plane through a silhouette edge of one).
/// The double form approximates F = f / 2^e, a power-of-two multiple chosen so that the
/// largest |n_i| lies in [1, 2) (for exact coefficients a positive multiple, each coefficient
/// within 2u of its own value): no sign and no crossing parameter changes, and value() is
/// close to a distance for well-shaped planes.
class ExactPlane {
 public:
  ExactPlane() = default;
  /// \throw InvalidInput if a coordinate is not finite or the points are collinear.
  static ExactPlane through(const Vec3& a, const Vec3& b, const Vec3& c);
  /// The plane through a and b parallel to direction d (a viewpoint at infinity): exact, the
  /// direction is never added to a point. f(p) = −det[b − a, d, p − a].
  /// \throw InvalidInput if a value is not finite or d is parallel to b − a (or zero).
  static ExactPlane through_direction(const Vec3& a, const Vec3& b, const Vec3& d);
  /// \throw InvalidInput if a coefficient is not finite or the normal is zero.
  static ExactPlane from_coefficients(const Plane& plane);
  /// The plane of the pencil of f and g through the point e (or parallel to the direction e
  /// when e_is_direction): h = g(E)·f − f(E)·g, with E the point e, or the point at infinity
  /// e (homogeneous (e, 0): f(E) = n_f·e). Exact: h vanishes on the common line of f and g and
  /// at E, and a point where f and g are both positive is positive on h when f(E) < 0 ≤ g(E)
  /// (a silhouette edge between a face f turned to the viewpoint E and a face g that is not:
  /// the plane through the edge and the viewpoint, the piece on its positive side). Its
  /// coefficients are exact multiprecision numbers (by_exact()), computed from f's and g's
  /// own, so no vertex of the edge is needed: the edges of an exact convex piece whose corners
  /// are not doubles. Cost: a few dozen multiprecision operations.
  /// \throw InvalidInput if h vanishes identically (f and g parallel, or E on both).
  static ExactPlane pencil(const ExactPlane& f, const ExactPlane& g, const Vec3& e,
                           bool e_is_direction);
  /// A plane from exact coefficients (kernel/src/core/exact_plane.h builds them: planes of
  /// exact points that are not doubles, pencils). \throw InvalidInput if the normal is zero
  /// or the offset too large for the normal.
  /// Takes the coefficients over (their interval enclosures are filled in, no copy is made).
  static ExactPlane from_exact(std::shared_ptr<internal::ExactCoefficients> coefficients);

  /// fl(n·p + k), always in this order: ((n0·x + n1·y) + n2·z) + k, so every caller (scalar or
  /// vectorized) gets the same bits.
  double value(double x, double y, double z) const {
    return ((n_[0] * x + n_[1] * y) + n_[2] * z) + k_;
  }
  double value(const Vec3& p) const { return value(p.x(), p.y(), p.z()); }
  /// B(m) with |value(p) − F(p)| ≤ B(m) for every p with max |p_i| ≤ m: the rounding of the
  /// evaluation (γ₄ of the terms), the rounding of n and k themselves (a static bound on their
  /// construction in double) and underflow, inflated so that computing B itself in double
  /// cannot make it too small.
  double error_bound(double m) const { return slope_ * m + offset_; }

  const Vec3& normal() const { return n_; }  // n (not unit length)
  double offset() const { return k_; }       // k
  double error_slope() const { return slope_; }
  double error_offset() const { return offset_; }
  bool by_points() const { return by_points_; }
  bool negated() const { return negated_; }  // f is −(the defining form): see flipped()
  bool by_direction() const { return by_direction_; }
  /// Exact multiprecision coefficients (pencil(), from_exact()): neither points nor doubles.
  bool by_exact() const { return exact_ != nullptr; }
  const internal::ExactCoefficients* exact_coefficients() const { return exact_.get(); }
  /// When by_points(): the three points, or a, b and the direction when by_direction().
  const std::array<Vec3, 3>& points() const { return points_; }
  const Plane& coefficients() const { return plane_; }  // when !by_points() && !by_exact()
  /// The same plane with the other side inner (−f, exactly).
  ExactPlane flipped() const;

 private:
  static ExactPlane build(const Vec3& a, const Vec3& b, const Vec3& c, bool direction);

  bool by_points_ = false;
  bool by_direction_ = false;  // points_[2] is a direction (through_direction)
  bool negated_ = false;  // f is the negation of the defining form (flipped())
  std::array<Vec3, 3> points_{};
  std::shared_ptr<const internal::ExactCoefficients> exact_;
  Plane plane_;
  Vec3 n_ = Vec3::Zero();
  double k_ = 0, slope_ = 0, offset_ = 0;

  template <class T>
  friend T exact_plane_value(const ExactPlane& f, const Vec3& p);
};

/// Exact sign of f(p): Positive = inner side. A static filter on value() and error_bound()
/// decides almost always; interval arithmetic, then CGAL::Mpzf, decide the rest. Cost O(1).
Sign side_of_plane(const ExactPlane& f, const Vec3& p);

/// side_of_plane(f, p) for a caller that already has value = f.value(p) and
/// bound = f.error_bound(max |p_i|) (clippers need the value for the crossing too): the
/// static filter on them, the exact sign when it cannot decide. Cost O(1).
inline Sign side_of_plane(const ExactPlane& f, const Vec3& p, double value, double bound) {
  if (value > bound) return Sign::Positive;
  if (value < -bound) return Sign::Negative;
  return side_of_plane(f, p);
}

/// Exact sign of n·d, n the exact normal of f (pointing to the inner side): Positive when
/// moving along d goes into the inner side. Cost O(1).
Sign direction_sign(const ExactPlane& f, const Vec3& d);

/// Order of the points where the line through p and q crosses the planes f and g: the sign of
/// t_f − t_g with t_f = f(p) / (f(p) − f(q)), the parameter on p + (q − p)·t (Cyrus–Beck's
/// t = −Wn/Dn). Exact, decided as sign(g(p)·f(q) − f(p)·g(q)) · sign(f(p) − f(q)) ·
/// sign(g(p) − g(q)).
/// \pre f(p) ≠ f(q) and g(p) ≠ g(q) (the line crosses both planes). Cost O(1).
Sign compare_crossings(const ExactPlane& f, const ExactPlane& g, const Vec3& p, const Vec3& q);

/// Order along coordinate `axis` (0, 1, 2) of X, the point where line pq crosses f, and Y,
/// where line rs crosses f: the exact sign of X[axis] − Y[axis], with
/// X[axis] = (f(p)·q[axis] − f(q)·p[axis]) / (f(p) − f(q)) (a point on the plane, f(p) = 0,
/// gives p[axis] exactly). \pre f(p) ≠ f(q), f(r) ≠ f(s). Cost O(1).
Sign compare_crossings_along(const ExactPlane& f, const Vec3& p, const Vec3& q, const Vec3& r,
                             const Vec3& s, int axis);

}  // namespace hedra
