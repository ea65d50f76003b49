#include "hedra/mesh/boolean.h"

#include <gtest/gtest.h>

#include "hedra/mesh/convexity.h"
#include "hedra/core/error.h"
#include "hedra/core/primitives.h"

namespace hedra {
namespace {

Body cross(double a, double length) {
  const double h = a / 2, l = length / 2;
  Body x = box({-l, -h, -h}, {l, h, h});
  Body y = box({-h, -l, -h}, {h, l, h});
  Body z = box({-h, -h, -l}, {h, h, l});
  return unite(unite(x, y), z);
}

TEST(Boolean, CrossOfThreeBoxes) {
  Body c = cross(2, 6);
  EXPECT_EQ(c.volume(), 3 * 4 * 6 - 2 * 8);  // 3a²L − 2a³
  EXPECT_EQ(c.face_count(), 30);             // 6 arm ends + 24 arm sides
  EXPECT_FALSE(convexity(c).convex);
  EXPECT_EQ(c.classify({0, 0, 0}), Location::Inside);
  EXPECT_EQ(c.classify({2, 2, 0}), Location::Outside);
}

TEST(Boolean, PlateWithFiveByFiveHoles) {
  Body plate = box({0, 0, 0}, {11, 11, 1});
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      plate = *subtract(plate, box({1.0 + 2 * i, 1.0 + 2 * j, -1}, {2.0 + 2 * i, 2.0 + 2 * j, 2}));
  EXPECT_EQ(plate.volume(), 121 - 25);
  EXPECT_EQ(plate.face_count(), 2 + 4 + 25 * 4);
  int holes = 0;
  for (const Face& f : plate.faces()) holes += static_cast<int>(f.loops.size()) - 1;
  EXPECT_EQ(holes, 50);  // the top and the bottom each have 25
  EXPECT_EQ(plate.area(), 2 * (121 - 25) + 4 * 11 + 25 * 4);
}

TEST(Boolean, BoxMinusBoxSharingFaces) {
  Body a = box({0, 0, 0}, {2, 2, 2});
  std::optional<Body> half = subtract(a, box({1, 0, 0}, {2, 2, 2}));  // shares 5 face planes
  ASSERT_TRUE(half);
  EXPECT_EQ(half->volume(), 4);
  EXPECT_EQ(half->face_count(), 6);
  EXPECT_EQ(half->vertex_count(), 8);
  std::optional<Body> notch = subtract(a, box({0, 0, 0}, {1, 1, 1}));  // a corner cube
  ASSERT_TRUE(notch);
  EXPECT_EQ(notch->volume(), 7);
  EXPECT_EQ(notch->face_count(), 9);
  EXPECT_FALSE(subtract(a, box({-1, -1, -1}, {3, 3, 3})));  // nothing left
}

TEST(Boolean, TouchingBodies) {
  Body a = box({0, 0, 0}, {1, 1, 1});
  Body face_neighbour = box({1, 0, 0}, {2, 1, 1});
  Body u = unite(a, face_neighbour);
  EXPECT_EQ(u.volume(), 2);
  EXPECT_EQ(u.face_count(), 6);  // the shared face disappears, coplanar sides merge
  EXPECT_FALSE(intersect(a, face_neighbour));
  Body edge_neighbour = box({1, 1, 0}, {2, 2, 1});
  EXPECT_FALSE(intersect(a, edge_neighbour));
  std::optional<Body> same = subtract(a, edge_neighbour);
  ASSERT_TRUE(same);
  EXPECT_EQ(same->volume(), 1);
  EXPECT_EQ(same->face_count(), 6);
  EXPECT_THROW(unite(a, edge_neighbour), InvalidInput);  // not a manifold solid
}

TEST(Boolean, ConvexIntersectionByPlaneSetsEqualsBoolean) {
  Body a = box({0, 0, 0}, {4, 4, 4}).rotated_z(20, {2, 2, 0});
  Body b = pyramid({{1, 1}, {6, 1}, {6, 6}, {1, 6}}, -1, {3, 3, 7});
  std::optional<Body> by_planes = intersect_convex(a, b);
  std::optional<Body> by_boolean = intersect(a, b);
  ASSERT_TRUE(by_planes && by_boolean);
  EXPECT_NEAR(by_planes->volume(), by_boolean->volume(), 1e-12 * by_boolean->volume());
  EXPECT_EQ(by_planes->face_count(), by_boolean->face_count());
  EXPECT_EQ(by_planes->vertex_count(), by_boolean->vertex_count());
  EXPECT_TRUE(convexity(*by_planes).convex);
  // Axis-aligned: exact values.
  std::optional<Body> overlap = intersect_convex(box({0, 0, 0}, {2, 2, 2}), box({1, 1, 1}, {3, 3, 3}));
  ASSERT_TRUE(overlap);
  EXPECT_EQ(overlap->volume(), 1);
  EXPECT_EQ(overlap->face_count(), 6);
  EXPECT_FALSE(intersect_convex(box({0, 0, 0}, {1, 1, 1}), box({2, 0, 0}, {3, 1, 1})));
  EXPECT_FALSE(intersect_convex(box({0, 0, 0}, {1, 1, 1}), box({1, 0, 0}, {2, 1, 1})));  // a face
}

}  // namespace
}  // namespace hedra
