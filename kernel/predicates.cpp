#include "kernel/predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Mpzf.h>

#include <cmath>

namespace hedra {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

K::Point_3 cg(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
K::Point_2 cg(const Vec2& p) { return {p.x(), p.y()}; }

Sign to_sign(CGAL::Sign s) { return static_cast<Sign>(static_cast<int>(s)); }

int dominant_axis(const Vec3& a, const Vec3& b, const Vec3& c) {
  Vec3 n = (b - a).cross(c - a);
  int axis;
  n.cwiseAbs().maxCoeff(&axis);
  return axis;
}

Vec2 drop(const Vec3& p, int axis) {
  switch (axis) {
    case 0: return {p.y(), p.z()};
    case 1: return {p.z(), p.x()};
    default: return {p.x(), p.y()};
  }
}

}  // namespace

Sign orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return to_sign(CGAL::orientation(cg(a), cg(b), cg(c), cg(d)));
}

Sign orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  return to_sign(CGAL::orientation(cg(a), cg(b), cg(c)));
}

Sign side_of_plane(const Plane& plane, const Vec3& p) {
  const Vec4& k = plane.coefficients;
  // Filter: interval arithmetic decides almost always.
  {
    CGAL::Protect_FPU_rounding<true> guard;
    using I = CGAL::Interval_nt_advanced;
    I v = I(k[0]) * I(p.x()) + I(k[1]) * I(p.y()) + I(k[2]) * I(p.z()) + I(k[3]);
    if (v.inf() > 0) return Sign::Positive;
    if (v.sup() < 0) return Sign::Negative;
  }
  // Exact: Mpzf represents every double and their sums and products exactly.
  CGAL::Mpzf v = CGAL::Mpzf(k[0]) * CGAL::Mpzf(p.x()) + CGAL::Mpzf(k[1]) * CGAL::Mpzf(p.y()) +
                 CGAL::Mpzf(k[2]) * CGAL::Mpzf(p.z()) + CGAL::Mpzf(k[3]);
  return to_sign(CGAL::sign(v));
}

bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
  return CGAL::collinear(cg(a), cg(b), cg(c));
}

SegmentTriangle segment_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                 const Vec3& c) {
  Sign sp = orient3d(a, b, c, p);
  Sign sq = orient3d(a, b, c, q);
  if (sp == sq && sp != Sign::Zero) return SegmentTriangle::Disjoint;
  if (sp == Sign::Zero || sq == Sign::Zero) {
    // An end point in the triangle's plane, or the whole segment coplanar.
    if (sp == Sign::Zero && on_triangle(p, a, b, c)) return SegmentTriangle::Degenerate;
    if (sq == Sign::Zero && on_triangle(q, a, b, c)) return SegmentTriangle::Degenerate;
    if (sp == Sign::Zero && sq == Sign::Zero) {
      // Coplanar: degenerate unless clearly apart; conservative is fine for its users
      // (ray casting retries with another ray).
      return SegmentTriangle::Degenerate;
    }
    return SegmentTriangle::Disjoint;
  }
  // p and q strictly on opposite sides: the line pq crosses the plane inside the triangle
  // iff it passes on the same side of the three edges.
  Sign e0 = orient3d(p, q, a, b);
  Sign e1 = orient3d(p, q, b, c);
  Sign e2 = orient3d(p, q, c, a);
  if (e0 == Sign::Zero || e1 == Sign::Zero || e2 == Sign::Zero) {
    bool pos = e0 == Sign::Positive || e1 == Sign::Positive || e2 == Sign::Positive;
    bool neg = e0 == Sign::Negative || e1 == Sign::Negative || e2 == Sign::Negative;
    return (pos && neg) ? SegmentTriangle::Disjoint : SegmentTriangle::Degenerate;
  }
  return (e0 == e1 && e1 == e2) ? SegmentTriangle::Crossing : SegmentTriangle::Disjoint;
}

bool on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  if (orient3d(a, b, c, p) != Sign::Zero) return false;
  // Coplanar: dropping the dominant axis of the normal projects injectively, and dropping a
  // coordinate is exact, so the 2D predicates below stay exact.
  int axis = dominant_axis(a, b, c);
  Vec2 pa = drop(a, axis), pb = drop(b, axis), pc = drop(c, axis), pp = drop(p, axis);
  Sign s0 = orient2d(pa, pb, pp), s1 = orient2d(pb, pc, pp), s2 = orient2d(pc, pa, pp);
  bool pos = s0 == Sign::Positive || s1 == Sign::Positive || s2 == Sign::Positive;
  bool neg = s0 == Sign::Negative || s1 == Sign::Negative || s2 == Sign::Negative;
  return !(pos && neg);
}

}  // namespace hedra
