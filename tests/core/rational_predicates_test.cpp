// The 2D orientation and in-circle tests and the 3D side of a plane of
// kernel/src/core/rational_predicates.h against
// CGAL's own exact predicates (the reference), on rational points made the way the exact
// decomposition makes them (quotients of lazy exact numbers), in general position and in the
// degenerate positions its caps meet: collinear runs and cocircular corners.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/rational_predicates.h"

namespace hedra::internal {
namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = EK::FT;
using P2 = EK::Point_2;

FT rational(std::mt19937_64& rng) {
  std::uniform_int_distribution<long> num(-1000000, 1000000), den(1, 999983);
  return FT(static_cast<double>(num(rng))) / FT(static_cast<double>(den(rng)));
}

P2 point(std::mt19937_64& rng) { return P2(rational(rng), rational(rng)); }

// p + t (q − p): exactly on the line pq.
P2 along(const P2& p, const P2& q, const FT& t) { return P2(p.x() + t * (q.x() - p.x()), p.y() + t * (q.y() - p.y())); }

// A rational point of the circle of centre c and radius r, at parameter s ((1 − s², 2s) / (1 + s²)).
P2 on_circle(const P2& c, const FT& r, const FT& s) {
  const FT d = 1 + s * s;
  return P2(c.x() + r * (1 - s * s) / d, c.y() + r * 2 * s / d);
}

void expect_same(const P2& p, const P2& q, const P2& r) {
  EXPECT_EQ(orientation_2(p, q, r), CGAL::orientation(p, q, r));
}

void expect_same(const P2& p, const P2& q, const P2& r, const P2& t) {
  EXPECT_EQ(side_of_oriented_circle_2(p, q, r, t), CGAL::side_of_oriented_circle(p, q, r, t));
}

TEST(RationalPredicates, OrientationEqualsCgalInGeneralAndCollinearPositions) {
  std::mt19937_64 rng(7);
  int zero = 0;
  for (int i = 0; i < 300; ++i) {
    const P2 p = point(rng), q = point(rng), r = point(rng);
    expect_same(p, q, r);
    // Exactly collinear (the interval stage cannot decide): the integer stage must say 0.
    const P2 x = along(p, q, rational(rng));
    EXPECT_EQ(orientation_2(p, q, x), CGAL::COLLINEAR);
    expect_same(p, x, q);
    expect_same(x, q, p);
    zero += orientation_2(x, p, q) == CGAL::COLLINEAR;
    // Off the line by the smallest of steps: a sign the intervals may not see.
    const P2 y(x.x() + FT(1) / FT(1e15), x.y());
    expect_same(p, q, y);
    expect_same(q, p, y);
  }
  EXPECT_EQ(zero, 300);
}

TEST(RationalPredicates, InCircleEqualsCgalInGeneralAndCocircularPositions) {
  std::mt19937_64 rng(11);
  int zero = 0;
  for (int i = 0; i < 200; ++i) {
    const P2 p = point(rng), q = point(rng), r = point(rng), t = point(rng);
    expect_same(p, q, r, t);
    expect_same(q, p, r, t);
    // Four rational points of one circle: exactly cocircular.
    const P2 c = point(rng);
    const FT radius = FT(1) + rational(rng) * rational(rng);
    const P2 a = on_circle(c, radius, rational(rng)), b = on_circle(c, radius, rational(rng)),
             d = on_circle(c, radius, rational(rng)), e = on_circle(c, radius, rational(rng));
    EXPECT_EQ(side_of_oriented_circle_2(a, b, d, e), CGAL::ON_ORIENTED_BOUNDARY);
    expect_same(a, b, d, e);
    zero += side_of_oriented_circle_2(b, a, e, d) == CGAL::ON_ORIENTED_BOUNDARY;
    // Just inside and just outside.
    const P2 in(e.x() + (c.x() - e.x()) / FT(1e14), e.y() + (c.y() - e.y()) / FT(1e14));
    const P2 out(e.x() - (c.x() - e.x()) / FT(1e14), e.y() - (c.y() - e.y()) / FT(1e14));
    expect_same(a, b, d, in);
    expect_same(a, b, d, out);
    expect_same(d, b, a, in);
    EXPECT_NE(side_of_oriented_circle_2(a, b, d, in), side_of_oriented_circle_2(a, b, d, out));
  }
  EXPECT_EQ(zero, 200);
}

// Points with one denominator for both coordinates (the shortcut in homogeneous()) and with
// coordinates that are doubles (denominators powers of two).
TEST(RationalPredicates, SharedDenominatorsAndDoubles) {
  const P2 p(FT(1) / 3, FT(2) / 3), q(FT(4) / 3, FT(5) / 3), r(FT(7) / 3, FT(8) / 3);
  EXPECT_EQ(orientation_2(p, q, r), CGAL::COLLINEAR);
  EXPECT_EQ(orientation_2(p, q, P2(FT(7) / 3, FT(9) / 3)), CGAL::LEFT_TURN);
  EXPECT_EQ(orientation_2(p, q, P2(FT(7) / 3, FT(7) / 3)), CGAL::RIGHT_TURN);
  const P2 a(0.1, 0.2), b(0.30000000000000004, 0.4), c(0.5, 0.6000000000000001);
  expect_same(a, b, c);
  expect_same(a, b, c, P2(0.7, 0.8));
  // The unit circle's rational points (3/5, 4/5), (−4/5, 3/5), (−3/5, −4/5) and (1, 0).
  const P2 u(FT(3) / 5, FT(4) / 5), v(FT(-4) / 5, FT(3) / 5), w(FT(-3) / 5, FT(-4) / 5);
  EXPECT_EQ(side_of_oriented_circle_2(u, v, w, P2(1, 0)), CGAL::ON_ORIENTED_BOUNDARY);
  EXPECT_EQ(side_of_oriented_circle_2(u, v, w, P2(0, 0)), CGAL::ON_POSITIVE_SIDE);
  EXPECT_EQ(side_of_oriented_circle_2(u, v, w, P2(2, 0)), CGAL::ON_NEGATIVE_SIDE);
}

// The side of a point against a plane (exact_convex() in decompose.cpp): planes through three
// rational points and points exactly on them (the interval stage cannot decide), a tiny step
// off, and in general position, against CGAL's Plane_3::oriented_side.
TEST(RationalPredicates, OrientedSide3EqualsCgalOnAndNearThePlane) {
  using P3 = EK::Point_3;
  std::mt19937_64 rng(11);
  auto point3 = [&] { return P3(rational(rng), rational(rng), rational(rng)); };
  int on = 0, off = 0;
  for (int i = 0; i < 300; ++i) {
    const P3 a = point3(), b = point3(), c = point3();
    const EK::Plane_3 h(a, b, c);
    const FT s = rational(rng), t = rational(rng);
    const P3 x = a + s * (b - a) + t * (c - a);  // exactly on h
    EXPECT_EQ(oriented_side_3(h, x), CGAL::ON_ORIENTED_BOUNDARY);
    on += oriented_side_3(h, x) == CGAL::ON_ORIENTED_BOUNDARY;
    for (const P3& y : {P3(x.x() + FT(1) / FT(1e15), x.y(), x.z()), P3(x.x(), x.y(), x.z() - FT(1) / FT(1e15)), point3()}) {
      EXPECT_EQ(oriented_side_3(h, y), h.oriented_side(y));
      off += oriented_side_3(h, y) != CGAL::ON_ORIENTED_BOUNDARY;
    }
    EXPECT_EQ(oriented_side_3(h.opposite(), x + (b - a)), h.opposite().oriented_side(x + (b - a)));
  }
  EXPECT_EQ(on, 300);
  EXPECT_GE(off, 890);  // a step of 1e-15 off a plane through rational points is rarely 0
}

}  // namespace
}  // namespace hedra::internal
