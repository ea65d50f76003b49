// ExactPlane and its predicates (hedra/core/predicates.h): the double evaluation stays within its
// bound, and the exact predicates agree with rational arithmetic.
#include <gtest/gtest.h>

#include <random>

#include "testing/clip_fixtures.h"
#include "hedra/core/error.h"
#include "hedra/core/predicates.h"
#include "hedra/core/primitives.h"

namespace hedra {
namespace {

using testing::Rational;

Sign sign_of(const Rational& q) {
  return q > 0 ? Sign::Positive : (q < 0 ? Sign::Negative : Sign::Zero);
}

// F = f / 2^e: the double form's scale, recovered from a point where f is far from zero.
Rational scaled_exact(const ExactPlane& f, const Vec3& p, const Rational& scale) {
  return testing::exact_value(f, p) / scale;
}

TEST(ExactPlane, ValueStaysWithinItsBound) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 40; ++k) {
    const double scale = std::pow(10.0, k % 10 * 3 - 12);  // 1e-12 … 1e15
    const Vec3 a = scale * Vec3(u(rng), u(rng), u(rng)), b = scale * Vec3(u(rng), u(rng), u(rng)),
               c = scale * Vec3(u(rng), u(rng), u(rng));
    const ExactPlane by_points = ExactPlane::through(a, b, c);
    const ExactPlane by_coefficients =
        ExactPlane::from_coefficients(Plane(u(rng), u(rng), u(rng), scale * u(rng)));
    for (const ExactPlane& f : {by_points, by_coefficients, by_points.flipped()}) {
      // The power of two between f and its double form: exact ratio at a far point.
      const Vec3 far = a + 1e3 * scale * f.normal().normalized();
      const Rational ratio = testing::exact_value(f, far) / Rational(f.value(far));
      const double two_power = std::exp2(std::round(std::log2(testing::to_double(ratio))));
      for (int i = 0; i < 200; ++i) {
        const Vec3 p = i % 2 ? Vec3(scale * Vec3(u(rng), u(rng), u(rng)))
                             : Vec3(a + u(rng) * (b - a) + u(rng) * (c - a));  // near the plane
        const double m = p.cwiseAbs().maxCoeff();
        const Rational exact = scaled_exact(f, p, Rational(two_power));
        EXPECT_LE(testing::to_double(CGAL::abs(Rational(f.value(p)) - exact)), f.error_bound(m));
        EXPECT_EQ(side_of_plane(f, p), sign_of(exact));
      }
    }
  }
}

// The double form of a plane through three points is built in double with a static bound on
// its rounding (no interval arithmetic): the bound must hold, and every sign stay exact, where
// that rounding is largest: slivers whose normal is below the rounding of its products, small
// triangles far from the origin (k cancels), planes through a direction, and points exactly on
// the plane.
TEST(ExactPlane, SliversFarPlanesAndDirectionPlanesStayExact) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int bounded = 0, zero_normals = 0;
  for (int k = 0; k < 600; ++k) {
    const double offset = std::pow(10.0, k % 7 * 2 - 2), size = std::pow(10.0, -(k % 5));
    const Vec3 a = offset * Vec3(u(rng), u(rng), u(rng));
    const Vec3 d = size * Vec3(u(rng), u(rng), u(rng));
    Vec3 c = a + 2 * d;
    c[k % 3] = std::nextafter(c[k % 3], k % 2 ? 1e300 : -1e300);  // a sliver, a few ulps off
    if (k % 4 == 3) c += size * 1e-3 * Vec3(u(rng), u(rng), u(rng));  // thin, not a sliver
    const Vec3 b = a + d;
    if (collinear(a, b, c)) continue;
    const ExactPlane f =
        k % 6 == 5 ? ExactPlane::through_direction(a, b, c - b) : ExactPlane::through(a, b, c);
    if (f.normal().isZero()) ++zero_normals;
    const Vec3 far = a + offset * 1e3 * Vec3(u(rng), u(rng), u(rng));
    const Rational ratio_at_far = testing::exact_value(f, far);
    const bool well_scaled = std::abs(f.value(far)) > 1e3 * f.error_bound(far.cwiseAbs().maxCoeff());
    const double two_power =
        well_scaled ? std::exp2(std::round(std::log2(testing::to_double(ratio_at_far / Rational(f.value(far))))))
                    : 0;
    for (int i = 0; i < 60; ++i) {
      Vec3 p = a + u(rng) * (b - a) + u(rng) * (c - a);  // near the plane
      if (i % 3 == 1) p[i % 3] = std::nextafter(p[i % 3], 1e300);
      if (i % 3 == 2) p = i % 2 ? b : c;
      const Rational exact = testing::exact_value(f, p);
      EXPECT_EQ(side_of_plane(f, p), sign_of(exact)) << k << " " << i;
      if (well_scaled) {
        const double m = p.cwiseAbs().maxCoeff();
        EXPECT_LE(testing::to_double(CGAL::abs(Rational(f.value(p)) - exact / Rational(two_power))),
                  f.error_bound(m));
        ++bounded;
      }
    }
  }
  EXPECT_GT(bounded, 10000);
  // Points exactly on a plane through integer points, far from the origin: Zero.
  const Vec3 a(1e9 + 3, -2e9 + 7, 5e8 + 1), b = a + Vec3(5, 1, -3), c = a + Vec3(-2, 7, 4);
  const ExactPlane f = ExactPlane::through(a, b, c);
  for (int i = -5; i <= 5; ++i)
    EXPECT_EQ(side_of_plane(f, a + i * (b - a) - 2 * i * (c - a)), Sign::Zero);
  EXPECT_EQ(side_of_plane(f, a + (b - a) + Vec3(0, 0, 1)), sign_of(testing::exact_value(f, a + (b - a) + Vec3(0, 0, 1))));
  (void)zero_normals;
}

TEST(ExactPlane, FacesOfABodyAgreeWithFaceSide) {
  const Body b = testing::icosahedron(3).rotated_x(17);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int f = 0; f < b.face_count(); ++f) {
    const auto& s = b.support(f);
    const ExactPlane plane =
        ExactPlane::through(b.vertices()[s[0]], b.vertices()[s[1]], b.vertices()[s[2]]);
    for (const Vec3& v : b.vertices()) EXPECT_EQ(side_of_plane(plane, v), b.face_side(f, v));
    for (int i = 0; i < 50; ++i) {
      const Vec3 p(u(rng), u(rng), u(rng));
      EXPECT_EQ(side_of_plane(plane, p), b.face_side(f, p));
      EXPECT_EQ(side_of_plane(plane.flipped(), p), -b.face_side(f, p));
    }
  }
  // Coefficient planes decide as side_of_plane(Plane) does.
  const Plane q(1, 1, 1, -1);
  const ExactPlane e = ExactPlane::from_coefficients(q);
  for (double z : {0.25, std::nextafter(0.25, 1.0), std::nextafter(0.25, 0.0)})
    EXPECT_EQ(side_of_plane(e, Vec3(0.5, 0.25, z)), side_of_plane(q, Vec3(0.5, 0.25, z)));
}

TEST(ExactPlane, CompareCrossingsIsExact) {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(-1, 1);
  // Planes through a common line: a segment through that line crosses both at the same point.
  const Vec3 a(0.125, 0.25, 0.375), b(0.7, -0.4, 0.9);
  const ExactPlane f = ExactPlane::through(a, b, {1, 1, 1});
  const ExactPlane g = ExactPlane::through(a, b, {-1, 2, 0.5});
  const Vec3 p(-3, -3, -3), q = 2 * a - p;  // through a, exactly (dyadic coordinates)
  EXPECT_EQ(compare_crossings(f, g, p, q), Sign::Zero);
  EXPECT_EQ(compare_crossings(f, g, p, q + Vec3(0, 0, 1e-12)),
            -compare_crossings(g, f, p, q + Vec3(0, 0, 1e-12)));
  int decided = 0;
  for (int i = 0; i < 3000; ++i) {
    const ExactPlane f1 = ExactPlane::from_coefficients(Plane(u(rng), u(rng), u(rng), u(rng)));
    const ExactPlane f2 = ExactPlane::through(
        Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)));
    const Vec3 s(u(rng), u(rng), u(rng)), t(u(rng), u(rng), u(rng));
    const Rational w1 = testing::exact_value(f1, s), e1 = testing::exact_value(f1, t);
    const Rational w2 = testing::exact_value(f2, s), e2 = testing::exact_value(f2, t);
    if (w1 == e1 || w2 == e2) continue;
    EXPECT_EQ(compare_crossings(f1, f2, s, t), sign_of(w1 / (w1 - e1) - w2 / (w2 - e2)));
    // Along an axis: the exact crossing points' coordinates.
    const Vec3 r(u(rng), u(rng), u(rng)), v(u(rng), u(rng), u(rng));
    const Rational wr = testing::exact_value(f1, r), ev = testing::exact_value(f1, v);
    if (wr == ev) continue;
    const int axis = i % 3;
    const Rational x1 = Rational(s[axis]) + (Rational(t[axis]) - s[axis]) * (w1 / (w1 - e1));
    const Rational x2 = Rational(r[axis]) + (Rational(v[axis]) - r[axis]) * (wr / (wr - ev));
    EXPECT_EQ(compare_crossings_along(f1, s, t, r, v, axis), sign_of(x1 - x2));
    ++decided;
  }
  EXPECT_GT(decided, 2000);
}

// A pencil plane h = g(E)·f − f(E)·g (ExactPlane::pencil): its exact coefficients are
// multiprecision numbers, its double form is a rounded multiple of them. Reference: h's
// definition in rational arithmetic on f's and g's own exact values.
Rational pencil_value(const ExactPlane& f, const ExactPlane& g, const Vec3& e, bool direction,
                      const Vec3& p) {
  const auto at = [&](const ExactPlane& x) {
    return direction ? testing::exact_value(x, e) - testing::exact_value(x, Vec3::Zero())
                     : testing::exact_value(x, e);
  };
  return at(g) * testing::exact_value(f, p) - at(f) * testing::exact_value(g, p);
}

TEST(ExactPlane, PencilPlanesAreExactThroughTheirLineAndTheViewpoint) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int near_zero = 0;
  for (int k = 0; k < 60; ++k) {
    const double scale = std::pow(10.0, k % 6 * 5 - 12);  // 1e-12 … 1e13
    const Vec3 a = scale * Vec3(u(rng), u(rng), u(rng)), b = scale * Vec3(u(rng), u(rng), u(rng)),
               c = scale * Vec3(u(rng), u(rng), u(rng)), d = scale * Vec3(u(rng), u(rng), u(rng));
    // Two faces of a convex piece meeting at edge ab: f through (a, b, c), g through (b, a, d).
    const ExactPlane f = ExactPlane::through(a, b, c), g = ExactPlane::through(b, a, d);
    const bool direction = k % 2;
    const Vec3 e = direction ? Vec3(u(rng), u(rng), u(rng)) : Vec3(3 * scale * Vec3(u(rng), u(rng), u(rng)));
    const ExactPlane h = ExactPlane::pencil(f, g, e, direction);
    ASSERT_TRUE(h.by_exact());
    // On the common line of f and g, and through the viewpoint (or parallel to the direction).
    EXPECT_EQ(side_of_plane(h, a), Sign::Zero);
    EXPECT_EQ(side_of_plane(h, b), Sign::Zero);
    if (direction) {
      EXPECT_EQ(direction_sign(h, e), Sign::Zero);
    } else {
      EXPECT_EQ(side_of_plane(h, e), Sign::Zero);
    }
    // The power of two between h's exact function and its double form.
    const Vec3 far = a + 1e3 * scale * h.normal().normalized();
    const Rational ratio = pencil_value(f, g, e, direction, far) / Rational(h.value(far));
    ASSERT_GT(ratio, 0);
    for (int i = 0; i < 100; ++i) {
      // Random points, points near the edge and points on the line through a and b.
      const double t = u(rng);
      const Vec3 p = i % 3 == 0 ? Vec3(scale * Vec3(u(rng), u(rng), u(rng)))
                     : i % 3 == 1 ? Vec3(a + t * (b - a) + 1e-9 * scale * Vec3(u(rng), u(rng), u(rng)))
                                  : Vec3(a + t * (b - a));
      const Rational exact = pencil_value(f, g, e, direction, p);
      EXPECT_EQ(side_of_plane(h, p), sign_of(exact));
      EXPECT_EQ(side_of_plane(h.flipped(), p), -sign_of(exact));
      EXPECT_LE(testing::to_double(CGAL::abs(Rational(h.value(p)) - exact / ratio)),
                h.error_bound(p.cwiseAbs().maxCoeff()));
      if (CGAL::abs(exact / ratio) < h.error_bound(p.cwiseAbs().maxCoeff())) ++near_zero;
      // direction_sign: n_h·v.
      const Vec3 v(u(rng), u(rng), u(rng));
      const Rational along = pencil_value(f, g, e, direction, v) - pencil_value(f, g, e, direction, Vec3::Zero());
      EXPECT_EQ(direction_sign(h, v), sign_of(along));
    }
    // The pencil of a pencil (coefficients already multiprecision): still exact.
    const ExactPlane h2 = ExactPlane::pencil(h, f, c, false);
    for (int i = 0; i < 20; ++i) {
      const Vec3 p = scale * Vec3(u(rng), u(rng), u(rng));
      const Rational hc = pencil_value(f, g, e, direction, c), fc = testing::exact_value(f, c);
      const Rational exact = fc * pencil_value(f, g, e, direction, p) - hc * testing::exact_value(f, p);
      EXPECT_EQ(side_of_plane(h2, p), sign_of(exact));
    }
    EXPECT_EQ(side_of_plane(h2, c), Sign::Zero);
  }
  EXPECT_GT(near_zero, 200);  // the exact stage was asked
}

TEST(ExactPlane, PencilOfParallelPlanesIsRefused) {
  const ExactPlane f = ExactPlane::through({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const ExactPlane g = ExactPlane::through({0, 0, 1}, {0, 1, 1}, {1, 0, 1});
  // One plane twice: h vanishes identically.
  EXPECT_THROW(ExactPlane::pencil(f, f, {0, 0, 5}, false), InvalidInput);
  // Parallel planes seen along their normal: h is a nonzero constant, no plane.
  EXPECT_THROW(ExactPlane::pencil(f, g, {0, 0, 1}, true), InvalidInput);
  // Parallel planes and a point: the parallel plane through the point (their line is at
  // infinity).
  const ExactPlane h = ExactPlane::pencil(f, g, {0, 0, 5}, false);
  EXPECT_EQ(side_of_plane(h, {3, -2, 5}), Sign::Zero);
  EXPECT_NE(side_of_plane(h, {3, -2, 4}), Sign::Zero);
}

TEST(ExactPlane, BadPlanes) {
  EXPECT_THROW(ExactPlane::through({0, 0, 0}, {1, 1, 1}, {2, 2, 2}), InvalidInput);
  EXPECT_THROW(ExactPlane::from_coefficients(Plane(0, 0, 0, 1)), InvalidInput);
  EXPECT_THROW(ExactPlane::from_coefficients(Plane(NAN, 0, 1, 1)), InvalidInput);
}

}  // namespace
}  // namespace hedra
