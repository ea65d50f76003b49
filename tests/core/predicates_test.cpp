#include "hedra/core/predicates.h"

#include <gtest/gtest.h>

#include <gmpxx.h>

#include <array>
#include <cmath>
#include <random>

namespace hedra {
namespace {

TEST(Predicates, Orient3dSignConvention) {
  // Counter-clockwise seen from +z: normal +z; a point above is Positive.
  Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(orient3d(a, b, c, Vec3(0.2, 0.2, 1)), Sign::Positive);
  EXPECT_EQ(orient3d(a, b, c, Vec3(0.2, 0.2, -1)), Sign::Negative);
  EXPECT_EQ(orient3d(a, b, c, Vec3(5, 7, 0)), Sign::Zero);
}

TEST(Predicates, ExactWhereFloatingPointFails) {
  // The plane x + y + z = 1e16 through three far points; d lies exactly on it and d + (0,0,1)
  // one unit above. The determinant's terms are ~1e32, so a plain double evaluation cannot
  // see the unit; the filtered exact predicate does.
  Vec3 a(1e16, 0, 0), b(0, 1e16, 0), c(0, 0, 1e16);
  const double z = 1e16 - 9007199254740992.0;  // 1e16 − 2^53, exact
  Vec3 d(4503599627370496.0, 4503599627370496.0, z);  // 2^52 + 2^52 + z = 1e16
  EXPECT_EQ(orient3d(a, b, c, d), Sign::Zero);
  EXPECT_EQ(orient3d(a, b, c, d + Vec3(0, 0, 1)), Sign::Positive);
  EXPECT_EQ(orient3d(a, b, c, d - Vec3(0, 0, 1)), Sign::Negative);
}

TEST(Predicates, Orient3dOfTwoEqualPointsIsZeroEvenWhereTheFilterCannotDecide) {
  // Coordinates near 1e200: the permanent overflows, so the static filter passes every
  // question on; with two equal points the answer is Zero before any exact stage. A point a
  // hair off the plane (one ulp of 1e200 in z) stays decided by the exact stages.
  const Vec3 a(1e200, 0, 0), b(0, 1e200, 0), c(0, 0, 1e200);
  EXPECT_EQ(orient3d(a, b, c, a), Sign::Zero);
  EXPECT_EQ(orient3d(a, b, c, c), Sign::Zero);
  EXPECT_EQ(orient3d(a, a, c, Vec3(1, 2, 3)), Sign::Zero);
  EXPECT_EQ(orient3d(a, b, b, Vec3(1, 2, 3)), Sign::Zero);
  EXPECT_EQ(orient3d(a, b, c, Vec3(0, 0, std::nextafter(1e200, 2e200))), Sign::Positive);
  EXPECT_EQ(orient3d(a, b, c, Vec3(0, 0, std::nextafter(1e200, 0.0))), Sign::Negative);
}

TEST(Predicates, SideOfPlaneIsExact) {
  Plane p(1, 1, 1, -1);
  EXPECT_EQ(side_of_plane(p, Vec3(0.5, 0.25, 0.25)), Sign::Zero);
  EXPECT_EQ(side_of_plane(p, Vec3(0.5, 0.25, std::nextafter(0.25, 1.0))), Sign::Positive);
  EXPECT_EQ(side_of_plane(p, Vec3(0.5, 0.25, std::nextafter(0.25, 0.0))), Sign::Negative);
  // 0.1 + 0.2 + 0.7 − 1 is not 0 in floating point, but the exact value of the doubles decides.
  Plane q(1, 1, 1, -1);
  const double x = 0.1, y = 0.2, z = 0.7;
  const long double exact = static_cast<long double>(x) + y + z - 1;  // 64-bit mantissa: exact here
  Sign expected = exact > 0 ? Sign::Positive : (exact < 0 ? Sign::Negative : Sign::Zero);
  EXPECT_EQ(side_of_plane(q, Vec3(x, y, z)), expected);
  // Huge coordinates: the interval filter overflows, the exact path decides.
  EXPECT_EQ(side_of_plane(Plane(1e200, 0, 0, -1e200), Vec3(1e200, 0, 0)), Sign::Positive);
}

// The static filter of side_of_plane(Plane) against exact rationals (GMP), on points within a
// few ulps of the plane and far from it, at scales from 1e-150 to 1e150 (products near the
// subnormal range and near overflow included).
TEST(Predicates, SideOfPlaneAgreesWithRationals) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> ulps(-3, 3), scale(-150, 150);
  int zero = 0, decided = 0;
  for (int i = 0; i < 20000; ++i) {
    const double s = std::pow(10.0, scale(random)), t = std::pow(10.0, scale(random) / 2);
    Plane plane(unit(random) * s, unit(random) * s, unit(random) * s, unit(random) * s * t);
    double x = unit(random) * t, y = unit(random) * t, z = 0;
    if (i % 4 == 1) {
      // Small integers times powers of two: the point lies exactly on the plane.
      std::uniform_int_distribution<int> small(-8, 8);
      const double e = std::ldexp(1.0, scale(random) / 3), f = std::ldexp(1.0, scale(random) / 3);
      const double a = small(random) * e, b = small(random) * e, c = (1 + std::abs(small(random))) * e;
      x = small(random) * f, y = small(random) * f, z = small(random) * f;
      plane = Plane(a, b, c, -(a * x + b * y + c * z));
    } else {
      const Vec4& k = plane.coefficients;
      if (k[2] == 0) continue;
      z = -(k[0] * x + k[1] * y + k[3]) / k[2];
      if (i % 4 == 0) z += unit(random) * t;  // far from the plane
    }
    const Vec4& k = plane.coefficients;
    for (int u = ulps(random); u > 0; --u) z = std::nextafter(z, INFINITY);
    for (int u = ulps(random); u < 0; ++u) z = std::nextafter(z, -INFINITY);
    if (!std::isfinite(z)) continue;
    const mpq_class exact = mpq_class(k[0]) * mpq_class(x) + mpq_class(k[1]) * mpq_class(y) +
                            mpq_class(k[2]) * mpq_class(z) + mpq_class(k[3]);
    const int c = sgn(exact);
    const Sign expected = c > 0 ? Sign::Positive : (c < 0 ? Sign::Negative : Sign::Zero);
    ASSERT_EQ(side_of_plane(plane, Vec3(x, y, z)), expected) << "case " << i;
    zero += c == 0;
    ++decided;
  }
  EXPECT_GT(decided, 19000);
  EXPECT_GT(zero, 0);  // some points exactly on their plane
}

// orient3d, PlaneOrientation and orient_direction against exact rationals (GMP) on nearly coplanar points, where
// the static filter's bound matters: corners of lat-long quadrilaterals on spheres (planar in
// exact arithmetic, rounded to double), points rounded onto random planes, and exactly coplanar
// points, moved by a few ulps or not, at scales from 1e-100 to 1e100 (2^-300 to 2^300). Many
// have a determinant between Shewchuk's bound (7.8e-16 of the permanent), where the filter
// decides now, and the 1e-14 it used before.
TEST(Predicates, Orient3dAgreesWithRationalsOnNearlyCoplanarPoints) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(-1, 1), angle(0, 6.283185307179586);
  std::uniform_int_distribution<int> ulps(-2, 2), scale(-100, 100), parts(8, 4000);
  // det[b − a, c − a, d − a] (d_is_direction: det[b − a, c − a, d]), differences exact.
  const auto exact_det = [](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, bool d_is_direction) {
    const auto diff = [](const Vec3& x, const Vec3& y, int k) -> mpq_class { return mpq_class(x[k]) - mpq_class(y[k]); };
    const mpq_class ux = diff(b, a, 0), uy = diff(b, a, 1), uz = diff(b, a, 2);
    const mpq_class vx = diff(c, a, 0), vy = diff(c, a, 1), vz = diff(c, a, 2);
    const mpq_class wx = d_is_direction ? mpq_class(d.x()) : diff(d, a, 0),
                    wy = d_is_direction ? mpq_class(d.y()) : diff(d, a, 1),
                    wz = d_is_direction ? mpq_class(d.z()) : diff(d, a, 2);
    return mpq_class(ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx));
  };
  const auto sign_of = [](int c) { return c > 0 ? Sign::Positive : (c < 0 ? Sign::Negative : Sign::Zero); };
  int in_window = 0, zero = 0;
  for (int i = 0; i < 20000; ++i) {
    const double s = std::pow(10.0, scale(random));
    std::array<Vec3, 4> p;
    bool perturb = true;
    if (i % 3 == 2) {
      // Exactly coplanar: small integers times a power of two on the plane x + 2y − z = k·2^e,
      // left as they are every other time (orientation exactly zero).
      std::uniform_int_distribution<int> small(-64, 64);
      const double e = std::ldexp(1.0, scale(random) * 3);
      const int k = small(random);
      for (Vec3& q : p) {
        const int x = small(random), y = small(random);
        q = Vec3(x * e, y * e, (x + 2 * y - k) * e);
      }
      perturb = i % 2 == 0;
    } else if (i % 3 == 0) {
      // A lat-long quadrilateral of a sphere of radius s around a random centre.
      const Vec3 centre(unit(random) * s, unit(random) * s, unit(random) * s);
      const int n = parts(random), m = parts(random) / 2 + 2;
      const double t0 = angle(random) / 2, p0 = angle(random), dt = 3.141592653589793 / m, dp = 6.283185307179586 / n;
      const auto at = [&](double t, double ph) {
        return Vec3(centre.x() + s * std::sin(t) * std::cos(ph), centre.y() + s * std::sin(t) * std::sin(ph),
                    centre.z() + s * std::cos(t));
      };
      p = {at(t0, p0), at(t0 + dt, p0), at(t0 + dt, p0 + dp), at(t0, p0 + dp)};
    } else {
      // Four points rounded onto a random plane through the origin of the box.
      const Vec3 n(unit(random), unit(random), unit(random));
      if (std::abs(n.z()) < 0.1) continue;
      for (Vec3& q : p) {
        const double x = unit(random) * s, y = unit(random) * s;
        q = Vec3(x, y, -(n.x() * x + n.y() * y) / n.z());
      }
    }
    if (perturb)
      for (Vec3& q : p)
        for (int k = 0; k < 3; ++k)
          for (int u = ulps(random); u != 0; u += u > 0 ? -1 : 1) q[k] = std::nextafter(q[k], u > 0 ? INFINITY : -INFINITY);
    // orient3d(a, b, c, d) is the sign of det[b − a, c − a, d − a] (Positive above a
    // counter-clockwise a, b, c).
    const mpq_class det = exact_det(p[0], p[1], p[2], p[3], false);
    ASSERT_EQ(orient3d(p[0], p[1], p[2], p[3]), sign_of(sgn(det))) << "case " << i;
    // PlaneOrientation: the same sign through its own filter (the determinant expanded along
    // d's row), for the plane and for the plane with its corners rotated.
    ASSERT_EQ(PlaneOrientation(p[0], p[1], p[2])(p[3]), sign_of(sgn(det))) << "case " << i;
    ASSERT_EQ(PlaneOrientation(p[1], p[2], p[0])(p[3]), sign_of(sgn(det))) << "case " << i;
    // orient_direction(a, b, c, d): the same with d a direction, not a point.
    ASSERT_EQ(orient_direction(p[0], p[1], p[2], p[3]), sign_of(sgn(exact_det(p[0], p[1], p[2], p[3], true))))
        << "case " << i;
    zero += sgn(det) == 0;
    // The window between the two bounds, measured against |b − a|·|c − a|·|d − a| (the
    // permanent's order of magnitude).
    const double size = (p[1] - p[0]).norm() * (p[2] - p[0]).norm() * (p[3] - p[0]).norm();
    const double relative = std::abs(det.get_d()) / size;
    in_window += relative > 1e-15 && relative <= 1e-14;
  }
  EXPECT_GT(in_window, 1000);
  EXPECT_GT(zero, 1000);
}

TEST(Predicates, SegmentTriangle) {
  Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  EXPECT_EQ(segment_triangle({0.5, 0.5, -1}, {0.5, 0.5, 1}, a, b, c), SegmentTriangle::Crossing);
  EXPECT_EQ(segment_triangle({3, 3, -1}, {3, 3, 1}, a, b, c), SegmentTriangle::Disjoint);
  EXPECT_EQ(segment_triangle({1, 0, -1}, {1, 0, 1}, a, b, c), SegmentTriangle::Degenerate);  // edge
  EXPECT_EQ(segment_triangle({0, 0, -1}, {0, 0, 1}, a, b, c), SegmentTriangle::Degenerate);  // vertex
  EXPECT_EQ(segment_triangle({0.5, 0.5, 0}, {0.5, 0.5, 1}, a, b, c), SegmentTriangle::Degenerate);
  EXPECT_EQ(segment_triangle({0.5, 0.5, 1}, {0.5, 0.5, 2}, a, b, c), SegmentTriangle::Disjoint);
}

TEST(Predicates, OnTriangle) {
  Vec3 a(0, 0, 5), b(2, 0, 5), c(0, 2, 5);
  EXPECT_TRUE(on_triangle({0.5, 0.5, 5}, a, b, c));
  EXPECT_TRUE(on_triangle({1, 1, 5}, a, b, c));  // on the hypotenuse
  EXPECT_TRUE(on_triangle({0, 0, 5}, a, b, c));
  EXPECT_FALSE(on_triangle({1.5, 1, 5}, a, b, c));
  EXPECT_FALSE(on_triangle({0.5, 0.5, 5.000000001}, a, b, c));
  EXPECT_TRUE(collinear({0, 0, 0}, {1, 1, 1}, {3, 3, 3}));
  EXPECT_FALSE(collinear({0, 0, 0}, {1, 1, 1}, {3, 3, 3.0000001}));
}

}  // namespace
}  // namespace hedra
