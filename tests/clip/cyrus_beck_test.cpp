#include "hedra/baselines/cyrus_beck_double.h"
#include "hedra/clip/cyrus_beck.h"

#include <gtest/gtest.h>

#include <random>

#include "testing/clip_fixtures.h"
#include "hedra/core/error.h"
#include "hedra/core/primitives.h"
#include "hedra/core/transform.h"

namespace hedra {
namespace {

using testing::ExactClip;
using testing::Rational;

// clip_segment agrees with the exact rational Cyrus–Beck: same decision, same bounding planes,
// t within the documented bound. Returns the largest end-point error seen.
double expect_matches_exact(const ConvexClipper& c, const Vec3& p1, const Vec3& p2) {
  const ExactClip exact = testing::exact_clip(c, p1, p2);
  const std::optional<ClipPart> part = clip_segment(c, p1, p2);
  EXPECT_EQ(part.has_value(), exact.visible) << p1.transpose() << " -> " << p2.transpose();
  if (!part || !exact.visible) return 0;
  EXPECT_EQ(part->point, exact.point);
  EXPECT_EQ(part->start.plane, exact.low_plane);
  EXPECT_EQ(part->end.plane, exact.up_plane);
  EXPECT_LE(part->start.t, part->end.t);
  const double e_low = exact.low_plane < 0 ? 0 : crossing(c.plane(exact.low_plane), p1, p2).error;
  const double e_up = exact.up_plane < 0 ? 0 : crossing(c.plane(exact.up_plane), p1, p2).error;
  if (exact.low_plane < 0) {
    EXPECT_EQ(Rational(part->start.t), exact.t_low);
  }
  EXPECT_LE(std::abs(testing::to_double(Rational(part->start.t) - exact.t_low)), e_low);
  EXPECT_LE(std::abs(testing::to_double(Rational(part->end.t) - exact.t_up)),
            std::max(e_low, e_up));
  return std::max(testing::end_point_error(p1, p2, part->start.t, exact.t_low),
                  testing::end_point_error(p1, p2, part->end.t, exact.t_up));
}

Vec3 random_point(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  return {u(rng), u(rng), u(rng)};
}

TEST(CyrusBeck, RandomSegmentsAgainstRandomConvexBodiesMatchExactRationals) {
  std::mt19937_64 rng(20240501);
  double worst = 0;
  for (int body = 0; body < 12; ++body) {
    const double scale = std::pow(10.0, body % 4 * 3 - 3);  // 1e-3 … 1e6
    const Vec3 centre = random_point(rng, -scale, scale);
    const Body b = testing::random_convex_body(rng, 6 + body * 3, scale, centre);
    const ConvexClipper clipper(b);
    for (int i = 0; i < 400; ++i) {
      const Vec3 p1 = centre + random_point(rng, -2 * scale, 2 * scale);
      const Vec3 p2 = centre + random_point(rng, -2 * scale, 2 * scale);
      worst = std::max(worst, expect_matches_exact(clipper, p1, p2) / scale);
    }
  }
  EXPECT_LT(worst, 1e-9);  // relative to the body's size; each end is also within its bound
}

TEST(CyrusBeck, SegmentsBuiltOnVerticesEdgesAndFacesMatchExactRationals) {
  // End points at vertices, at exact points of edges and in faces of bodies whose coordinates
  // are small integers, so those points lie exactly on the planes.
  std::mt19937_64 rng(7);
  const std::vector<Body> bodies = {
      box({0, 0, 0}, {2, 2, 2}), pyramid({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, {2, 2, 4}),
      frustum({{0, 0}, {8, 0}, {4, 8}}, 0, {4, 2, 8}, 4), regular_prism(4, 2, -1, 1)};
  for (const Body& b : bodies) {
    const ConvexClipper clipper(b);
    const auto& v = b.vertices();
    std::uniform_int_distribution<size_t> pick(0, v.size() - 1);
    std::uniform_int_distribution<int> k(-2, 3);
    const auto special = [&]() -> Vec3 {
      const Vec3 a = v[pick(rng)], c = v[pick(rng)];
      switch (k(rng)) {
        case -2:
          return a;
        case -1:
          return 0.5 * (a + c);  // on an edge, a diagonal or inside
        case 0:
          return a + (a - c);  // on the line beyond a
        case 1:
          return 0.25 * (3 * a + c);
        default:
          return random_point(rng, -3, 6);
      }
    };
    for (int i = 0; i < 3000; ++i) expect_matches_exact(clipper, special(), special());
  }
}

// The open clipper split in two: the intersection of the two parts (intersect_parts) is the
// part clipped by all the planes at once, the same exact ends (hidden lines clip a large
// convex body by its silhouette planes, then by the front faces under the segment).
TEST(CyrusBeck, OpenPartsOfTwoPlaneSetsIntersectToThePartOfAll) {
  std::mt19937_64 rng(77);
  int both = 0;
  for (int body = 0; body < 8; ++body) {
    const Body b = testing::random_convex_body(rng, 10 + body * 4, 1.0, Vec3::Zero());
    const ConvexClipper clipper(b);
    const auto& planes = clipper.planes();
    const size_t split = planes.size() / 3;
    const std::span<const ExactPlane> all(planes), first = all.first(split), rest = all.subspan(split);
    for (int i = 0; i < 300; ++i) {
      const Vec3 p1 = random_point(rng, -2, 2), p2 = random_point(rng, -2, 2);
      const std::optional<SegmentPart> whole = clip_segment_open(all, p1, p2);
      const std::optional<SegmentPart> a = clip_segment_open(first, p1, p2), c = clip_segment_open(rest, p1, p2);
      const std::optional<SegmentPart> joined = a && c ? intersect_parts(*a, *c, p1, p2) : std::nullopt;
      ASSERT_EQ(whole.has_value(), joined.has_value()) << body << " " << i;
      if (!whole) continue;
      ++both;
      EXPECT_EQ(compare_ends(whole->lo, joined->lo, p1, p2), Sign::Zero) << body << " " << i;
      EXPECT_EQ(compare_ends(whole->hi, joined->hi, p1, p2), Sign::Zero) << body << " " << i;
      const std::optional<SegmentPart> by_clipper = clip_segment_open(clipper, p1, p2);
      ASSERT_TRUE(by_clipper);
      EXPECT_EQ(by_clipper->lo.t, whole->lo.t);
      EXPECT_EQ(by_clipper->hi.t, whole->hi.t);
    }
  }
  EXPECT_GT(both, 100);
}

TEST(CyrusBeck, PointSegments) {
  const ConvexClipper c(box({0, 0, 0}, {2, 2, 2}));
  auto inside = clip_segment(c, {1, 1, 1}, {1, 1, 1});
  ASSERT_TRUE(inside);
  EXPECT_TRUE(inside->point);
  auto on_face = clip_segment(c, {0, 1, 1}, {0, 1, 1});
  ASSERT_TRUE(on_face);
  EXPECT_TRUE(on_face->point);
  EXPECT_TRUE(clip_segment(c, {2, 2, 2}, {2, 2, 2}));  // a vertex
  EXPECT_FALSE(clip_segment(c, {3, 1, 1}, {3, 1, 1}));
  EXPECT_FALSE(clip_segment(c, {1, 1, std::nextafter(2.0, 3.0)}, {1, 1, std::nextafter(2.0, 3.0)}));
  EXPECT_EQ(clip_segment_outside(c, {1, 1, 1}, {1, 1, 1}).size(), 0u);
  EXPECT_EQ(clip_segment_outside(c, {3, 1, 1}, {3, 1, 1}).size(), 1u);
}

TEST(CyrusBeck, ParallelToAFace) {
  const ConvexClipper c(box({0, 0, 0}, {2, 2, 2}));
  // Inside, parallel to x = 0: whole, no bounding plane.
  auto in = clip_segment(c, {1, 0.5, 0.5}, {1, 1.5, 1.5});
  ASSERT_TRUE(in);
  EXPECT_EQ(in->start.t, 0);
  EXPECT_EQ(in->end.t, 1);
  EXPECT_EQ(in->start.plane, -1);
  EXPECT_EQ(in->end.plane, -1);
  // Outside, parallel: nothing, however long.
  EXPECT_FALSE(clip_segment(c, {-1, -5, 1}, {-1, 7, 1}));
  // Parallel and crossing the box: bounded by the two faces it crosses.
  auto across = clip_segment(c, {1, -2, 1}, {1, 6, 1});
  ASSERT_TRUE(across);
  EXPECT_EQ(across->start.t, 0.25);
  EXPECT_EQ(across->end.t, 0.5);
  EXPECT_EQ(across->start.plane, 2);  // y = min
  EXPECT_EQ(across->end.plane, 3);    // y = max
}

TEST(CyrusBeck, InAFacePlane) {
  const ConvexClipper c(box({0, 0, 0}, {2, 2, 2}));
  // In the plane z = 2, across the face: the clipper is closed, so the part on the face stays.
  auto on = clip_segment(c, {-1, 1, 2}, {3, 1, 2});
  ASSERT_TRUE(on);
  EXPECT_FALSE(on->point);
  EXPECT_EQ(on->start.t, 0.25);
  EXPECT_EQ(on->end.t, 0.75);
  // In the plane, outside the face: nothing.
  EXPECT_FALSE(clip_segment(c, {-1, 3, 2}, {3, 3, 2}));
  // Exterior clipping keeps the two ends off the face.
  const auto out = clip_segment_outside(c, {-1, 1, 2}, {3, 1, 2});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].end.t, 0.25);
  EXPECT_EQ(out[1].start.t, 0.75);
  // A slanted face: the plane of a pyramid side, crossing the face.
  const Body pyr = pyramid({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, {2, 2, 4});
  const ConvexClipper p(pyr);
  // Side y = 0 … apex: points (x, z/2, z) lie in it; the face spans 0 ≤ z ≤ 4, z/2 ≤ x ≤ 4 − z/2.
  auto slanted = clip_segment(p, {-2, 0.5, 1}, {6, 0.5, 1});
  ASSERT_TRUE(slanted);
  EXPECT_NEAR(slanted->start.t, 2.5 / 8, 1e-15);
  EXPECT_NEAR(slanted->end.t, 5.5 / 8, 1e-15);
}

TEST(CyrusBeck, ThroughAVertex) {
  const ConvexClipper c(box({0, 0, 0}, {2, 2, 2}));
  // Touching the corner (0, 0, 0) from outside: exactly one point.
  auto touch = clip_segment(c, {-1, 1, 0}, {1, -1, 0});
  ASSERT_TRUE(touch);
  EXPECT_TRUE(touch->point);
  EXPECT_EQ(touch->start.t, 0.5);
  EXPECT_EQ(touch->end.t, 0.5);
  EXPECT_EQ(point_at({-1, 1, 0}, {1, -1, 0}, touch->start.t), Vec3(0, 0, 0));
  // Exterior: a touching segment comes back whole.
  const auto out = clip_segment_outside(c, {-1, 1, 0}, {1, -1, 0});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].start.t, 0);
  EXPECT_EQ(out[0].end.t, 1);
  // Entering through the corner along the diagonal: three planes tie exactly at t = 1/2; the
  // first (face 0, x = min) is reported.
  auto diagonal = clip_segment(c, {-1, -1, -1}, {1, 1, 1});
  ASSERT_TRUE(diagonal);
  EXPECT_FALSE(diagonal->point);
  EXPECT_EQ(diagonal->start.t, 0.5);
  EXPECT_EQ(diagonal->start.plane, 0);
  EXPECT_EQ(diagonal->end.t, 1);
  // Passing just beside the corner: nothing.
  EXPECT_FALSE(clip_segment(c, {-1, 1, -std::ldexp(1.0, -40)}, {1, -1, -std::ldexp(1.0, -40)}));
  // A pyramid's apex, touched by a segment in no face plane.
  const ConvexClipper p(pyramid({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, {2, 2, 4}));
  auto apex = clip_segment(p, {0, 2, 6}, {4, 2, 2});
  ASSERT_TRUE(apex);
  EXPECT_TRUE(apex->point);
  EXPECT_LT((point_at({0, 2, 6}, {4, 2, 2}, apex->start.t) - Vec3(2, 2, 4)).norm(), 1e-15);
}

TEST(CyrusBeck, AlongAnEdge) {
  const ConvexClipper c(box({0, 0, 0}, {2, 2, 2}));
  auto edge = clip_segment(c, {-1, 0, 0}, {3, 0, 0});
  ASSERT_TRUE(edge);
  EXPECT_FALSE(edge->point);
  EXPECT_EQ(edge->start.t, 0.25);
  EXPECT_EQ(edge->end.t, 0.75);
  // Beside the edge, one ulp outside: nothing.
  EXPECT_FALSE(clip_segment(c, {-1, -std::ldexp(1.0, -60), 0}, {3, -std::ldexp(1.0, -60), 0}));
  // A slanted edge of a pyramid: from base corner (0, 0, 0) to the apex (2, 2, 4), extended.
  const ConvexClipper p(pyramid({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, {2, 2, 4}));
  const Vec3 a(-2, -2, -4), b(4, 4, 8);
  auto slanted = clip_segment(p, a, b);
  ASSERT_TRUE(slanted);
  EXPECT_FALSE(slanted->point);
  EXPECT_NEAR(slanted->start.t, 1.0 / 3, 1e-15);
  EXPECT_NEAR(slanted->end.t, 2.0 / 3, 1e-15);
  // The pyramid rotated by 30° (rounded coordinates): segments from a vertex to every other
  // vertex (edges and a base diagonal) against the exact reference.
  const Body rotated = pyramid({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, {2, 2, 4}).rotated_z(30);
  const ConvexClipper r(rotated);
  const Vec3 v0 = rotated.vertices()[0];
  for (const Vec3& w : rotated.vertices()) {
    if (w == v0) continue;
    auto part = clip_segment(r, v0, w);  // an edge or a diagonal between two vertices
    ASSERT_TRUE(part);
    expect_matches_exact(r, v0, w);
  }
}

TEST(CyrusBeck, CourseFormulationAgreesOnGenericSegments) {
  std::mt19937_64 rng(3);
  const Body b = testing::icosahedron(2);
  const ConvexClipper c(b);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p1 = random_point(rng, -4, 4), p2 = random_point(rng, -4, 4);
    const auto exact = clip_segment(c, p1, p2);
    const auto plain = cyrus_beck_double(b.matrix(), p1, p2);
    ASSERT_EQ(exact.has_value(), plain.has_value());
    if (!exact) continue;
    EXPECT_NEAR(exact->start.t, plain->first, 1e-9);
    EXPECT_NEAR(exact->end.t, plain->second, 1e-9);
  }
}

// Where the course's plain-double formulation (docs/algorithms.md §4) fails: the edges of random
// tetrahedra (each edge lies exactly in two face planes). The exact clipper keeps every edge whole
// (a closed volume contains its boundary); in double, W·n and D·n of those two planes are rounding
// noise, and part of the edges come back rejected or cut short. docs/stability.md cites this.
TEST(CyrusBeck, CourseFormulationMisjudgesEdgesOfTheClipper) {
  std::mt19937_64 rng(11);
  int wrong = 0, total = 0;
  for (int k = 0; k < 300; ++k) {
    std::vector<Vec3> v;
    for (int i = 0; i < 4; ++i) v.push_back(random_point(rng, -1, 1));
    if ((v[1] - v[0]).dot((v[2] - v[0]).cross(v[3] - v[0])) < 0) std::swap(v[2], v[3]);
    const Body tet(v, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
    const ConvexClipper c(tet);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const auto exact = clip_segment(c, v[i], v[j]);
        ASSERT_TRUE(exact.has_value());
        EXPECT_EQ(exact->start.t, 0);
        EXPECT_EQ(exact->end.t, 1);
        const auto plain = cyrus_beck_double(tet.matrix(), v[i], v[j]);
        wrong += !plain || plain->first != 0 || plain->second != 1;
        ++total;
      }
  }
  EXPECT_EQ(total, 1800);
  EXPECT_GT(wrong, 1500);  // 1708 with this seed: the failure the exact layer exists for
}

TEST(CyrusBeck, ClippersFromBodyMatrixAndPlanes) {
  const Body cube = box({-1, -1, -1}, {1, 1, 1});
  const ConvexClipper from_matrix = ConvexClipper::from_matrix(cube.matrix());
  auto part = clip_segment(from_matrix, {-3, 0, 0}, {3, 0, 0});
  ASSERT_TRUE(part);
  EXPECT_EQ(part->start.t, 1.0 / 3);
  EXPECT_EQ(part->end.t, 2.0 / 3);
  // An unbounded clipper (one half-space) works too.
  const ConvexClipper half =
      ConvexClipper::from_planes({ExactPlane::from_coefficients(Plane(0, 0, 1, 0))});
  auto upper = clip_segment(half, {0, 0, -1}, {0, 0, 3});
  ASSERT_TRUE(upper);
  EXPECT_EQ(upper->start.t, 0.25);
  EXPECT_EQ(upper->end.plane, -1);
  BodyMatrix bad(4, 1);
  bad << 0, 0, 0, 1;
  EXPECT_THROW(ConvexClipper::from_matrix(bad), InvalidInput);
}

TEST(CyrusBeck, RejectsNonConvexClippersAndBadPoints) {
  try {
    ConvexClipper c(testing::l_prism());
    FAIL() << "accepted a non-convex clipper";
  } catch (const InvalidInput& e) {
    EXPECT_NE(
        std::string(e.what()).find("not convex: vertices lie outside the planes of faces 4, 5"),
        std::string::npos)
        << e.what();
  }
  const ConvexClipper c(box({0, 0, 0}, {1, 1, 1}));
  EXPECT_THROW(clip_segment(c, {0, 0, NAN}, {1, 1, 1}), InvalidInput);
  EXPECT_THROW(clip_segment(c, {0, 0, 1e102}, {1, 1, 1}), InvalidInput);  // beyond ±1e101
}

// ---- Non-convex clippers through convex pieces ----

// The merged parts against the body itself, by sampling: points strictly inside a part are in
// the closed body, points strictly between parts are outside (away from the part ends).
void expect_matches_sampling(const Body& body, const std::vector<ClipPart>& parts, const Vec3& p1,
                             const Vec3& p2) {
  const double margin = 1e-9;
  for (int k = 0; k <= 200; ++k) {
    const double t = k / 200.0;
    bool near_end = false, in_part = false;
    for (const ClipPart& part : parts) {
      near_end =
          near_end || std::abs(t - part.start.t) < margin || std::abs(t - part.end.t) < margin;
      in_part = in_part || (part.start.t <= t && t <= part.end.t);
    }
    if (near_end) continue;
    const Location loc = body.classify(point_at(p1, p2, t));
    EXPECT_EQ(in_part, loc != Location::Outside)
        << "t = " << t << " on " << p1.transpose() << " -> " << p2.transpose();
  }
}

// The merged parts equal the union of the exact per-piece intervals, merged exactly.
void expect_union_of_pieces(const std::vector<ConvexClipper>& pieces,
                            const std::vector<ClipPart>& parts, const Vec3& p1, const Vec3& p2) {
  std::vector<std::pair<Rational, Rational>> exact;
  for (const ConvexClipper& c : pieces) {
    const ExactClip e = testing::exact_clip(c, p1, p2);
    if (e.visible) exact.push_back({e.t_low, e.t_up});
  }
  std::sort(exact.begin(), exact.end());
  std::vector<std::pair<Rational, Rational>> merged;
  for (const auto& iv : exact) {
    if (!merged.empty() && iv.first <= merged.back().second)
      merged.back().second = std::max(merged.back().second, iv.second);
    else
      merged.push_back(iv);
  }
  ASSERT_EQ(parts.size(), merged.size()) << p1.transpose() << " -> " << p2.transpose();
  for (size_t i = 0; i < parts.size(); ++i) {
    EXPECT_NEAR(parts[i].start.t, testing::to_double(merged[i].first), 1e-14);
    EXPECT_NEAR(parts[i].end.t, testing::to_double(merged[i].second), 1e-14);
    EXPECT_EQ(parts[i].point, merged[i].first == merged[i].second);
  }
}

TEST(CyrusBeckPieces, LPrismAsTwoBoxes) {
  const Body l = testing::l_prism();
  const std::vector<ConvexClipper> pieces = testing::clippers_of(testing::l_prism_pieces());
  // Across the shared face x = 1: one part, no gap, no duplicate.
  const auto across = clip_segment(pieces, {-1, 0.5, 1}, {5, 0.5, 1});
  ASSERT_EQ(across.size(), 1u);
  EXPECT_EQ(across[0].start.t, 1.0 / 6);
  EXPECT_NEAR(across[0].end.t, 5.0 / 6, 1e-15);
  // In the shared face's plane, inside both pieces' faces: one part.
  const auto in_plane = clip_segment(pieces, {1, -1, 1}, {1, 4, 1});
  ASSERT_EQ(in_plane.size(), 1u);
  EXPECT_EQ(in_plane[0].start.t, 0.2);
  EXPECT_EQ(in_plane[0].end.t, 0.8);
  // Across the notch: two parts, [0, 1/6] in the upright piece and [3/4, 1] in the foot.
  const auto two = clip_segment(pieces, {0.5, 2.5, 1}, {3.5, 0.5, 1});
  ASSERT_EQ(two.size(), 2u);
  EXPECT_NEAR(two[0].end.t, 1.0 / 6, 1e-15);
  EXPECT_EQ(two[1].start.t, 0.75);
  EXPECT_EQ(two[1].end.t, 1);
  const auto gaps = clip_segment_outside(pieces, {0.5, 2.5, 1}, {3.5, 0.5, 1});
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].start.t, two[0].end.t);
  EXPECT_EQ(gaps[0].end.t, two[1].start.t);

  std::mt19937_64 rng(11);
  for (int i = 0; i < 600; ++i) {
    const Vec3 p1 = random_point(rng, -1, 5), p2 = random_point(rng, -1, 5);
    const auto parts = clip_segment(pieces, p1, p2);
    expect_union_of_pieces(pieces, parts, p1, p2);
    expect_matches_sampling(l, parts, p1, p2);
  }
}

TEST(CyrusBeckPieces, PlateWithAHoleAsFourBoxes) {
  const Body plate = testing::plate_with_hole();
  const std::vector<ConvexClipper> pieces = testing::clippers_of(testing::plate_pieces());
  // Straight over the hole: two parts, with the hole between them.
  const auto over = clip_segment(pieces, {-1, 2, 0.5}, {5, 2, 0.5});
  ASSERT_EQ(over.size(), 2u);
  EXPECT_EQ(over[0].start.t, 1.0 / 6);
  EXPECT_EQ(over[0].end.t, 2.0 / 6);
  EXPECT_EQ(over[1].start.t, 4.0 / 6);
  EXPECT_NEAR(over[1].end.t, 5.0 / 6, 1e-15);
  // At x = 0.5 the segment crosses the faces y = 1 and y = 3 shared by the strips and the left
  // block: one part.
  const auto side = clip_segment(pieces, {0.5, -1, 0.5}, {0.5, 5, 0.5});
  ASSERT_EQ(side.size(), 1u);
  EXPECT_EQ(side[0].start.t, 1.0 / 6);
  EXPECT_NEAR(side[0].end.t, 5.0 / 6, 1e-15);
  // Exterior clipping: the hole and the two ends.
  const auto out = clip_segment_outside(pieces, {-1, 2, 0.5}, {5, 2, 0.5});
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[1].start.t, 2.0 / 6);
  EXPECT_EQ(out[1].end.t, 4.0 / 6);
  // Along the edge where the hole's wall x = 1 meets y = 1 (touching two pieces along lines).
  const auto edge = clip_segment(pieces, {1, 1, -1}, {1, 1, 2});
  ASSERT_EQ(edge.size(), 1u);
  EXPECT_EQ(edge[0].start.t, 1.0 / 3);
  EXPECT_EQ(edge[0].end.t, 2.0 / 3);

  std::mt19937_64 rng(12);
  for (int i = 0; i < 600; ++i) {
    Vec3 p1 = random_point(rng, -1, 5), p2 = random_point(rng, -1, 5);
    p1.z() = p1.z() / 3, p2.z() = p2.z() / 3;  // mostly through the plate's thickness
    const auto parts = clip_segment(pieces, p1, p2);
    expect_union_of_pieces(pieces, parts, p1, p2);
    expect_matches_sampling(plate, parts, p1, p2);
  }
}

TEST(CyrusBeckPieces, TouchingPointsMergeAway) {
  const std::vector<ConvexClipper> pieces = testing::clippers_of(testing::l_prism_pieces());
  // Touches the corner (4, 1, 2) of the L only: a single point part survives.
  const auto touch = clip_segment(pieces, {3, 2, 2}, {5, 0, 2});
  ASSERT_EQ(touch.size(), 1u);
  EXPECT_TRUE(touch[0].point);
  // Exterior: the whole segment.
  const auto out = clip_segment_outside(pieces, {3, 2, 2}, {5, 0, 2});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].start.t, 0);
  EXPECT_EQ(out[0].end.t, 1);
}

}  // namespace
}  // namespace hedra
