// Clipping at extreme scales (issue 17): the end points of a part are the exact crossings
// rounded once (end_point, crossing_point), checked against exact rational arithmetic; bodies
// of size 1e-100 and 1e70 clip as the unit cube does.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "hedra/clip/batch_clip.h"
#include "hedra/clip/cyrus_beck.h"
#include "hedra/core/primitives.h"
#include "testing/clip_fixtures.h"

namespace hedra {
namespace {

using testing::Rational;

// Whether c is the exact value x rounded to nearest: no double next to c is closer to x.
// Independent of crossing_point (CGAL's exact rationals, comparisons only).
bool nearest(double c, const Rational& x) {
  const double inf = std::numeric_limits<double>::infinity();
  const Rational d = CGAL::abs(Rational(c) - x);
  return d <= CGAL::abs(Rational(std::nextafter(c, inf)) - x) &&
         d <= CGAL::abs(Rational(std::nextafter(c, -inf)) - x);
}

// The exact point p1 + (p2 − p1)·t of a rational parameter.
Rational exact_coordinate(const Vec3& p1, const Vec3& p2, int i, const Rational& t) {
  return Rational(p1[i]) + (Rational(p2[i]) - Rational(p1[i])) * t;
}

// The part's end points are the exact part (rational Cyrus–Beck) rounded once, for the
// scalar, piece-wise and batch paths alike.
void expect_rounded_once(const ConvexClipper& clipper, const Vec3& p1, const Vec3& p2) {
  const testing::ExactClip exact = testing::exact_clip(clipper, p1, p2);
  const std::optional<ClipPart> part = clip_segment(clipper, p1, p2);
  ASSERT_EQ(part.has_value(), exact.visible) << p1.transpose() << " -> " << p2.transpose();
  if (!part) return;
  const Vec3 a = end_point(clipper, part->start, p1, p2), b = end_point(clipper, part->end, p1, p2);
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(nearest(a[i], exact_coordinate(p1, p2, i, exact.t_low)))
        << "start " << i << ": " << a[i] << " for " << p1.transpose() << " -> " << p2.transpose();
    EXPECT_TRUE(nearest(b[i], exact_coordinate(p1, p2, i, exact.t_up)))
        << "end " << i << ": " << b[i] << " for " << p1.transpose() << " -> " << p2.transpose();
  }
  const std::vector<ClipPart> pieces = clip_segment(std::span<const ConvexClipper>(&clipper, 1), p1, p2);
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(end_point(std::span<const ConvexClipper>(&clipper, 1), pieces[0].start, p1, p2), a);
  EXPECT_EQ(end_point(std::span<const ConvexClipper>(&clipper, 1), pieces[0].end, p1, p2), b);
  SegmentArrays batch;
  batch.push_back(p1, p2);
  BatchClipResult result;
  clip_batch(clipper, batch, result);
  ASSERT_TRUE(result.visible(0));
  EXPECT_EQ(end_point(clipper, result.part(0).start, p1, p2), a);
  EXPECT_EQ(end_point(clipper, result.part(0).end, p1, p2), b);
}

// The example: t = 1/2 ∓ 1/2·1e-70 rounds to 1/2, and P(1/2) is the origin; the
// exact crossings are x = −1 and x = 1.
TEST(ClipExtremes, SegmentFromMinus1e70To1e70ThroughTheUnitCube) {
  const ConvexClipper cube(box({-1, -1, -1}, {1, 1, 1}));
  const Vec3 p1(-1e70, 0, 0), p2(1e70, 0, 0);
  const std::optional<ClipPart> part = clip_segment(cube, p1, p2);
  ASSERT_TRUE(part);
  EXPECT_FALSE(part->point);
  EXPECT_EQ(end_point(cube, part->start, p1, p2), Vec3(-1, 0, 0));
  EXPECT_EQ(end_point(cube, part->end, p1, p2), Vec3(1, 0, 0));
  expect_rounded_once(cube, p1, p2);
  expect_rounded_once(cube, p2, p1);
  // Outside: the two long parts end exactly at the faces.
  const std::vector<ClipPart> out = clip_segment_outside(cube, p1, p2);
  ASSERT_EQ(out.size(), 2u);
  const std::span<const ConvexClipper> one(&cube, 1);
  EXPECT_EQ(end_point(one, out[0].start, p1, p2), p1);
  EXPECT_EQ(end_point(one, out[0].end, p1, p2), Vec3(-1, 0, 0));
  EXPECT_EQ(end_point(one, out[1].start, p1, p2), Vec3(1, 0, 0));
  EXPECT_EQ(end_point(one, out[1].end, p1, p2), p2);
}

// Random long segments through a cube at scales 1e-100, 1, 1e70: every end point is the
// exact crossing rounded once.
TEST(ClipExtremes, EndPointsAreTheExactCrossingsRoundedOnceAtEveryScale) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (const double scale : {1e-100, 1.0, 1e70}) {
    const ConvexClipper cube(box(Vec3::Constant(-scale), Vec3::Constant(scale)));
    for (const double reach : {2.0, 1e20, 1e60}) {
      const double far = std::min(scale * reach, 1e75);
      for (int k = 0; k < 40; ++k) {
        // Through a point inside the cube, out to ±far.
        const Vec3 inside(unit(rng) * scale, unit(rng) * scale, unit(rng) * scale);
        const Vec3 d = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
        const Vec3 p1 = inside - d * far, p2 = inside + d * far;
        if (p1.cwiseAbs().maxCoeff() > 1e75 || p2.cwiseAbs().maxCoeff() > 1e75) continue;
        expect_rounded_once(cube, p1, p2);
      }
    }
  }
}

TEST(ClipExtremes, CrossingPointIsExactOnThePlane) {
  // A crossing that is a double is returned exactly, whatever the segment's length.
  const ExactPlane f = ExactPlane::through({3, 0, 0}, {3, 1, 0}, {3, 0, 1});
  for (const double far : {10.0, 1e30, 1e70})
    EXPECT_EQ(crossing_point(f, Vec3(-far, 0.5, 0.25), Vec3(far, 0.5, 0.25)), Vec3(3, 0.5, 0.25));
  // 1/3 is not a double: the nearest one.
  const ExactPlane g = ExactPlane::through({0, 0, 0}, {0, 1, 0}, {0, 0, 1});
  const Vec3 x = crossing_point(g, Vec3(-1, 0, 0), Vec3(2, 1, 0));
  EXPECT_EQ(x.x(), 0);
  EXPECT_EQ(x.y(), 1.0 / 3);
}

}  // namespace
}  // namespace hedra
