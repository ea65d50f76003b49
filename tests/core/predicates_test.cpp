#include "hedra/core/predicates.h"

#include <gtest/gtest.h>

#include <cmath>

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
