#include "hedra/baselines/midpoint_clip.h"

#include <gtest/gtest.h>

#include <random>

#include "testing/clip_fixtures.h"
#include "hedra/clip/cyrus_beck.h"
#include "hedra/core/error.h"

namespace hedra {
namespace {

// Midpoint subdivision against the exact Cyrus–Beck on the same region: whatever it returns
// is visible, each end within eps (plus midpoint rounding) of the exact end, and only parts
// shorter than a few eps may be missed.
template <class Region>
void expect_within_eps(const Region& region, const ConvexClipper& exact, double eps,
                       std::uint64_t seed, double range) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-range, range);
  const double slack = 1e-12 * range;
  int found = 0;
  for (int i = 0; i < 1500; ++i) {
    const Vec3 p1(u(rng), u(rng), u(rng)), p2(u(rng), u(rng), u(rng));
    const auto part = clip_segment(exact, p1, p2);
    const auto mid = midpoint_clip(region, p1, p2, eps);
    if (mid) {
      ++found;
      ASSERT_TRUE(part) << "midpoint found a part the exact method does not";
      EXPECT_TRUE(exact.contains(mid->start));
      EXPECT_TRUE(exact.contains(mid->end));
      EXPECT_LE((mid->start - point_at(p1, p2, part->start.t)).norm(), eps + slack);
      EXPECT_LE((mid->end - point_at(p1, p2, part->end.t)).norm(), eps + slack);
      EXPECT_LE(std::abs(mid->t_start - part->start.t) * (p2 - p1).norm(), eps + slack);
    } else if (part) {
      const double length = (p2 - p1).norm() * (part->end.t - part->start.t);
      EXPECT_LE(length, 2 * eps) << "midpoint missed a part of length " << length;
    }
  }
  EXPECT_GT(found, 100);
}

TEST(MidpointClip, BoxWithinEpsOfExact) {
  const ClipBox b = ClipBox::from_bounds({-1, -2, -0.5}, {3, 1, 2});
  for (double eps : {1e-2, 1e-6, 1e-10}) expect_within_eps(b, box_clipper(b), eps, 1, 5);
}

TEST(MidpointClip, FrustumWithinEpsOfExact) {
  ViewFrustum f;
  f.x_left = -1, f.x_right = 2, f.y_bottom = -1.5, f.y_top = 1, f.z_far = -6, f.z_near = -1,
  f.z_cp = 3;
  for (double eps : {1e-3, 1e-9}) expect_within_eps(f, frustum_clipper(f), eps, 2, 8);
  // A segment from behind the viewer into the frustum is found, not rejected.
  const auto behind = midpoint_clip(f, {-30, 0, 4}, {1.5, 0, -4}, 1e-9);
  const auto exact = clip_segment(frustum_clipper(f), {-30, 0, 4}, {1.5, 0, -4});
  ASSERT_TRUE(exact);
  ASSERT_TRUE(behind);
}

TEST(MidpointClip, ConvexClipperWithinEpsOfExact) {
  const ConvexClipper ico(testing::icosahedron(2));
  for (double eps : {1e-4, 1e-8, 1e-12}) expect_within_eps(ico, ico, eps, 3, 3);
}

TEST(MidpointClip, CostGrowsWithLogOfLengthOverEps) {
  const ClipBox b = ClipBox::from_bounds({0, 0, 0}, {1, 1, 1});
  const auto coarse = midpoint_clip(b, {-1, 0.5, 0.5}, {2, 0.5, 0.5}, 1e-3);
  const auto fine = midpoint_clip(b, {-1, 0.5, 0.5}, {2, 0.5, 0.5}, 1e-9);
  ASSERT_TRUE(coarse && fine);
  EXPECT_NEAR(fine->bisections - coarse->bisections, 2 * std::log2(1e6), 4);
  EXPECT_LE(fine->bisections, 2 * 33);
  // Visible ends are exact; trivially visible and invisible segments need no midpoint.
  const auto inside = midpoint_clip(b, {0.2, 0.2, 0.2}, {0.8, 0.8, 0.8}, 1e-9);
  ASSERT_TRUE(inside);
  EXPECT_EQ(inside->bisections, 0);
  EXPECT_EQ(inside->t_start, 0);
  EXPECT_EQ(inside->t_end, 1);
  EXPECT_FALSE(midpoint_clip(b, {2, 0, 0}, {3, 1, 1}, 1e-9));
  // Passing a corner outside: no part, found without an endless search.
  const auto miss = midpoint_clip(b, {-1, 0.5, 0.5}, {0.5, -1, 0.5}, 1e-12);
  EXPECT_FALSE(miss);
  EXPECT_THROW(midpoint_clip(b, {0, 0, 0}, {1, 1, 1}, 0), InvalidInput);
}

}  // namespace
}  // namespace hedra
