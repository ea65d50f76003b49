#include "hedra/clip/batch_clip.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "testing/clip_fixtures.h"
#include "hedra/core/error.h"
#include "hedra/baselines/outcodes.h"
#include "hedra/core/primitives.h"

namespace hedra {
namespace {

// The bits are what must match (−0 against +0 would be a difference).
bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;  // NOLINT(bugprone-suspicious-memory-comparison)
}

// Every result equals clip_segment's, bit for bit. Returns how many took the exact path.
size_t expect_equals_scalar(const ConvexClipper& c, const SegmentArrays& s,
                            const BatchClipResult& r) {
  size_t exact = 0;
  EXPECT_EQ(r.size(), s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    const std::optional<ClipPart> part = clip_segment(c, s.start(i), s.end(i));
    exact += (r.flags[i] & kClipExactPath) != 0;
    EXPECT_EQ(r.visible(i), part.has_value()) << "segment " << i;
    if (!part || !r.visible(i)) continue;
    EXPECT_TRUE(same_bits(r.t_start[i], part->start.t)) << "segment " << i;
    EXPECT_TRUE(same_bits(r.t_end[i], part->end.t)) << "segment " << i;
    EXPECT_EQ(r.start_plane[i], part->start.plane) << "segment " << i;
    EXPECT_EQ(r.end_plane[i], part->end.plane) << "segment " << i;
    EXPECT_EQ((r.flags[i] & kClipPoint) != 0, part->point) << "segment " << i;
  }
  return exact;
}

// Random segments, and segments made to be degenerate: ends at vertices, at exact points of
// edges and faces, point segments, segments in face planes.
SegmentArrays mixed_segments(const Body& body, size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const Eigen::AlignedBox3d& box = body.bbox();
  const Vec3 lo = box.min() - 0.5 * box.diagonal(), hi = box.max() + 0.5 * box.diagonal();
  std::uniform_real_distribution<double> u(0, 1);
  const auto random = [&] {
    return Vec3(lo.x() + (hi.x() - lo.x()) * u(rng), lo.y() + (hi.y() - lo.y()) * u(rng),
                lo.z() + (hi.z() - lo.z()) * u(rng));
  };
  const auto& v = body.vertices();
  std::uniform_int_distribution<size_t> pick(0, v.size() - 1);
  SegmentArrays s;
  for (size_t i = 0; i < n; ++i) {
    switch (i % 8) {
      case 0:
        s.push_back(v[pick(rng)], v[pick(rng)]);
        break;
      case 1:
        s.push_back(0.5 * (v[pick(rng)] + v[pick(rng)]), random());
        break;
      case 2: {
        const Vec3 p = random();
        s.push_back(p, p);
        break;
      }
      case 3: {
        const Vec3 a = v[pick(rng)], b = v[pick(rng)];
        s.push_back(a + (a - b), b + (b - a));  // a vertex pair's line, extended both ways
        break;
      }
      default:
        s.push_back(random(), random());
    }
  }
  return s;
}

TEST(BatchClip, EqualsScalarBitForBitOnBoxAndIcosahedron) {
  for (const Body& body : {box({0, 0, 0}, {2, 2, 2}), testing::icosahedron(1.5),
                           pyramid({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, {2, 2, 4})}) {
    const ConvexClipper c(body);
    const SegmentArrays s = mixed_segments(body, 20000, 42);
    for (int threads : {1, 2, 0}) {
      for (bool avx2 : {true, false}) {  // the AVX2 code (where the CPU has it) and the baseline
        BatchClipOptions options;
        options.threads = threads;
        options.min_parallel = 1000;  // make the small batch use threads
        options.allow_avx2 = avx2;
        BatchClipResult r;
        clip_batch(c, s, r, options);
        const size_t exact = expect_equals_scalar(c, s, r);
        // The degenerate half of the data needs the exact path; random segments almost never.
        EXPECT_GT(exact, 0u);
        EXPECT_LT(exact, s.size() / 2);
      }
    }
  }
}

TEST(BatchClip, RandomBodiesAndWideCoordinateRanges) {
  std::mt19937_64 rng(99);
  for (int k = 0; k < 8; ++k) {
    const double scale = std::pow(10.0, 2 * k - 8);  // 1e-8 … 1e6
    const Vec3 centre(scale * 3, -scale, scale / 2);
    const Body body = testing::random_convex_body(rng, 10 + 5 * k, scale, centre);
    const ConvexClipper c(body);
    const SegmentArrays s = mixed_segments(body, 5000, 100 + k);
    BatchClipResult r;
    clip_batch(c, s, r);
    expect_equals_scalar(c, s, r);
  }
}

TEST(BatchClip, PlaneClippersAndALargeThreadedBatch) {
  // Frustum planes (three-point and coefficient planes mixed), 300 000 segments: TBB splits the
  // batch; the result must not depend on the thread count.
  ViewFrustum f;
  f.x_left = -1, f.x_right = 2, f.y_bottom = -1.5, f.y_top = 1, f.z_far = -6, f.z_near = -1,
  f.z_cp = 3;
  const ConvexClipper c = frustum_clipper(f);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-8, 8);
  SegmentArrays s;
  for (int i = 0; i < 300000; ++i) s.push_back({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)});
  BatchClipResult one, two;
  BatchClipOptions o1, o2;
  o1.threads = 1;
  o2.threads = 2;
  clip_batch(c, s, one, o1);
  clip_batch(c, s, two, o2);
  EXPECT_EQ(one.flags, two.flags);
  EXPECT_EQ(std::memcmp(one.t_start.data(), two.t_start.data(), 8 * s.size()), 0);
  EXPECT_EQ(std::memcmp(one.t_end.data(), two.t_end.data(), 8 * s.size()), 0);
  EXPECT_EQ(one.start_plane, two.start_plane);
  expect_equals_scalar(c, s, one);
}

TEST(BatchClip, InvalidCoordinatesThrowAsTheScalarPath) {
  const ConvexClipper c(box({0, 0, 0}, {1, 1, 1}));
  SegmentArrays s;
  s.push_back({0, 0, 0}, {1, 1, 1});
  s.push_back({0, NAN, 0}, {1, 1, 1});
  BatchClipResult r;
  EXPECT_THROW(clip_batch(c, s, r), InvalidInput);
  SegmentArrays far;
  far.push_back({0, 0, 0}, {1e102, 1, 1});  // beyond kMaxAbsCoordinate
  EXPECT_THROW(clip_batch(c, far, r), InvalidInput);
  SegmentArrays ragged;
  ragged.push_back({0, 0, 0}, {1, 1, 1});
  ragged.x2.push_back(3);
  EXPECT_THROW(clip_batch(c, ragged, r), InvalidInput);
}

}  // namespace
}  // namespace hedra
