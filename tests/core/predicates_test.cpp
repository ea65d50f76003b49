#include "hedra/core/predicates.h"

#include <gtest/gtest.h>

#include <gmpxx.h>

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
