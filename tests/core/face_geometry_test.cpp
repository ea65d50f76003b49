#include "hedra/core/face_geometry.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "hedra/core/predicates.h"
#include "hedra/core/transform.h"

namespace hedra {
namespace {

// A regular k-gon of radius 1 in the plane z = 0, counter-clockwise seen from +z (its outer
// side, so its inner side is −z), moved by t: rounded, planar only within rounding.
std::vector<Vec3> turned_polygon(int k, const Transform& t) {
  std::vector<Vec3> c;
  for (int i = 0; i < k; ++i) {
    const double a = 2 * std::numbers::pi * i / k;
    c.push_back(t.apply(Vec3(std::cos(a), std::sin(a), 0)));
  }
  return c;
}

// Reference for convex_polygon_split, by brute force over every corner: the triangles are the
// outer side of the corners' convex hull exactly when no corner lies strictly outside any
// triangle's plane; and they tile the polygon: k − 2 triangles, each side of the polygon in
// one triangle, each diagonal in two with opposite directions, every triangle turning as the
// polygon does (seen along its normal).
void expect_convex_split(const std::vector<Vec3>& c, const std::vector<std::array<int, 3>>& tri) {
  const int k = static_cast<int>(c.size());
  ASSERT_EQ(static_cast<int>(tri.size()), k - 2);
  std::multiset<std::pair<int, int>> edges;
  Vec3 normal = Vec3::Zero();
  for (int i = 0; i < k; ++i) normal += (c[static_cast<size_t>(i)] - c[0]).cross(c[static_cast<size_t>((i + 1) % k)] - c[0]);
  for (const auto& t : tri) {
    const Vec3 &a = c[static_cast<size_t>(t[0])], &b = c[static_cast<size_t>(t[1])], &d = c[static_cast<size_t>(t[2])];
    EXPECT_GT((b - a).cross(d - a).dot(normal), 0);
    for (int x = 0; x < k; ++x)
      EXPECT_NE(orient3d(a, b, d, c[static_cast<size_t>(x)]), Sign::Positive) << "corner " << x << " outside";
    for (int e = 0; e < 3; ++e) edges.insert({t[static_cast<size_t>(e)], t[static_cast<size_t>((e + 1) % 3)]});
  }
  for (const auto& [a, b] : edges) {
    const bool side = (b - a + k) % k == 1;
    EXPECT_EQ(edges.count({a, b}), 1u);
    EXPECT_EQ(edges.count({b, a}), side ? 0u : 1u) << a << "→" << b;
  }
}

// Issue 14, "exact inside": a rotated cylinder's cap read back from a file is a convex polygon
// planar only within rounding; its triangles must be the outer side of the hull of its corners.
TEST(FaceGeometry, ConvexPolygonSplitIsTheOuterSideOfTheHull) {
  std::mt19937 random(20261207);
  std::uniform_real_distribution<double> u(-1, 1);
  int folded = 0;
  for (int k : {3, 4, 5, 6, 8, 12, 17, 32, 64, 200})
    for (int turn = 0; turn < 6; ++turn) {
      const Transform t = Transform::rotation(Vec3(u(random), u(random), u(random)), 180 * u(random),
                                              Vec3(u(random), u(random), u(random)));
      const std::vector<Vec3> c = turned_polygon(k, t);
      for (int i = 3; i < k; ++i) folded += orient3d(c[0], c[1], c[2], c[static_cast<size_t>(i)]) != Sign::Zero;
      const std::vector<std::array<int, 3>> tri = convex_polygon_split(c);
      SCOPED_TRACE("k " + std::to_string(k) + " turn " + std::to_string(turn));
      expect_convex_split(c, tri);
      if (k == 4) {  // the quadrilateral rule
        const auto q = convex_quad_split(c[0], c[1], c[2], c[3]);
        EXPECT_EQ(tri, (std::vector<std::array<int, 3>>{q[0], q[1]}));
      }
    }
  EXPECT_GT(folded, 100);  // the rotations leave corners off the plane of the first three
}

// Exactly planar polygons are split too (every triangle on the one plane); a polygon that is not
// strictly convex in projection, or has collinear corners, is not split.
TEST(FaceGeometry, ConvexPolygonSplitRefusesWhatIsNotStrictlyConvex) {
  const std::vector<Vec3> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_EQ(convex_polygon_split(square).size(), 2u);
  std::vector<Vec3> flat = turned_polygon(9, Transform::identity());
  for (Vec3& p : flat) p.z() = 0;
  expect_convex_split(flat, convex_polygon_split(flat));
  const std::vector<Vec3> dent{{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {1, 0.5, 0}, {0, 2, 0}};
  EXPECT_TRUE(convex_polygon_split(dent).empty());
  const std::vector<Vec3> straight{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
  EXPECT_TRUE(convex_polygon_split(straight).empty());
  EXPECT_TRUE(convex_polygon_split({{0, 0, 0}, {1, 0, 0}}).empty());
}

}  // namespace
}  // namespace hedra
