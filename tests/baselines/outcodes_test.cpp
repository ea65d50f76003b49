#include "hedra/baselines/outcodes.h"

#include <gtest/gtest.h>

#include <random>

#include "hedra/clip/cyrus_beck.h"
#include "hedra/core/error.h"

namespace hedra {
namespace {

ViewFrustum course_frustum() {
  // Far face [−1, 1]² at z = 0, near plane z = 5, centre of projection at z = 10.
  ViewFrustum f;
  f.x_left = -1, f.x_right = 1, f.y_bottom = -1, f.y_top = 1;
  f.z_far = 0, f.z_near = 5, f.z_cp = 10;
  return f;
}

TEST(Outcodes, BoxBitsInTheCoursesOrder) {
  const ClipBox b;  // [−1, 1]³, z_near = 1, z_far = −1
  EXPECT_EQ(outcode(b, {0, 0, 0}), 0);
  EXPECT_EQ(outcode(b, {1, -1, 1}), 0);  // on the boundary: inside
  EXPECT_EQ(outcode(b, {-2, 0, 0}), kOutLeft);
  EXPECT_EQ(outcode(b, {2, 2, 0}), kOutRight | kOutTop);
  EXPECT_EQ(outcode(b, {0, -3, 0}), kOutBottom);
  EXPECT_EQ(outcode(b, {0, 0, 2}), kOutNear);
  EXPECT_EQ(outcode(b, {0, 0, -2}), kOutFar);
  EXPECT_EQ(outcode(b, {std::nextafter(1.0, 2.0), 0, 0}), kOutRight);
  EXPECT_TRUE(trivially_visible(outcode(b, {0, 0, 0}), outcode(b, {1, 1, 1})));
  EXPECT_TRUE(trivially_invisible(outcode(b, {2, 0, 0}), outcode(b, {3, 5, 0})));
  EXPECT_FALSE(trivially_invisible(outcode(b, {-2, 0, 0}), outcode(b, {3, 0, 0})));
  // The box clipper's planes say the same, bit by bit.
  const ConvexClipper c = box_clipper(b);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    for (int k = 0; k < 6; ++k)
      EXPECT_EQ((outcode(b, p) >> k) & 1, side_of_plane(c.plane(k), p) == Sign::Negative);
  }
  EXPECT_THROW(ClipBox::from_bounds({0, 0, 0}, {1, 0, 1}).validate(), InvalidInput);
}

TEST(Outcodes, FrustumBitsFollowTheCoursesTestFunctions) {
  ViewFrustum f;
  f.x_left = -1, f.x_right = 2, f.y_bottom = -1.5, f.y_top = 1, f.z_far = -6, f.z_near = -1,
  f.z_cp = 3;
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-8, 8);
  int checked = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng) - 3);
    if (p.z() > f.z_cp) continue;
    const FrustumTests t = frustum_tests(f, p);
    if (std::abs(t.left) < 1e-9 || std::abs(t.right) < 1e-9 || std::abs(t.bottom) < 1e-9 ||
        std::abs(t.top) < 1e-9)
      continue;  // the literal double evaluation decides reliably away from the planes
    std::uint8_t expected = 0;
    if (t.left < 0) expected |= kOutLeft;
    if (t.right > 0) expected |= kOutRight;
    if (t.bottom < 0) expected |= kOutBottom;
    if (t.top > 0) expected |= kOutTop;
    if (p.z() > f.z_near) expected |= kOutNear;
    if (p.z() < f.z_far) expected |= kOutFar;
    EXPECT_EQ(outcode(f, p), expected) << p.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 3000);
}

TEST(Outcodes, FrustumSignsAreExactOnThePlanes) {
  ViewFrustum f;
  f.x_left = -1, f.x_right = 2, f.y_bottom = -1, f.y_top = 1, f.z_far = -6, f.z_near = -1,
  f.z_cp = 3;
  // The right plane passes through (0, ·, 3) and (2, ·, −6): at z = −1.5 it is at x = 1.
  EXPECT_EQ(outcode(f, {1, 0, -1.5}) & kOutRight, 0);
  EXPECT_EQ(outcode(f, {std::nextafter(1.0, 2.0), 0, -1.5}) & kOutRight, kOutRight);
  EXPECT_EQ(outcode(f, {2, 0, -6}), 0);  // a far corner's edge
  // The frustum clipper's planes agree with the half-space codes everywhere.
  const ConvexClipper c = frustum_clipper(f);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-10, 10);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    for (int k = 0; k < 6; ++k)
      EXPECT_EQ((halfspace_outcode(f, p) >> k) & 1, side_of_plane(c.plane(k), p) == Sign::Negative)
          << p.transpose() << " bit " << k;
  }
  EXPECT_TRUE(c.contains({0, 0, -3}));
}

TEST(Outcodes, PointsBeyondTheCentreOfProjectionHaveTheirSideBitsInverted) {
  const ViewFrustum f = course_frustum();
  // On the axis behind the viewer: every side test fails at once (the planes crossed at the
  // centre); the course's inversion (docs/algorithms.md §3.2) gives 0000, and T5 still marks it
  // invisible.
  EXPECT_EQ(halfspace_outcode(f, {0, 0, 11}), kOutSides | kOutNear);
  EXPECT_EQ(outcode(f, {0, 0, 11}), kOutNear);
  // Behind the viewer on the far left: its image through the centre falls on the right.
  EXPECT_EQ(halfspace_outcode(f, {-100, 0, 11}), kOutLeft | kOutBottom | kOutTop | kOutNear);
  EXPECT_EQ(outcode(f, {-100, 0, 11}), kOutRight | kOutNear);
  // Exactly at z = z_cp: no inversion.
  EXPECT_EQ(outcode(f, {0, 0, 10}), kOutNear);
  EXPECT_EQ(outcode(f, {-1, 0, 10}), kOutLeft | kOutNear);
  // In front of the viewer, nothing changes.
  EXPECT_EQ(outcode(f, {0, 0, 2}), 0);
  EXPECT_EQ(outcode(f, {-3, 0, 2}), kOutLeft);
}

TEST(Outcodes, SegmentsAcrossTheCentrePlaneAreNotRejectedByInvertedBits) {
  const ViewFrustum f = course_frustum();
  // From behind the viewer on the left to a point in front, right of the right plane: the
  // course's codes share T2, yet the segment passes through the frustum.
  const Vec3 a(-100, 0, 11), b(1.5, 0, 0.5);
  EXPECT_TRUE(trivially_invisible(outcode(f, a), outcode(f, b)));
  EXPECT_FALSE(trivially_invisible(f, a, b));
  const auto part = clip_segment(frustum_clipper(f), a, b);
  ASSERT_TRUE(part);
  EXPECT_EQ(outcode(f, point_at(a, b, 0.5 * (part->start.t + part->end.t))), 0);
  // Segments entirely behind, or entirely beside, are still rejected.
  EXPECT_TRUE(trivially_invisible(f, {0, 0, 11}, {5, 5, 20}));
  EXPECT_TRUE(trivially_invisible(f, {3, 0, 1}, {4, 0, 4}));
}

}  // namespace
}  // namespace hedra
