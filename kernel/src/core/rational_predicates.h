// Internal: 2D orientation and in-circle tests on points with exact rational coordinates (CGAL's
// lazy exact kernel, Epeck), for the triangulations of the exact decomposition's caps and faces
// (decompose/split.cpp). Interval arithmetic first, as CGAL's own filtered predicates; where
// that cannot decide, the exact sign in homogeneous integer coordinates.
//
// Why not CGAL's exact stage: it evaluates the determinant in GMP rationals, and every rational
// addition and product reduces its result by a gcd. The points met there are cut points made
// by chains of plane cuts, with numerators and denominators of hundreds of bits, and the
// undecided tests are exactly the degenerate ones (collinear and cocircular corners of a cap),
// so that stage ran often: GMP's gcd was 25–60 % of a rotated body's decomposition. Writing
// x = a/b, y = c/d as (X, Y, W) = (a·d, c·b, b·d) with W > 0 turns each test into a
// determinant of integers: products and sums only, no gcd. The signs are the same, so the
// triangulations are the same.
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/predicates/kernel_ftC2.h>

#include <gmpxx.h>

namespace hedra::internal {

namespace rational {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;

// A point in homogeneous integer coordinates, W > 0.
struct H2 {
  mpz_class x, y, w;
};

inline H2 homogeneous(const EK::Point_2& p) {
  const auto& e = CGAL::exact(p);
  const mpq_class& x = e.x();
  const mpq_class& y = e.y();
  H2 h;
  if (x.get_den() == y.get_den()) {
    h.x = x.get_num();
    h.y = y.get_num();
    h.w = x.get_den();
  } else {
    h.x = x.get_num() * y.get_den();
    h.y = y.get_num() * x.get_den();
    h.w = x.get_den() * y.get_den();
  }
  return h;
}

// The point as doubles, where its coordinates are doubles (an input vertex, a cut point of an
// axis-aligned body): then CGAL's predicates on doubles (static filter, exact fallback) decide.
inline bool doubles(const EK::Point_2& p, CGAL::Epick::Point_2& out) {
  const auto& a = p.approx();
  if (a.x().inf() != a.x().sup() || a.y().inf() != a.y().sup()) return false;
  out = CGAL::Epick::Point_2(a.x().inf(), a.y().inf());
  return true;
}

// Sign of | a0 a1 a2 ; b0 b1 b2 ; c0 c1 c2 |.
inline int det3_sign(const mpz_class& a0, const mpz_class& a1, const mpz_class& a2,
                     const mpz_class& b0, const mpz_class& b1, const mpz_class& b2,
                     const mpz_class& c0, const mpz_class& c1, const mpz_class& c2) {
  const mpz_class m0 = b1 * c2 - b2 * c1;
  const mpz_class m1 = b0 * c2 - b2 * c0;
  const mpz_class m2 = b0 * c1 - b1 * c0;
  return sgn(a0 * m0 - a1 * m1 + a2 * m2);
}

}  // namespace rational

/// Orientation of (p, q, r): LEFT_TURN when r is left of the line p → q. Exact; equal to
/// CGAL::orientation. Cost: on doubles, CGAL's filtered test on doubles; else one interval
/// evaluation, in degenerate and near-degenerate cases one 3 × 3 integer determinant.
inline CGAL::Orientation orientation_2(const rational::EK::Point_2& p, const rational::EK::Point_2& q,
                                       const rational::EK::Point_2& r) {
  if (CGAL::Epick::Point_2 dp, dq, dr; rational::doubles(p, dp) && rational::doubles(q, dq) && rational::doubles(r, dr))
    return CGAL::orientation(dp, dq, dr);
  {
    CGAL::Protect_FPU_rounding<true> guard;
    const auto &ap = p.approx(), &aq = q.approx(), &ar = r.approx();
    const CGAL::Uncertain<CGAL::Sign> s =
        CGAL::orientationC2(ap.x(), ap.y(), aq.x(), aq.y(), ar.x(), ar.y());
    if (CGAL::is_certain(s)) return CGAL::get_certain(s);
  }
  using rational::homogeneous;
  const rational::H2 a = homogeneous(p), b = homogeneous(q), c = homogeneous(r);
  // det [X Y W] of the three rows has the sign of the orientation times W_p W_q W_r > 0.
  return static_cast<CGAL::Orientation>(rational::det3_sign(a.x, a.y, a.w, b.x, b.y, b.w, c.x, c.y, c.w));
}

/// Side of t with respect to the circle through p, q, r, oriented as p, q, r: ON_POSITIVE_SIDE
/// when t is inside the circle of counter-clockwise p, q, r. Exact; equal to
/// CGAL::side_of_oriented_circle. Cost: as orientation_2().
inline CGAL::Oriented_side side_of_oriented_circle_2(const rational::EK::Point_2& p, const rational::EK::Point_2& q,
                                                     const rational::EK::Point_2& r, const rational::EK::Point_2& t) {
  if (CGAL::Epick::Point_2 dp, dq, dr, dt; rational::doubles(p, dp) && rational::doubles(q, dq) &&
                                           rational::doubles(r, dr) && rational::doubles(t, dt))
    return CGAL::side_of_oriented_circle(dp, dq, dr, dt);
  {
    CGAL::Protect_FPU_rounding<true> guard;
    const auto &ap = p.approx(), &aq = q.approx(), &ar = r.approx(), &at = t.approx();
    const CGAL::Uncertain<CGAL::Oriented_side> s = CGAL::side_of_oriented_circleC2(
        ap.x(), ap.y(), aq.x(), aq.y(), ar.x(), ar.y(), at.x(), at.y());
    if (CGAL::is_certain(s)) return CGAL::get_certain(s);
  }
  using rational::homogeneous;
  const rational::H2 d = homogeneous(t);
  // Each of p, q, r relative to t: (A_x, A_y) / (W_a W_t); its row (A_x, A_y, A_x² + A_y²)
  // scaled by (W_a W_t)² > 0 is (A_x S, A_y S, A_x² + A_y²) with S = W_a W_t. The sign of the
  // determinant of these rows is the in-circle sign (positive: t inside the circle of
  // counter-clockwise p, q, r).
  struct Row {
    mpz_class x, y, l;
  };
  auto row = [&](const rational::EK::Point_2& pt) {
    const rational::H2 a = homogeneous(pt);
    Row out;
    const mpz_class ax = a.x * d.w - d.x * a.w, ay = a.y * d.w - d.y * a.w, s = a.w * d.w;
    out.l = ax * ax + ay * ay;
    out.x = ax * s;
    out.y = ay * s;
    return out;
  };
  const Row a = row(p), b = row(q), c = row(r);
  return static_cast<CGAL::Oriented_side>(rational::det3_sign(a.x, a.y, a.l, b.x, b.y, b.l, c.x, c.y, c.l));
}

/// Side of p against the plane (ON_POSITIVE_SIDE where a·x + b·y + c·z + d > 0), as
/// CGAL's Plane_3::oriented_side, exact. Interval first; the exact stage sums the four terms
/// n_i / d_i as Σ n_i · Π_{j≠i} d_j in integers (no gcd), where GMP rationals reduce every
/// product and sum by a gcd. Cost: one interval evaluation, else 18 integer products.
inline CGAL::Oriented_side oriented_side_3(const rational::EK::Plane_3& h, const rational::EK::Point_3& p) {
  {
    CGAL::Protect_FPU_rounding<true> guard;
    const auto& ah = h.approx();
    const auto& ap = p.approx();
    const CGAL::Uncertain<CGAL::Sign> s =
        CGAL::sign(ah.a() * ap.x() + ah.b() * ap.y() + ah.c() * ap.z() + ah.d());
    if (CGAL::is_certain(s)) return static_cast<CGAL::Oriented_side>(CGAL::get_certain(s));
  }
  const auto& eh = CGAL::exact(h);
  const auto& ep = CGAL::exact(p);
  const mpq_class coef[3] = {eh.a(), eh.b(), eh.c()};  // by value in CGAL's Plane_3
  const mpq_class* coord[3] = {&ep.x(), &ep.y(), &ep.z()};
  mpz_class n[4], d[4];
  for (int i = 0; i < 3; ++i) {
    n[i] = coef[i].get_num() * coord[i]->get_num();
    d[i] = coef[i].get_den() * coord[i]->get_den();
  }
  const mpq_class last = eh.d();
  n[3] = last.get_num();
  d[3] = last.get_den();
  mpz_class suffix[5];
  suffix[4] = 1;
  for (int i = 3; i >= 0; --i) suffix[i] = suffix[i + 1] * d[i];
  mpz_class prefix = 1, sum = 0;
  for (int i = 0; i < 4; ++i) {
    sum += n[i] * prefix * suffix[i + 1];
    prefix *= d[i];
  }
  return static_cast<CGAL::Oriented_side>(sgn(sum));
}

/// A triangulation traits class: Epeck with the two predicates above (CGAL's triangulations
/// call them through orientation_2_object() and side_of_oriented_circle_2_object()).
struct RationalTriangulationTraits : rational::EK {
  struct Orientation_2 {
    using result_type = CGAL::Orientation;
    CGAL::Orientation operator()(const Point_2& p, const Point_2& q, const Point_2& r) const {
      return orientation_2(p, q, r);
    }
  };
  struct Side_of_oriented_circle_2 {
    using result_type = CGAL::Oriented_side;
    CGAL::Oriented_side operator()(const Point_2& p, const Point_2& q, const Point_2& r, const Point_2& t) const {
      return side_of_oriented_circle_2(p, q, r, t);
    }
  };
  Orientation_2 orientation_2_object() const { return {}; }
  Side_of_oriented_circle_2 side_of_oriented_circle_2_object() const { return {}; }
};

}  // namespace hedra::internal
