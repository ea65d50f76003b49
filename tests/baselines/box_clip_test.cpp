#include "hedra/baselines/box_clip.h"

#include <gtest/gtest.h>

#include <random>

#include "hedra/clip/cyrus_beck.h"

namespace hedra {
namespace {

ClipBox test_box() { return ClipBox::from_bounds({-1, -2, -0.5}, {3, 1, 2}); }

TEST(BoxClip, CohenSutherlandAndLiangBarskyAgreeWithExactCyrusBeck) {
  const ClipBox b = test_box();
  const ConvexClipper exact = box_clipper(b);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-5, 5);
  int visible = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p1(u(rng), u(rng), u(rng)), p2(u(rng), u(rng), u(rng));
    const auto part = clip_segment(exact, p1, p2);
    const auto cs = cohen_sutherland(b, p1, p2);
    const auto lb = liang_barsky(b, p1, p2);
    // Random segments are not degenerate: every method sees the same visibility.
    ASSERT_EQ(cs.has_value(), part.has_value()) << p1.transpose() << " -> " << p2.transpose();
    ASSERT_EQ(lb.has_value(), part.has_value());
    if (!part) continue;
    ++visible;
    const Vec3 a = point_at(p1, p2, part->start.t), c = point_at(p1, p2, part->end.t);
    EXPECT_LT((cs->first - a).norm(), 1e-12);
    EXPECT_LT((cs->second - c).norm(), 1e-12);
    EXPECT_NEAR(lb->first, part->start.t, 1e-12);
    EXPECT_NEAR(lb->second, part->end.t, 1e-12);
  }
  EXPECT_GT(visible, 2000);
}

TEST(BoxClip, DegenerateSegments) {
  const ClipBox b = ClipBox::from_bounds({0, 0, 0}, {2, 2, 2});
  // Parallel to a face, outside: none; inside: whole.
  EXPECT_FALSE(cohen_sutherland(b, {-1, 0, 1}, {-1, 2, 1}));
  EXPECT_FALSE(liang_barsky(b, {-1, 0, 1}, {-1, 2, 1}));
  const auto whole = liang_barsky(b, {1, 0.5, 1}, {1, 1.5, 1});
  ASSERT_TRUE(whole);
  EXPECT_EQ(whole->first, 0);
  EXPECT_EQ(whole->second, 1);
  // Through the corner (0, 0, 0) only: one point.
  const auto corner = cohen_sutherland(b, {-1, 1, 0}, {1, -1, 0});
  ASSERT_TRUE(corner);
  EXPECT_EQ(corner->first, Vec3(0, 0, 0));
  EXPECT_EQ(corner->second, Vec3(0, 0, 0));
  const auto corner_lb = liang_barsky(b, {-1, 1, 0}, {1, -1, 0});
  ASSERT_TRUE(corner_lb);
  EXPECT_EQ(corner_lb->first, 0.5);
  EXPECT_EQ(corner_lb->second, 0.5);
  // Passing the corner outside without being trivially rejected (codes left and bottom).
  EXPECT_FALSE(cohen_sutherland(b, {-1, 0.5, 1}, {0.5, -1, 1}));
  EXPECT_FALSE(liang_barsky(b, {-1, 0.5, 1}, {0.5, -1, 1}));
  // Across the box through two faces: exact points on the faces.
  const auto across = cohen_sutherland(b, {-1, 1, 1}, {3, 1, 1});
  ASSERT_TRUE(across);
  EXPECT_EQ(across->first, Vec3(0, 1, 1));
  EXPECT_EQ(across->second, Vec3(2, 1, 1));
  // A point segment.
  EXPECT_TRUE(cohen_sutherland(b, {1, 1, 1}, {1, 1, 1}));
  EXPECT_FALSE(liang_barsky(b, {3, 1, 1}, {3, 1, 1}));
}

TEST(BoxClip, CohenSutherlandTerminatesNearEdges) {
  // Segments passing within rounding of an edge of the box (rounding can set a bit again on an
  // end just moved onto a plane): the method must end, close to the exact result.
  const ClipBox b = ClipBox::from_bounds({0.1, 0.2, 0.3}, {0.7, 0.9, 1.3});
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 5000; ++i) {
    const Vec3 edge_point(0.1, 0.2, 0.3 + (1.3 - 0.3) * (0.5 + 0.5 * u(rng)));
    const Vec3 d(u(rng), u(rng), u(rng));
    const Vec3 p1 = edge_point - d, p2 = edge_point + d * (1 + u(rng));
    const auto cs = cohen_sutherland(b, p1, p2);
    const auto exact = clip_segment(box_clipper(b), p1, p2);
    if (cs && exact) {
      EXPECT_LT((cs->first - point_at(p1, p2, exact->start.t)).norm(), 1e-12);
      EXPECT_LT((cs->second - point_at(p1, p2, exact->end.t)).norm(), 1e-12);
    } else if (cs) {
      EXPECT_LT((cs->first - cs->second).norm(), 1e-12);  // at most a sliver near the edge
    } else if (exact) {
      EXPECT_LT((point_at(p1, p2, exact->end.t) - point_at(p1, p2, exact->start.t)).norm(), 1e-12);
    }
  }
}

}  // namespace
}  // namespace hedra
