#include "hedra/core/predicates.h"

#include "core/expansion.h"
#include "core/filtered_sign.h"
#include "core/exact_plane.h"

#include <CGAL/Gmpq.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Mpzf.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <type_traits>

#include "hedra/core/error.h"

namespace hedra {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

K::Point_3 cg(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
K::Point_2 cg(const Vec2& p) { return {p.x(), p.y()}; }

using internal::to_sign;

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

// Static filter for the sign of det[u, v, w], u, v, w as given in double (differences already
// rounded, or exact): Shewchuk's bound for orient3d, errboundA = (7 + 56u)·u times the permanent
// of the rounded differences, both evaluated in double in his order (three terms, each a
// difference times a 2 × 2 minor, summed left to right; no fused multiply-add: the build has
// -ffp-contract=off). J. R. Shewchuk, "Adaptive precision floating-point arithmetic and fast
// robust geometric predicates", 1997, §4.3, and his predicates.c. It was 1e-14 (13 × larger):
// the lat-long quadrilaterals of a tessellated sphere, whose orientation is 1e-15 of the
// permanent, then all went to CGAL's interval and exact stages. nullopt when it cannot decide,
// or when the permanent is so small or large that underflow or overflow could void the bound
// (above 1e-250, underflow adds at most a few 2^-1074 to the sum, far below the bound).
std::optional<Sign> det3_sign_within_bound(double det, double permanent) {
  constexpr double kHalfUlp = 0.5 * std::numeric_limits<double>::epsilon();  // 2^-53
  constexpr double kErrboundA = (7.0 + 56.0 * kHalfUlp) * kHalfUlp;
  if (!(permanent > 1e-250) || !(permanent < 1e250)) return std::nullopt;
  const double bound = kErrboundA * permanent;
  if (det > bound) return Sign::Positive;
  if (det < -bound) return Sign::Negative;
  return std::nullopt;
}

// det[u, v, w] evaluated in that order, and its sign where the bound above decides.
std::optional<Sign> det3_filter(const Vec3& u, const Vec3& v, const Vec3& w) {
  const double m0 = v.y() * w.z() - v.z() * w.y(), m1 = v.z() * w.x() - v.x() * w.z(),
               m2 = v.x() * w.y() - v.y() * w.x();
  const double det = u.x() * m0 + u.y() * m1 + u.z() * m2;
  const double permanent = std::abs(u.x()) * (std::abs(v.y() * w.z()) + std::abs(v.z() * w.y())) +
                           std::abs(u.y()) * (std::abs(v.z() * w.x()) + std::abs(v.x() * w.z())) +
                           std::abs(u.z()) * (std::abs(v.x() * w.y()) + std::abs(v.y() * w.x()));
  return det3_sign_within_bound(det, permanent);
}

// The exact stages of orient3d (d a point) and orient_direction (d a direction): the sign of
// det[b − a, c − a, d − a] or det[b − a, c − a, d] in interval arithmetic, then in Mpzf when
// the interval holds zero. Out of line, so that the filtered callers stay small functions.
[[gnu::noinline, gnu::cold]] Sign det3_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                            bool d_is_point) {
  return internal::filtered_sign([&](auto zero) {
    using T = decltype(zero);
    T u[3], v[3], w[3];
    for (int i = 0; i < 3; ++i) {
      u[i] = T(b[i]) - T(a[i]);
      v[i] = T(c[i]) - T(a[i]);
      w[i] = d_is_point ? T(d[i]) - T(a[i]) : T(d[i]);
    }
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
  });
}

}  // namespace

Sign orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  if (const auto s = det3_filter(b - a, c - a, d - a)) return *s;
  // Two equal points make the determinant exactly zero; the interval stage cannot see that and
  // Mpzf costs a few hundred ns with allocations. Callers ask this often (a face's plane
  // against a neighbour list that holds the face's own corners).
  if (d == a || d == b || d == c || a == b || a == c || b == c) return Sign::Zero;
  // Exactly zero (four exactly coplanar points: a planar quadrilateral) is what the filter
  // leaves most; expansions decide it where the differences are exact, without Mpzf.
  if (const auto s = internal::expansion::orient3d(a.data(), b.data(), c.data(), d.data(), true)) return *s;
  return det3_exact(a, b, c, d, true);
}

PlaneOrientation::PlaneOrientation(const Vec3& a, const Vec3& b, const Vec3& c) : a_(a), b_(b), c_(c) {
  const Vec3 u = b - a, v = c - a;
  cross_ = Vec3(u.y() * v.z() - u.z() * v.y(), u.z() * v.x() - u.x() * v.z(), u.x() * v.y() - u.y() * v.x());
  absolute_ = Vec3(std::abs(u.y() * v.z()) + std::abs(u.z() * v.y()), std::abs(u.z() * v.x()) + std::abs(u.x() * v.z()),
                   std::abs(u.x() * v.y()) + std::abs(u.y() * v.x()));
}

// det[u, v, w] = w·(u × v): det3_filter's evaluation with the rows in the order (w, u, v), the
// same structure (each rounded difference times a 2 × 2 minor of rounded differences, summed
// left to right), so the same bound errboundA · permanent holds.
Sign PlaneOrientation::operator()(const Vec3& x) const {
  const Vec3 w = x - a_;
  const double det = w.x() * cross_.x() + w.y() * cross_.y() + w.z() * cross_.z();
  const double permanent =
      std::abs(w.x()) * absolute_.x() + std::abs(w.y()) * absolute_.y() + std::abs(w.z()) * absolute_.z();
  if (const auto s = det3_sign_within_bound(det, permanent)) return *s;
  return orient3d(a_, b_, c_, x);
}

Sign orient_direction(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  if (const auto s = det3_filter(b - a, c - a, d)) return *s;
  if (const auto s = internal::expansion::orient3d(a.data(), b.data(), c.data(), d.data(), false)) return *s;
  return det3_exact(a, b, c, d, false);
}

bool parallel_to(const Vec3& a, const Vec3& b, const Vec3& d) {
  // Filter: a cross product clearly away from zero (far beyond the rounding of b − a and of
  // the products) decides; the exact test decides the rest.
  const Vec3 e = b - a;
  if (e.cross(d).cwiseAbs().maxCoeff() > 1e-10 * e.cwiseAbs().maxCoeff() * d.cwiseAbs().maxCoeff())
    return false;
  using Q = CGAL::Mpzf;
  const Q x[3] = {Q(b.x()) - Q(a.x()), Q(b.y()) - Q(a.y()), Q(b.z()) - Q(a.z())};
  const Q y[3] = {Q(d.x()), Q(d.y()), Q(d.z())};
  return CGAL::sign(x[1] * y[2] - x[2] * y[1]) == CGAL::ZERO &&
         CGAL::sign(x[2] * y[0] - x[0] * y[2]) == CGAL::ZERO &&
         CGAL::sign(x[0] * y[1] - x[1] * y[0]) == CGAL::ZERO;
}

Sign orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  return to_sign(CGAL::orientation(cg(a), cg(b), cg(c)));
}

Sign side_of_plane(const Plane& plane, const Vec3& p) {
  const Vec4& k = plane.coefficients;
  // Static filter first (no change of the rounding mode, which costs more than the sum): the
  // double sum of the four terms is within γ4·Σ|terms| of the exact value (Higham, eq. 3.5;
  // no fused multiply-add, -ffp-contract=off), plus a few subnormal ulps when a product
  // underflows. 2e-15 exceeds γ4 even for a directed rounding mode (unit 2u: γ4 ≈ 8.9e-16)
  // and covers the rounding of the bound itself; an overflow makes the bound infinite or the
  // value NaN, and both fall through.
  {
    const double a = k[0] * p.x(), b = k[1] * p.y(), c = k[2] * p.z();
    const double v = ((a + b) + c) + k[3];
    const double bound = 2e-15 * (((std::abs(a) + std::abs(b)) + std::abs(c)) + std::abs(k[3])) + 1e-300;
    if (v > bound) return Sign::Positive;
    if (v < -bound) return Sign::Negative;
  }
  // Interval arithmetic decides almost always.
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

// ---- ExactPlane ----

namespace {

constexpr double kUnit = 0.5 * std::numeric_limits<double>::epsilon();  // u = 2^-53
constexpr double kTiny = std::numeric_limits<double>::denorm_min();
// γ_n of Higham: |fl(Σ_{i<n} x_i·y_i) − Σ x_i·y_i| ≤ γ_n · Σ |x_i·y_i| (no underflow).
constexpr double gamma_n(int n) { return n * kUnit / (1 - n * kUnit); }
// Covers the few roundings of computing a bound in double (each a factor ≥ 1 − u).
constexpr double kBoundInflation = 1 + 8 * kUnit;

using internal::filtered_sign;


}  // namespace

namespace {

// Coefficient i of exact coefficients as T: itself in the Mpzf stage, its enclosure in the
// interval stage (a positive multiple of the same function, so every sign agrees).
template <class T>
T coefficient(const internal::ExactCoefficients& e, size_t i) {
  if constexpr (std::is_same_v<T, CGAL::Mpzf>) {
    return e.c[i];
  } else {
    return T(e.interval[i].first, e.interval[i].second);
  }
}

}  // namespace

// f(p) exactly (T = Mpzf) or enclosed (T = Interval, under upward rounding).
template <class T>
T exact_plane_value(const ExactPlane& f, const Vec3& p) {
  T value(0);
  if (const internal::ExactCoefficients* e = f.exact_.get()) {
    value = coefficient<T>(*e, 0) * T(p.x()) + coefficient<T>(*e, 1) * T(p.y()) +
            coefficient<T>(*e, 2) * T(p.z()) + coefficient<T>(*e, 3);
  } else if (f.by_points_) {
    const Vec3 &a = f.points_[0], &b = f.points_[1], &c = f.points_[2];
    const T bax = T(b.x()) - T(a.x()), bay = T(b.y()) - T(a.y()), baz = T(b.z()) - T(a.z());
    // Through a direction: c is the direction itself, not a point.
    const T cax = f.by_direction_ ? T(c.x()) : T(c.x()) - T(a.x());
    const T cay = f.by_direction_ ? T(c.y()) : T(c.y()) - T(a.y());
    const T caz = f.by_direction_ ? T(c.z()) : T(c.z()) - T(a.z());
    const T pax = T(p.x()) - T(a.x()), pay = T(p.y()) - T(a.y()), paz = T(p.z()) - T(a.z());
    const T det = bax * (cay * paz - caz * pay) - bay * (cax * paz - caz * pax) +
                  baz * (cax * pay - cay * pax);
    value = T(0) - det;  // f = −det[b − a, c − a, p − a]: Positive on the inner side
  } else {
    const Vec4& k = f.plane_.coefficients;
    value = T(k[0]) * T(p.x()) + T(k[1]) * T(p.y()) + T(k[2]) * T(p.z()) + T(k[3]);
  }
  return f.negated_ ? T(0) - value : value;
}

ExactPlane ExactPlane::through(const Vec3& a, const Vec3& b, const Vec3& c) {
  if (!a.allFinite() || !b.allFinite() || !c.allFinite())
    throw InvalidInput("plane through a point with a coordinate that is not finite");
  return build(a, b, c, false);  // throws for collinear points
}

ExactPlane ExactPlane::through_direction(const Vec3& a, const Vec3& b, const Vec3& d) {
  if (!a.allFinite() || !b.allFinite() || !d.allFinite())
    throw InvalidInput("plane through a point or direction that is not finite");
  // Parallel to d: the exact cross product (b − a) × d must not vanish.
  ExactPlane probe;
  probe.by_points_ = true;
  probe.by_direction_ = true;
  probe.points_ = {a, b, d};
  // Degenerate iff f vanishes identically (f(a) = 0): test it at a moved along each axis.
  bool degenerate = true;
  for (int i = 0; i < 3 && degenerate; ++i) {
    Vec3 q = a;
    q[i] += std::abs(a[i]) + 1;  // differs from a[i] whatever the rounding
    degenerate = filtered_sign([&](auto zero) {
                   return exact_plane_value<decltype(zero)>(probe, q);
                 }) == Sign::Zero;
  }
  if (degenerate) throw InvalidInput("plane through two points parallel to their own direction");
  return build(a, b, d, true);
}

ExactPlane ExactPlane::build(const Vec3& a, const Vec3& b, const Vec3& c, bool direction) {
  ExactPlane f;
  f.by_points_ = true;
  f.by_direction_ = direction;
  f.points_ = {a, b, c};
  // n = (c − a) × (b − a) and k = −n·a, so that n·p + k = −det[b − a, c − a, p − a] = f(p),
  // computed in double (round to nearest, no contraction) with a static bound on each error
  // (Higham, ch. 3; u = 2^-53, γ_n = nu/(1 − nu)):
  //  - a difference d = fl(q − a) is within γ1·|d| of q − a (subtraction never underflows);
  //  - n0 = fl(fl(cay·baz) − fl(caz·bay)): each exact product is the computed factors' product
  //    times (1 + θ2), the computed one times (1 + θ2), so |n0 − N0| ≤ 2γ2·P0 + 2·tiny with
  //    P0 = |cay·baz| + |caz·bay| (tiny: the underflow of the two products);
  //  - k = −((n0·ax + n1·ay) + n2·az): |k − K| ≤ Σ rad_i·|a_i| + γ3·Σ|n_i·a_i| + 3·tiny.
  // The bounds are themselves computed in double: (1 + 16u) covers their own few roundings,
  // and 2γ2·(1 + 16u) < γ5.
  const double bax = b.x() - a.x(), bay = b.y() - a.y(), baz = b.z() - a.z();
  const double cax = direction ? c.x() : c.x() - a.x();
  const double cay = direction ? c.y() : c.y() - a.y();
  const double caz = direction ? c.z() : c.z() - a.z();
  const double p0 = cay * baz, q0 = caz * bay, p1 = caz * bax, q1 = cax * baz, p2 = cax * bay,
               q2 = cay * bax;
  const double mid[3] = {p0 - q0, p1 - q1, p2 - q2};
  constexpr double kGrow = 1 + 16 * kUnit;
  double rad[4];
  rad[0] = (gamma_n(5) * (std::abs(p0) + std::abs(q0)) + 2 * kTiny) * kGrow;
  rad[1] = (gamma_n(5) * (std::abs(p1) + std::abs(q1)) + 2 * kTiny) * kGrow;
  rad[2] = (gamma_n(5) * (std::abs(p2) + std::abs(q2)) + 2 * kTiny) * kGrow;
  const double t0 = mid[0] * a.x(), t1 = mid[1] * a.y(), t2 = mid[2] * a.z();
  const double k = -((t0 + t1) + t2);
  rad[3] = (rad[0] * std::abs(a.x()) + rad[1] * std::abs(a.y()) + rad[2] * std::abs(a.z()) +
            gamma_n(3) * (std::abs(t0) + std::abs(t1) + std::abs(t2)) + 3 * kTiny) *
           kGrow;
  // Three points: collinear iff the exact normal is zero. A computed component above its
  // bound proves it is not (almost always); only otherwise is the exact test asked.
  if (!direction && std::abs(mid[0]) <= rad[0] && std::abs(mid[1]) <= rad[1] &&
      std::abs(mid[2]) <= rad[2] && collinear(a, b, c))
    throw InvalidInput("plane through three collinear points");
  // A sliver whose exact normal is below the rounding of its products can come out as n = 0:
  // scale by the radii then (the double form is 0 within its bound, so every sign is exact).
  const double largest = std::max({std::abs(mid[0]), std::abs(mid[1]), std::abs(mid[2])});
  const int e = std::ilogb(largest > 0 ? largest : std::max({rad[0], rad[1], rad[2]}));
  // x·2^-e: one multiplication by the power of two when it is a normal double (the same
  // correctly rounded result as std::ldexp, without a library call per coefficient).
  const double power = e > -1000 && e < 1000 ? std::ldexp(1.0, -e) : 0;
  const auto scaled = [&](double x) { return power != 0 ? x * power : std::ldexp(x, -e); };
  double slope = 0;
  for (int i = 0; i < 3; ++i) {
    // Scaling by 2^-e is exact except in the subnormal range (half an ulp there: kTiny).
    f.n_[i] = scaled(mid[i]);
    const double r = scaled(rad[i]) * (1 + 2 * kUnit) + kTiny;
    slope += gamma_n(4) * std::abs(f.n_[i]) + r;
  }
  f.k_ = scaled(k);
  const double rk = scaled(rad[3]) * (1 + 2 * kUnit) + kTiny;
  f.slope_ = slope * kBoundInflation;
  f.offset_ = (gamma_n(4) * std::abs(f.k_) + rk + 8 * kTiny) * kBoundInflation;
  if (!std::isfinite(f.k_) || !std::isfinite(f.slope_) || !std::isfinite(f.offset_))
    throw InvalidInput("plane through points too far from the origin");
  return f;
}

ExactPlane ExactPlane::from_coefficients(const Plane& plane) {
  const Vec4& c = plane.coefficients;
  if (!c.allFinite()) throw InvalidInput("plane with a coefficient that is not finite");
  if (c.head<3>().isZero()) throw InvalidInput("plane with a zero normal");
  ExactPlane f;
  f.plane_ = plane;
  const int e = std::ilogb(c.head<3>().cwiseAbs().maxCoeff());
  double slope = 0;
  for (int i = 0; i < 3; ++i) {
    f.n_[i] = std::ldexp(c[i], -e);  // exact outside the subnormal range
    slope += gamma_n(4) * std::abs(f.n_[i]) + kTiny;
  }
  f.k_ = std::ldexp(c[3], -e);
  if (!std::isfinite(f.k_))
    throw InvalidInput("plane too far from the origin for the size of its normal");
  f.slope_ = slope * kBoundInflation;
  f.offset_ = (gamma_n(4) * std::abs(f.k_) + 9 * kTiny) * kBoundInflation;
  return f;
}

namespace {

// x = m·2^e with m in [0.5, 1) truncated toward zero (|m − exact| < 2^-53), or (0, 0).
std::pair<double, long> mantissa_exponent(const CGAL::Mpzf& x) {
  if (CGAL::sign(x) == CGAL::ZERO) return {0.0, 0};
  // Exactly as a rational (Mpzf's own export, any exponent); its denominator is a power of 2.
  const CGAL::Gmpq q(x);
  long e = 0;
  const double m = mpz_get_d_2exp(&e, mpq_numref(q.mpq()));
  return {m, e - static_cast<long>(mpz_sizeinbase(mpq_denref(q.mpq()), 2)) + 1};
}

}  // namespace

ExactPlane ExactPlane::from_exact(std::shared_ptr<internal::ExactCoefficients> coefficients) {
  if (!coefficients) throw InvalidInput("plane without coefficients");
  const auto& c = coefficients->c;
  std::array<std::pair<double, long>, 4> me;
  for (size_t i = 0; i < 4; ++i) me[i] = mantissa_exponent(c[i]);
  long top = std::numeric_limits<long>::min();
  for (size_t i = 0; i < 3; ++i)
    if (me[i].first != 0) top = std::max(top, me[i].second);
  if (top == std::numeric_limits<long>::min()) throw InvalidInput("plane with a zero normal");
  // F = f / 2^(top − 1): the largest |n_i| in [1, 2). Each coefficient of F is m·2^(e − top + 1),
  // m truncated (relative error below 2u); ldexp rounds only in the subnormal range (kTiny).
  ExactPlane f;
  double approx[4], radius[4];
  for (size_t i = 0; i < 4; ++i) {
    const long shift = me[i].second - top + 1;
    if (me[i].first == 0 || shift < -1100) {
      approx[i] = 0.0;  // zero, or below the subnormal range
      radius[i] = me[i].first == 0 ? 0.0 : kTiny;
    } else {
      if (shift > 1100) throw InvalidInput("plane too far from the origin for the size of its normal");
      approx[i] = std::ldexp(me[i].first, static_cast<int>(shift));
      radius[i] = 4 * kUnit * std::abs(approx[i]) + 2 * kTiny;
    }
  }
  if (!std::isfinite(approx[3]) || !std::isfinite(radius[3]))
    throw InvalidInput("plane too far from the origin for the size of its normal");
  double slope = 0;
  for (size_t i = 0; i < 4; ++i) {
    coefficients->interval[i] = {approx[i] - radius[i], approx[i] + radius[i]};
    if (i < 3) {
      f.n_[static_cast<int>(i)] = approx[i];
      slope += gamma_n(4) * std::abs(approx[i]) + radius[i];
    }
  }
  f.k_ = approx[3];
  f.slope_ = slope * kBoundInflation;
  f.offset_ = (gamma_n(4) * std::abs(f.k_) + radius[3] + 8 * kTiny) * kBoundInflation;
  f.exact_ = std::move(coefficients);
  return f;
}

ExactPlane ExactPlane::pencil(const ExactPlane& f, const ExactPlane& g, const Vec3& e,
                              bool e_is_direction) {
  if (!e.allFinite()) throw InvalidInput("pencil plane through a point that is not finite");
  using Q = CGAL::Mpzf;
  const std::array<Q, 4> a = internal::exact_coefficients(f), b = internal::exact_coefficients(g);
  const Q ex(e.x()), ey(e.y()), ez(e.z());
  Q fe = a[0] * ex + a[1] * ey + a[2] * ez, ge = b[0] * ex + b[1] * ey + b[2] * ez;
  if (!e_is_direction) {
    fe = fe + a[3];
    ge = ge + b[3];
  }
  auto h = std::make_shared<internal::ExactCoefficients>();
  for (size_t i = 0; i < 4; ++i) h->c[i] = ge * a[i] - fe * b[i];
  if (CGAL::sign(h->c[0]) == CGAL::ZERO && CGAL::sign(h->c[1]) == CGAL::ZERO &&
      CGAL::sign(h->c[2]) == CGAL::ZERO)
    throw InvalidInput("pencil plane of two parallel planes, or through a point on both");
  return from_exact(std::move(h));
}

namespace internal {

std::array<CGAL::Mpzf, 4> exact_coefficients(const ExactPlane& f) {
  using Q = CGAL::Mpzf;
  std::array<Q, 4> h{Q(0), Q(0), Q(0), Q(0)};
  if (const ExactCoefficients* e = f.exact_coefficients()) {
    h = e->c;
  } else if (f.by_points()) {
    // f(p) = −det[b − a, c', p − a] = (p − a)·(c' × (b − a)), c' = c − a or the direction c.
    const auto& p = f.points();
    std::array<Q, 3> ba, ca;
    for (int i = 0; i < 3; ++i) {
      ba[static_cast<size_t>(i)] = Q(p[1][i]) - Q(p[0][i]);
      ca[static_cast<size_t>(i)] = f.by_direction() ? Q(p[2][i]) : Q(p[2][i]) - Q(p[0][i]);
    }
    h[0] = ca[1] * ba[2] - ca[2] * ba[1];
    h[1] = ca[2] * ba[0] - ca[0] * ba[2];
    h[2] = ca[0] * ba[1] - ca[1] * ba[0];
    h[3] = Q(0) - (h[0] * Q(p[0][0]) + h[1] * Q(p[0][1]) + h[2] * Q(p[0][2]));
  } else {
    const Vec4& c = f.coefficients().coefficients;
    for (int i = 0; i < 4; ++i) h[static_cast<size_t>(i)] = Q(c[i]);
  }
  if (f.negated())
    for (Q& v : h) v = Q(0) - v;
  return h;
}

ExactPlane plane_from_exact(const std::array<CGAL::Mpzf, 4>& c) {
  auto h = std::make_shared<ExactCoefficients>();
  h->c = c;
  return ExactPlane::from_exact(std::move(h));
}

}  // namespace internal

ExactPlane ExactPlane::flipped() const {
  ExactPlane f = *this;
  f.negated_ = !negated_;
  f.n_ = -n_;
  f.k_ = -k_;
  return f;
}

Sign side_of_plane(const ExactPlane& f, const Vec3& p) {
  const double v = f.value(p), bound = f.error_bound(p.cwiseAbs().maxCoeff());
  if (v > bound) return Sign::Positive;
  if (v < -bound) return Sign::Negative;
  // One of the plane's own defining points (a vertex shared by neighbouring faces, an edge end
  // on a silhouette plane through it) lies on it: zero without exact arithmetic.
  if (f.by_points()) {
    const auto& q = f.points();
    if (p == q[0] || p == q[1] || (!f.by_direction() && p == q[2])) return Sign::Zero;
  }
  return filtered_sign([&](auto zero) { return exact_plane_value<decltype(zero)>(f, p); });
}

Sign direction_sign(const ExactPlane& f, const Vec3& d) {
  // Static filter from the documented bound of the double form: |value(p) − F(p)| ≤
  // error_bound(max |p_i|) with F = f / 2^e affine, so value(d) − value(0) is within
  // error_bound(max |d_i|) + error_bound(0) of F(d) − F(0) = n·d / 2^e, plus the rounding of
  // the subtraction. It decides unless n·d is within rounding of 0.
  const double diff = f.value(d) - f.value(0, 0, 0);
  const double bound =
      (f.error_bound(d.cwiseAbs().maxCoeff()) + f.error_bound(0)) * (1 + 4 * kUnit) +
      2 * kUnit * std::abs(diff);
  if (diff > bound) return Sign::Positive;
  if (diff < -bound) return Sign::Negative;
  return filtered_sign([&](auto zero) {
    using T = decltype(zero);
    T value(0);
    if (f.by_points()) {
      const auto& pts = f.points();
      const Vec3 &a = pts[0], &b = pts[1], &c = pts[2];
      const T bax = T(b.x()) - T(a.x()), bay = T(b.y()) - T(a.y()), baz = T(b.z()) - T(a.z());
      const T cax = f.by_direction() ? T(c.x()) : T(c.x()) - T(a.x());
      const T cay = f.by_direction() ? T(c.y()) : T(c.y()) - T(a.y());
      const T caz = f.by_direction() ? T(c.z()) : T(c.z()) - T(a.z());
      const T det = bax * (cay * T(d.z()) - caz * T(d.y())) - bay * (cax * T(d.z()) - caz * T(d.x())) +
                    baz * (cax * T(d.y()) - cay * T(d.x()));
      value = T(0) - det;
    } else if (const internal::ExactCoefficients* e = f.exact_coefficients()) {
      value = coefficient<T>(*e, 0) * T(d.x()) + coefficient<T>(*e, 1) * T(d.y()) + coefficient<T>(*e, 2) * T(d.z());
    } else {
      const Vec4& k = f.coefficients().coefficients;
      value = T(k[0]) * T(d.x()) + T(k[1]) * T(d.y()) + T(k[2]) * T(d.z());
    }
    return f.negated() ? T(0) - value : value;
  });
}

Sign compare_crossings(const ExactPlane& f, const ExactPlane& g, const Vec3& p, const Vec3& q) {
  return filtered_sign([&](auto zero) {
    using T = decltype(zero);
    const T fp = exact_plane_value<T>(f, p), fq = exact_plane_value<T>(f, q);
    const T gp = exact_plane_value<T>(g, p), gq = exact_plane_value<T>(g, q);
    // t_f − t_g = (g(p)·f(q) − f(p)·g(q)) / ((f(p) − f(q))·(g(p) − g(q))): same sign as
    // the product of the three factors.
    return (gp * fq - fp * gq) * (fp - fq) * (gp - gq);
  });
}

Sign compare_crossings_along(const ExactPlane& f, const Vec3& p, const Vec3& q, const Vec3& r,
                             const Vec3& s, int axis) {
  return filtered_sign([&](auto zero) {
    using T = decltype(zero);
    const T fp = exact_plane_value<T>(f, p), fq = exact_plane_value<T>(f, q);
    const T fr = exact_plane_value<T>(f, r), fs = exact_plane_value<T>(f, s);
    const T nx = fp * T(q[axis]) - fq * T(p[axis]), dx = fp - fq;
    const T ny = fr * T(s[axis]) - fs * T(r[axis]), dy = fr - fs;
    // X − Y = (nx·dy − ny·dx) / (dx·dy).
    return (nx * dy - ny * dx) * dx * dy;
  });
}

}  // namespace hedra
