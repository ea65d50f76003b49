#include "hedra/baselines/decompose_baselines.h"
#include "hedra/decompose/decompose.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "testing/decomposition_suite.h"
#include "hedra/mesh/convexity.h"
#include "hedra/core/error.h"
#include "hedra/decompose/split.h"
#include "hedra/mesh/boolean.h"
#include "hedra/mesh/merge_coplanar.h"

namespace hedra {
namespace {

double total_volume(const std::vector<Body>& pieces) {
  double v = 0;
  for (const Body& p : pieces) v += p.volume();
  return v;
}

// Pieces cover the body and do not overlap: at random points, a point inside the body is
// inside exactly one piece (or on the common boundary of several), a point outside is in none.
void expect_partition(const Body& body, const std::vector<Body>& pieces, const std::string& name) {
  std::mt19937 random(42);
  const Eigen::AlignedBox3d box = body.bbox();
  std::uniform_real_distribution<double> u(0, 1);
  int inside_points = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Vec3 p = box.min() + (box.max() - box.min()).cwiseProduct(Vec3(u(random), u(random), u(random)));
    const Location where = body.classify(p);
    int in = 0, on = 0;
    for (const Body& piece : pieces) {
      Location l = piece.classify(p);
      in += l == Location::Inside;
      on += l == Location::OnBoundary;
    }
    if (where == Location::Inside) {
      ++inside_points;
      EXPECT_TRUE(in == 1 || (in == 0 && on >= 2)) << name << " at " << p.transpose();
    } else if (where == Location::Outside) {
      EXPECT_EQ(in, 0) << name << " at " << p.transpose();
    }
  }
  EXPECT_GT(inside_points, 0) << name;
}

TEST(Decompose, SuiteExactConvexCoveringAndRotationInvariant) {
  for (const suite::Shape& shape : suite::shapes(false)) {
    for (bool rotate : {false, true}) {
      const Body body = rotate ? suite::rotated(shape.body) : shape.body;
      const std::string name = shape.name + (rotate ? " (rotated)" : "");
      DecomposeOptions options;
      options.verify = true;
      Decomposition d = decompose(body, options);
      EXPECT_TRUE(d.verified) << name;
      for (const Body& piece : d.pieces) EXPECT_TRUE(convexity(piece).convex) << name;
      EXPECT_NEAR(total_volume(d.pieces), body.volume(), 1e-12 * body.volume()) << name;
      expect_partition(body, d.pieces, name);
      if (rotate) {
        EXPECT_EQ(d.pieces.size(), decompose(shape.body).pieces.size()) << name;
      }
    }
  }
}

// The exact model returned with the pieces (Decomposition::piece_planes, InputPlanes): every
// input vertex lies on its faces' canonical planes, whose support triples are oriented as the
// faces; every rounded piece has one plane per face, lies within rounding on the inner side of
// each, with three or more corners on it — exactly (orient3d on the input support triple) for
// the axis-aligned unrotated shapes, whose cut points are doubles.
TEST(Decompose, PiecesCarryTheExactPlanesOfTheInput) {
  for (const suite::Shape& shape : suite::shapes(false)) {
    for (bool rotate : {false, true}) {
      const Body body = rotate ? suite::rotated(shape.body) : shape.body;
      const std::string name = shape.name + (rotate ? " (rotated)" : "");
      // The model of the rounded body, as hidden lines and shadows ask for it: the Booleans
      // among the shapes (the cross) would otherwise be cut from their exact solids.
      DecomposeOptions options;
      options.from_exact_solid = false;
      const Decomposition d = decompose(body, options);
      if (d.pieces.size() == 1) continue;  // convex input: the body itself, no model
      EXPECT_FALSE(d.from_exact_solid) << name;
      ASSERT_EQ(d.piece_planes.size(), d.pieces.size()) << name;
      const InputPlanes& m = d.planes;
      ASSERT_EQ(m.face_planes.size(), static_cast<size_t>(body.face_count())) << name;
      for (int f = 0; f < body.face_count(); ++f) {
        ASSERT_FALSE(m.face_planes[static_cast<size_t>(f)].empty()) << name;
        for (const auto& [c, sign] : m.face_planes[static_cast<size_t>(f)]) {
          for (int v : body.faces()[static_cast<size_t>(f)].loops[0])
            EXPECT_TRUE(m.on(c, v, body.vertices()[static_cast<size_t>(v)])) << name << " face " << f;
          // The face's outward side is the plane's side `sign`: the body's vertices off the
          // face's plane, where the face is a supporting plane, are not all on the outer side.
          const auto& t = m.support[static_cast<size_t>(c)];
          const Vec3 outward = sign * (t[1] - t[0]).cross(t[2] - t[0]);
          EXPECT_GT(outward.dot(-body.inner_normal(f)), 0) << name << " face " << f;
        }
      }
      for (size_t k = 0; k < d.pieces.size(); ++k) {
        const Body& piece = d.pieces[k];
        EXPECT_EQ(d.piece_planes[k].size(), static_cast<size_t>(piece.face_count())) << name << " piece " << k;
        // The rounded piece's corners are cut points rounded once: within rounding of the
        // exact planes (exactly on them where they are input vertices).
        const double tol = 1e-12 * body.scale();
        for (const auto& [c, sign] : d.piece_planes[k]) {
          int on = 0, exact = 0;
          for (const Vec3& p : piece.vertices()) {
            const double value = sign * m.approx[static_cast<size_t>(c)].value(p);
            EXPECT_LE(value, tol) << name << " piece " << k << " plane " << c;
            on += std::abs(value) <= tol;
            exact += m.side(c, p) == Sign::Zero;
          }
          EXPECT_GE(on, 3) << name << " piece " << k << " plane " << c;
          if (!rotate && shape.name.find("star") == std::string::npos) {
            EXPECT_GE(exact, 3) << name << " piece " << k;
          }
        }
      }
    }
  }
}

TEST(Decompose, PieceCounts) {
  EXPECT_EQ(decompose(prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2)).pieces.size(), 2u);
  EXPECT_EQ(decompose(suite::comb(4)).pieces.size(), 6u);  // the spine and 5 teeth: optimal
  EXPECT_EQ(decompose(prism({{0, 0}, {4, 0}, {4, 3}, {0, 3}}, 0, 2, {{{1, 1}, {3, 1}, {3, 2}, {1, 2}}}))
                .pieces.size(),
            4u);
  EXPECT_EQ(decompose(suite::staircase(10)).pieces.size(), 10u);
}

TEST(Decompose, MergePassKeepsTheCoverExactAndNeverAddsPieces) {
  for (const suite::Shape& shape : suite::shapes(false)) {
    DecomposeOptions plain, merge;
    plain.verify = merge.verify = true;
    merge.merge = true;
    const Decomposition a = decompose(shape.body, plain), b = decompose(shape.body, merge);
    EXPECT_TRUE(b.verified) << shape.name;
    EXPECT_EQ(b.pieces.size() + b.merges, a.pieces.size()) << shape.name;
  }
  // Pieces that over-split a convex union are joined: the two halves of a box cut through
  // its middle, and the four quarters of a box given as pieces.
  int merges = 0;
  const std::vector<Body> quarters = {box({0, 0, 0}, {1, 1, 1}), box({1, 0, 0}, {2, 1, 1}),
                                      box({0, 1, 0}, {1, 2, 1}), box({1, 1, 0}, {2, 2, 1})};
  std::vector<Body> whole = merge_convex(quarters, &merges);
  ASSERT_EQ(whole.size(), 1u);
  EXPECT_EQ(merges, 3);
  EXPECT_EQ(whole[0].face_count(), 6);
  EXPECT_DOUBLE_EQ(whole[0].volume(), 4);
  // An L of three unit boxes: two pieces at best (never all three).
  std::vector<Body> l = merge_convex({box({0, 0, 0}, {1, 1, 1}), box({1, 0, 0}, {2, 1, 1}),
                                      box({0, 1, 0}, {1, 2, 1})});
  EXPECT_EQ(l.size(), 2u);
  // Touching along an edge only: never joined.
  EXPECT_EQ(merge_convex({box({0, 0, 0}, {1, 1, 1}), box({1, 1, 0}, {2, 2, 1})}).size(), 2u);
}

// Seeded random property test: random star-shaped prisms and random unions of boxes, each
// also under a random rotation about a random axis: exact verification, covering, and the
// same piece count after the rotation.
TEST(Decompose, RandomPrismsAndUnionsOfBoxesUnderRandomRotations) {
  std::mt19937 random(2026);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::pair<std::string, Body>> bodies;
  for (int k = 0; k < 6; ++k) {
    const std::vector<Vec2> polygon = suite::random_polygon(random);
    bodies.emplace_back("prism " + std::to_string(k), prism(polygon, 0, 0.3 + u(random)));
  }
  for (int k = 0; k < 4; ++k) {
    auto random_box = [&] {
      const Vec3 lo(u(random) * 2, u(random) * 2, u(random) * 2);
      return box(lo, lo + Vec3(0.5 + u(random), 0.5 + u(random), 0.5 + u(random)));
    };
    Body b = random_box();
    for (int j = 0; j < 2; ++j) {
      Body c = random_box();
      // Overlapping boxes only: a union of disjoint boxes is several bodies.
      if (b.bbox().intersects(c.bbox())) b = unite(b, c);
    }
    bodies.emplace_back("union " + std::to_string(k), b);
  }
  for (const auto& [name, body] : bodies) {
    const Transform rotation = Transform::rotation(
        Vec3(u(random) - 0.5, u(random) - 0.5, u(random) - 0.5), 360 * u(random), body.centroid());
    DecomposeOptions options;
    options.verify = true;
    const Decomposition plain = decompose(body, options);
    const Body turned = body.transformed(rotation);
    const Decomposition rotated = decompose(turned, options);
    EXPECT_TRUE(plain.verified) << name;
    EXPECT_TRUE(rotated.verified) << name;
    EXPECT_EQ(plain.pieces.size(), rotated.pieces.size()) << name;
    EXPECT_NEAR(total_volume(rotated.pieces), turned.volume(), 1e-12 * turned.volume()) << name;
    expect_partition(turned, rotated.pieces, name + " (rotated)");
  }
}

// Issue 15: a prism over a 4000-point star (2000 reflex vertical edges) used to take minutes
// (every cut crossed the whole core and its pieces kept every earlier cut's points). Now a
// second or two in a Release build. Checked exactly: every piece convex (exact verification
// and the convexity test), the pieces' exact volumes summing to the input's exactly, that
// volume the star's area (shoelace in long double) times the height, and the cover.
TEST(Decompose, LargeStarPrismExactConvexAndCovering) {
#ifdef HEDRA_SANITIZED
  const int spikes = 500;  // the verification and the partition check under ASan + UBSan (25 s)
#else
  const int spikes = 2000;
#endif
  const Polygon2 outline = suite::star(spikes, 1, 0.5);
  ASSERT_EQ(outline.size(), 2u * spikes);
  const Body body = prism(outline, 0, 1);
  DecomposeOptions options;
  options.verify = true;
  const Decomposition d = decompose(body, options);
  EXPECT_TRUE(d.verified);
  EXPECT_EQ(d.degenerate_pieces, 0);
  long double area = 0;
  for (size_t i = 0; i < outline.size(); ++i) {
    const Vec2& a = outline[i];
    const Vec2& b = outline[(i + 1) % outline.size()];
    area += static_cast<long double>(a.x()) * b.y() - static_cast<long double>(b.x()) * a.y();
  }
  const double expected = static_cast<double>(std::abs(area) / 2);  // height 1
  EXPECT_NEAR(d.exact_volume, expected, 1e-13 * expected);
  EXPECT_NEAR(total_volume(d.pieces), expected, 1e-12 * expected);
  bool all_convex = true;
  for (const Body& piece : d.pieces) all_convex = all_convex && convexity(piece).convex;
  EXPECT_TRUE(all_convex);
  // No two spike tips fit in one convex piece (the segment between them leaves the star), so
  // 2000 pieces at least; 2001 (the spikes and the core) is what the method gave before.
  EXPECT_GE(d.pieces.size(), static_cast<size_t>(spikes));
  EXPECT_LE(d.pieces.size(), static_cast<size_t>(spikes) + 1);
  expect_partition(body, d.pieces, "star " + std::to_string(2 * spikes));
}

TEST(Decompose, ConvexInputComesBackUnchanged) {
  Body b = box({0, 0, 0}, {1, 2, 3}).rotated_z(17);
  Decomposition d = decompose(b);
  ASSERT_EQ(d.pieces.size(), 1u);
  EXPECT_EQ(d.pieces[0].vertices(), b.vertices());
  EXPECT_EQ(d.cuts, 0);
}

// Every suite shape, large ones included, and each rotated: the same pieces (vertex for vertex,
// in the same order) at 1 and 2 threads.
TEST(Decompose, SameResultAtAnyThreadCount) {
  for (const suite::Shape& shape : suite::shapes(true))
    for (bool rotate : {false, true}) {
      const Body body = rotate ? suite::rotated(shape.body) : shape.body;
      DecomposeOptions one, two;
      one.threads = 1;
      two.threads = 2;
      Decomposition a = decompose(body, one), b = decompose(body, two);
      ASSERT_EQ(a.pieces.size(), b.pieces.size()) << shape.name << (rotate ? " rotated" : "");
      for (size_t i = 0; i < a.pieces.size(); ++i)
        EXPECT_EQ(a.pieces[i].vertices(), b.pieces[i].vertices()) << shape.name << (rotate ? " rotated" : "");
    }
}

// The two large suite shapes (comb 64, plate with 10 × 10 holes), plain and rotated: exact
// verification, convex pieces, volumes, cover, and the same piece count after rotation.
TEST(Decompose, LargeSuiteShapesExactConvexCoveringAndRotationInvariant) {
  std::vector<suite::Shape> large = suite::shapes(true);
  large.erase(large.begin(), large.begin() + static_cast<long>(suite::shapes(false).size()));
  ASSERT_EQ(large.size(), 2u);
  for (const suite::Shape& shape : large) {
    size_t plain_pieces = 0;
    for (bool rotate : {false, true}) {
      const Body body = rotate ? suite::rotated(shape.body) : shape.body;
      const std::string name = shape.name + (rotate ? " (rotated)" : "");
      DecomposeOptions options;
      options.verify = true;
      const Decomposition d = decompose(body, options);
      EXPECT_TRUE(d.verified) << name;
      for (const Body& piece : d.pieces) EXPECT_TRUE(convexity(piece).convex) << name;
      EXPECT_NEAR(total_volume(d.pieces), body.volume(), 1e-12 * body.volume()) << name;
      expect_partition(body, d.pieces, name);
      if (rotate) {
        EXPECT_EQ(d.pieces.size(), plain_pieces) << name;
      }
      plain_pieces = d.pieces.size();
    }
  }
}

TEST(Decompose, MaxPiecesAndCancellation) {
  DecomposeOptions limited;
  limited.max_pieces = 3;
  EXPECT_THROW(decompose(suite::comb(16), limited), InvalidInput);
  DecomposeOptions cancel;
  cancel.progress = [](int, int) { return false; };
  EXPECT_THROW(decompose(suite::comb(4), cancel), DecompositionCancelled);
}

TEST(Split, BoxThroughMiddleAndThroughFace) {
  Body b = box({0, 0, 0}, {2, 2, 2});
  SplitResult r = split(b, Plane(1, 0, 0, -0.5));  // x = 0.5; above: x > 0.5
  ASSERT_EQ(r.below.size(), 1u);
  ASSERT_EQ(r.above.size(), 1u);
  EXPECT_EQ(r.below[0].volume(), 2);
  EXPECT_EQ(r.above[0].volume(), 6);
  EXPECT_EQ(r.below[0].face_count(), 6);
  SplitResult touching = split(b, Plane(1, 0, 0, 0));  // the plane of a face: nothing below
  EXPECT_TRUE(touching.below.empty());
  ASSERT_EQ(touching.above.size(), 1u);
  EXPECT_EQ(touching.above[0].volume(), 8);
  SplitResult diagonal = split(b, Plane(1, 1, 0, -2));  // through two vertical edges
  ASSERT_EQ(diagonal.below.size(), 1u);
  EXPECT_EQ(diagonal.below[0].volume(), 4);
  EXPECT_EQ(diagonal.below[0].face_count(), 5);
}

TEST(Split, ComponentsOnOneSide) {
  // A U shape cut across its arms: two components above.
  Body u = prism({{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 1);
  SplitResult r = split(u, Plane(0, 1, 0, -2));  // y = 2
  EXPECT_EQ(r.above.size(), 2u);
  EXPECT_EQ(r.below.size(), 1u);
  EXPECT_EQ(r.above[0].volume() + r.above[1].volume() + r.below[0].volume(), u.volume());
}

}  // namespace
}  // namespace hedra

namespace hedra {
namespace {

TEST(DecomposeFloat, AgreesOnCleanInputAndFailsLoudly) {
  const Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2);
  Decomposition d = decompose_float(l, 1e-12);
  EXPECT_EQ(d.pieces.size(), 2u);
  EXPECT_NEAR(total_volume(d.pieces), 12, 1e-12);
  // On every suite shape it either succeeds with convex pieces of the right total volume or
  // throws DecompositionFailed — never returns garbage silently.
  for (const suite::Shape& shape : suite::shapes(false)) {
    const Body body = suite::rotated(shape.body);
    try {
      Decomposition f = decompose_float(body, 1e-9);
      for (const Body& piece : f.pieces) EXPECT_TRUE(convexity(piece).convex) << shape.name;
      EXPECT_NEAR(total_volume(f.pieces), body.volume(), 1e-9 * body.volume()) << shape.name;
    } catch (const DecompositionFailed& e) {
      SUCCEED() << shape.name << ": " << e.what();
    }
  }
}

// Triangle soups whose coplanar triangles are perturbed by 1e-9 of the size: the planes meet
// at tiny angles. The float variant must fail with DecompositionFailed (it used to loop for
// ever when an epsilon cut did not split its piece); the exact method succeeds, verified, its
// pieces rounded once (issue 14: it used to fail with "a piece is thinner than double
// coordinates can represent"). Neither hangs or crashes.
TEST(DecomposePerturbed, BothMethodsTerminateAndFailCleanly) {
  std::mt19937 random(1234);
  std::uniform_real_distribution<double> u(-1, 1);
  const Body l = suite::rotated(prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2));
  const Body comb = suite::rotated(suite::comb(4));
  int float_failures = 0, exact_failures = 0;
  for (const Body* source : {&l, &comb}) {
    std::vector<Vec3> v = source->vertices();
    for (Vec3& p : v) p += 1e-9 * source->scale() * Vec3(u(random), u(random), u(random));
    std::vector<Face> faces;
    for (const Triangle& t : source->triangles()) faces.push_back(Face{t.v[0], t.v[1], t.v[2]});
    BodyOptions o;
    o.planarity_tolerance = 1;
    const Body soup(std::move(v), std::move(faces), o);
    try {
      // Where it finishes, its pieces must be right: rounding no longer breaks them (one of
      // the two soups used to fail only there; issue 14).
      const Decomposition f = decompose_float(soup, 1e-9);
      EXPECT_NEAR(total_volume(f.pieces), soup.volume(), 1e-9 * soup.volume());
      expect_partition(soup, f.pieces, "float");
    } catch (const DecompositionFailed& e) {
      ++float_failures;
      const std::string what = e.what();
      EXPECT_TRUE(what.find("does not cut its piece") != std::string::npos ||
                  what.find("crosses itself") != std::string::npos)
          << what;
    }
    try {
      DecomposeOptions options;
      options.verify = true;
      const Decomposition d = decompose(soup, options);
      EXPECT_TRUE(d.verified);
      EXPECT_NEAR(total_volume(d.pieces), soup.volume(), 1e-9 * soup.volume());
      for (const Body& piece : d.pieces) EXPECT_TRUE(convexity(piece).convex);
    } catch (const InvalidInput& e) {
      ++exact_failures;
      ADD_FAILURE() << e.what();
    }
  }
  EXPECT_EQ(float_failures, 1);  // documented in docs/stability.md
  EXPECT_EQ(exact_failures, 0);
}

// Triangle soups perturbed at the rounding level (1e-15 of the size), the benchmark's smallest
// δ with its seed and order: the exact method finishes on all eight shapes with volumes right to
// 1e-12, and every piece is exactly convex in its rounded double coordinates (on comb 16 one
// piece's rounded vertices used to be a few ulps reflex; such a piece is now replaced by the
// hull of its rounded corners, docs/stability.md).
TEST(DecomposePerturbed, RoundingLevelSoupsGiveExactlyConvexPieces) {
  std::mt19937 random(1234);
  std::uniform_real_distribution<double> u(-1, 1);
  int not_convex = 0, shapes = 0;
  for (const suite::Shape& shape : suite::shapes(false)) {
    if (shape.name == "cross" || shape.name.rfind("plate", 0) == 0) continue;
    const Body source = suite::rotated(shape.body);
    std::vector<Vec3> v = source.vertices();
    for (Vec3& p : v) p += 1e-15 * source.scale() * Vec3(u(random), u(random), u(random));
    std::vector<Face> faces;
    for (const Triangle& t : source.triangles()) faces.push_back(Face{t.v[0], t.v[1], t.v[2]});
    BodyOptions o;
    o.planarity_tolerance = 1;
    const Body soup(std::move(v), std::move(faces), o);
    const Decomposition d = decompose(soup);
    ++shapes;
    bool all_convex = true;
    for (const Body& piece : d.pieces) all_convex = all_convex && convexity(piece).convex;
    not_convex += !all_convex;
    EXPECT_NEAR(total_volume(d.pieces), soup.volume(), 1e-12 * soup.volume()) << shape.name;
  }
  EXPECT_EQ(shapes, 8);
  EXPECT_EQ(not_convex, 0);
}

#ifndef HEDRA_SANITIZED  // the sanitizer build has no CGAL decomposition (kernel/CMakeLists.txt)
TEST(DecomposeCgal, CoversTheBodyWithAtLeastAsManyPieces) {
  for (const suite::Shape& shape : suite::shapes(false)) {
    if (shape.name.rfind("plate", 0) == 0) continue;  // slow in CGAL; the benchmark covers it
    Decomposition cgal = decompose_cgal(shape.body);
    Decomposition ours = decompose(shape.body);
    // CGAL's slivers (degenerate_pieces) have next to no volume.
    EXPECT_NEAR(total_volume(cgal.pieces), shape.body.volume(), 1e-6 * shape.body.volume())
        << shape.name;
    for (const Body& piece : cgal.pieces) EXPECT_TRUE(convexity(piece).convex) << shape.name;
    EXPECT_LE(ours.pieces.size(), cgal.pieces.size() + cgal.degenerate_pieces) << shape.name;
  }
}
#endif

// ---- Float32 parts (issue 14): a triangle mesh is a valid body as it is ----------------------

// Decomposition::exact_pieces: each piece as the planes of the exact piece's faces. Checked
// against the rounded piece (its corners within rounding of every plane, inside all of them,
// at least three on each; where the input's corners are doubles and every cut lands on a
// double, exactly) and against the exact-planes run, where every piece is exactly convex.
TEST(Decompose, ExactPiecesAreThePlanesOfTheExactPieces) {
  const Body drilled = *subtract(box({-2, -2, 0}, {2, 2, 1}), cylinder(0.5, -1, 2, 0.01));
  std::vector<std::pair<std::string, Body>> inputs;
  for (const suite::Shape& shape : suite::shapes(false)) {
    inputs.emplace_back(shape.name, shape.body);
    inputs.emplace_back(shape.name + " (rotated)", suite::rotated(shape.body));
  }
  inputs.emplace_back("drilled plate", drilled);
  inputs.emplace_back("drilled plate (float32, rotated)",
                      suite::float32_soup(drilled.transformed(Transform::rotation({1, 2, 3}, 37))));
  // Slanted faces: cut points that are not doubles.
  inputs.emplace_back("slanted L", prism({{0, 0}, {3, 0}, {3, 1}, {1, 1.0 / 3}, {0.7, 3}, {0, 3}}, 0, 2));
  // Random prisms under random rotations: some pieces are exactly convex although their
  // quadrilaterals fold (outward), with faces through cut points (multiprecision planes).
  std::mt19937 random(2027);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 12; ++k) {
    const std::vector<Vec2> polygon = suite::random_polygon(random);  // drawn before the height
    const Body p = prism(polygon, 0, 0.3 + u(random));
    inputs.emplace_back("random prism " + std::to_string(k) + " (rotated)",
                        p.transformed(Transform::rotation(Vec3(u(random) - 0.5, u(random) - 0.5, u(random) - 0.5),
                                                          360 * u(random), p.centroid())));
  }
  int with = 0, without = 0, through_cut_points = 0;
  for (const auto& [name, body] : inputs) {
    const int before = without;  // pieces without an exact form before this input
    DecomposeOptions options;
    options.exact_pieces = true;
    const Decomposition d = decompose(body, options);
    if (d.pieces.size() == 1) continue;  // convex input: the body itself
    ASSERT_EQ(d.exact_pieces.size(), d.pieces.size()) << name;
    const double tol = 1e-12 * body.scale();
    const bool aligned = name.find("rotated") == std::string::npos && name.find("drilled") == std::string::npos &&
                         name.find("star") == std::string::npos && name.find("slanted") == std::string::npos;
    for (size_t k = 0; k < d.pieces.size(); ++k) {
      const ExactConvex& e = d.exact_pieces[k];
      const Body& piece = d.pieces[k];
      if (e.faces.empty()) {
        ++without;
        EXPECT_FALSE(aligned) << name << " piece " << k;  // exactly convex where nothing rounds
        continue;
      }
      ++with;
      ASSERT_GE(e.faces.size(), 4u) << name;
      for (const ExactPlane& f : e.faces) {
        through_cut_points += f.by_exact();
        int on = 0;
        for (const Vec3& p : piece.vertices()) {
          const double value = f.value(p) / f.normal().norm();
          EXPECT_GE(value, -tol) << name << " piece " << k;
          on += std::abs(value) <= tol;
          if (aligned) EXPECT_NE(side_of_plane(f, p), Sign::Negative) << name << " piece " << k;
        }
        EXPECT_GE(on, 3) << name << " piece " << k;
        EXPECT_GE(f.value(piece.centroid()) / f.normal().norm(), -tol) << name << " piece " << k;
      }
      // Each edge joins two faces along a line: two corners of the piece on both planes.
      for (const auto& [a, b] : e.edges) {
        ASSERT_LT(a, b);
        int both = 0;
        for (const Vec3& p : piece.vertices())
          both += std::abs(e.faces[static_cast<size_t>(a)].value(p)) <= tol * e.faces[static_cast<size_t>(a)].normal().norm() &&
                  std::abs(e.faces[static_cast<size_t>(b)].value(p)) <= tol * e.faces[static_cast<size_t>(b)].normal().norm();
        EXPECT_GE(both, 2) << name << " piece " << k << " edge " << a << "-" << b;
      }
      // Where nothing rounds, the faces are the rounded piece's, through input vertices.
      if (aligned) {
        EXPECT_EQ(e.faces.size(), static_cast<size_t>(piece.face_count())) << name << " piece " << k;
        EXPECT_EQ(e.edges.size(), piece.edges().size()) << name << " piece " << k;
      }
    }
    // Not asked for: none.
    EXPECT_TRUE(decompose(body).exact_pieces.empty()) << name;
    // A rotated float32 soup is decomposed as its triangles are: every exact piece convex.
    // A rotated double body's quadrilaterals are planar only within rounding; the guarded run
    // decides on them as planar, so its exact pieces fold by an ulp there and most get none.
    if (name.find("float32") != std::string::npos) EXPECT_EQ(without - before, 0) << name;
  }
  EXPECT_GT(with, 200);
  EXPECT_GT(through_cut_points, 5);  // faces whose plane has multiprecision coefficients
  std::printf("%d faces through cut points\n", through_cut_points);
}

// Issue 14 ("exact inside"): a frustum's top corners are the base's moved a third of the way
// to the apex; rounded, its sides were planar only within rounding, so a non-convex frustum
// was cut with the rounding guard, with pieces that fold by ulps, and Booleans and moves took
// the rounding. It keeps the exact frustum. Reference: the pyramid cut at z1 by a Boolean
// (CGAL's corefinement), exactly the same volume.
TEST(Decompose, NonConvexFrustumIsCutFromItsExactSolid) {
  Polygon2 star;
  for (int i = 0; i < 10; ++i) {
    const double a = 2 * std::numbers::pi * i / 10, r = i % 2 ? 0.8 : 2;
    star.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  const Vec3 apex(0.3, 0.2, 3);
  const Body f = frustum(star, 0, apex, 1);  // a third of the way: not a double
  ASSERT_TRUE(f.has_exact_solid());
  const std::optional<Body> cut = intersect(pyramid(star, 0, apex), box({-5, -5, -1}, {5, 5, 1}));
  ASSERT_TRUE(cut);
  EXPECT_EQ(exact_volume_sign({{1, f}, {-1, *cut}}), Sign::Zero);
  // Its rounding alone is another solid.
  const Body rounded(f.vertices(), f.faces());
  EXPECT_NE(exact_volume_sign({{1, rounded}, {-1, *cut}}), Sign::Zero);
  const size_t guarded_count = decompose(rounded).pieces.size();
  EXPECT_FALSE(decompose(rounded).from_exact_solid);
  for (const Body& body : {f, f.transformed(Transform::rotation({1, 2, 3}, 37))}) {
    DecomposeOptions options;
    options.verify = true;
    options.exact_pieces = true;
    options.prefer_exact_solid = true;
    const Decomposition d = decompose(body, options);
    EXPECT_TRUE(d.from_exact_solid);
    EXPECT_TRUE(d.verified);
    EXPECT_EQ(d.pieces.size(), guarded_count);  // the same cuts as on the rounding
    ASSERT_EQ(d.exact_pieces.size(), d.pieces.size());
    for (const ExactConvex& e : d.exact_pieces) EXPECT_GE(e.faces.size(), 4u);  // exactly convex
    EXPECT_NEAR(total_volume(d.pieces), body.volume(), 1e-12 * body.volume());
  }
}

// Regression: a Boolean's result was decomposed from its rounding. Where the result's exact
// solid has exactly planar faces, the pieces are those of the exact solid: their exact volumes
// sum to the exact result's, and every piece is exactly convex as planes.
TEST(Decompose, BooleanResultsAreDecomposedFromTheirExactSolid) {
  // A block less a slanted triangular prism through it: the prism's edges meet the block's top
  // and bottom at 1/6 and 5/6 of their length, points that are not doubles.
  const Vec3 d(0.5, 0.25, 6);
  const std::vector<Vec3> base = {{1, 1, -1}, {3, 1.25, -1}, {1.75, 3, -1}};
  std::vector<Vec3> corners = base;
  for (const Vec3& p : base) corners.push_back(p + d);  // dyadic sums: exact
  const Body prism_body(corners, {Face{0, 2, 1}, Face{3, 4, 5}, Face{0, 1, 4, 3}, Face{1, 2, 5, 4}, Face{2, 0, 3, 5}});
  const Body block = box({0, 0, 0}, {4, 4, 4});
  const std::optional<Body> holed = subtract(block, prism_body);
  ASSERT_TRUE(holed && holed->has_exact_solid());
  DecomposeOptions options;
  options.verify = true;
  options.exact_pieces = true;
  const Decomposition exact = decompose(*holed, options);
  EXPECT_TRUE(exact.from_exact_solid);
  EXPECT_TRUE(exact.verified);  // pieces' exact volumes sum to the exact solid's
  // The model is the solid's face planes, with the rounded body's vertices and faces on them by
  // construction: every vertex of a face on the face's plane (the rounded corners are off it by
  // an ulp, so an exact test alone would say no), and every other vertex on the side the
  // rounded plane puts it, where it is far from the plane.
  ASSERT_FALSE(exact.planes.empty());
  ASSERT_EQ(exact.piece_planes.size(), exact.pieces.size());
  ASSERT_EQ(exact.planes.face_planes.size(), static_cast<size_t>(holed->face_count()));
  int by_coefficients = 0;
  for (const ExactPlane& e : exact.planes.exact) by_coefficients += e.by_exact();
  EXPECT_GT(by_coefficients, 0);  // the slanted prism's faces through corners that are not doubles
  for (int f = 0; f < holed->face_count(); ++f) {
    const auto& planes = exact.planes.face_planes[static_cast<size_t>(f)];
    ASSERT_EQ(planes.size(), 1u) << "face " << f;
    const int c = planes[0].first;
    std::vector<char> on_face(static_cast<size_t>(holed->vertex_count()), 0);
    for (const auto& loop : holed->faces()[static_cast<size_t>(f)].loops)
      for (int v : loop) {
        on_face[static_cast<size_t>(v)] = 1;
        EXPECT_TRUE(exact.planes.on(c, v, holed->vertices()[static_cast<size_t>(v)])) << "face " << f << " vertex " << v;
      }
    // Outward: the face's rounded plane (inner normal) and the canonical plane's positive side.
    const Plane& rounded_plane = holed->plane(f);
    for (int v = 0; v < holed->vertex_count(); ++v) {
      const Vec3& q = holed->vertices()[static_cast<size_t>(v)];
      const double value = rounded_plane.value(q);
      if (on_face[static_cast<size_t>(v)] || std::abs(value) < 1e-9) continue;
      const Sign expected = (value > 0) == (planes[0].second > 0) ? Sign::Negative : Sign::Positive;
      EXPECT_EQ(exact.planes.side(c, q), expected) << "face " << f << " vertex " << v;
      EXPECT_FALSE(exact.planes.on(c, v, q)) << "face " << f << " vertex " << v;
    }
  }
  ASSERT_EQ(exact.exact_pieces.size(), exact.pieces.size());
  for (size_t k = 0; k < exact.pieces.size(); ++k) {
    EXPECT_GE(exact.exact_pieces[k].faces.size(), 4u) << "piece " << k;  // exactly convex
    EXPECT_TRUE(is_convex(exact.pieces[k]) || exact.pieces[k].volume() < 1e-9) << "piece " << k;
  }
  expect_partition(*holed, exact.pieces, "block less a slanted prism");
  EXPECT_NEAR(total_volume(exact.pieces), holed->volume(), 1e-12 * holed->volume());
  // The rounded body, as before: the same number of pieces here, and the same volume.
  options.from_exact_solid = false;
  const Decomposition rounded = decompose(*holed, options);
  EXPECT_FALSE(rounded.from_exact_solid);
  EXPECT_FALSE(rounded.planes.empty());
  EXPECT_EQ(rounded.pieces.size(), exact.pieces.size());
  options.from_exact_solid = true;
  // A Boolean that rounds no corner is its body exactly, and so is decomposed as any body.
  const std::optional<Body> notched = subtract(block, box({1, 1, 3}, {3, 5, 5}));
  ASSERT_TRUE(notched && notched->has_exact_solid());
  EXPECT_FALSE(decompose(*notched, options).from_exact_solid);
  // Rotated operands are the exact images of their corners, so the Boolean of them has exactly
  // planar faces too, and is cut from its exact solid.
  const Transform t = Transform::rotation({1, 2, 3}, 37);
  const std::optional<Body> turned = subtract(block.transformed(t), prism_body.transformed(t));
  ASSERT_TRUE(turned && turned->has_exact_solid());
  const Decomposition cut = decompose(*turned, options);
  EXPECT_TRUE(cut.from_exact_solid);
  EXPECT_TRUE(cut.verified);
  EXPECT_EQ(cut.pieces.size(), exact.pieces.size());
  // A sphere's quadrilaterals are exactly planar (primitives.h), and so is its share of a
  // Boolean's faces: a notched ball is cut from its exact solid.
  const std::optional<Body> notched_ball =
      subtract(sphere({0, 0, 0}, 1, 0.1), box({0.5, -0.2, -2}, {2, 0.2, 2}).transformed(t));
  ASSERT_TRUE(notched_ball && notched_ball->has_exact_solid());
  const Decomposition from_ball = decompose(*notched_ball, options);
  EXPECT_TRUE(from_ball.from_exact_solid);
  EXPECT_TRUE(from_ball.verified);
  EXPECT_GT(from_ball.pieces.size(), 1u);
  // Operands whose quadrilaterals are planar only within rounding (a rotated box's rounded
  // corners, as read from a file) give a solid with ulp folds: the rounded body is cut with the
  // rounding guard, also where exact pieces are preferred (hidden lines, shadows). Cutting the
  // folds as the solid's triangles instead gives slivers thinner than rounding, which broke
  // the outlines of a read-back sphere less a box into dashes (tried and left, stability.md).
  const Body read_back(block.transformed(t).vertices(), block.faces());
  const std::optional<Body> folded = subtract(read_back, prism_body.transformed(t));
  ASSERT_TRUE(folded && folded->has_exact_solid());
  const Decomposition guarded = decompose(*folded, options);
  EXPECT_FALSE(guarded.from_exact_solid);
  EXPECT_TRUE(guarded.verified);
  DecomposeOptions preferring = options;
  preferring.prefer_exact_solid = true;
  EXPECT_FALSE(decompose(*folded, preferring).from_exact_solid);
  // The result moved exactly (an affine move of the exact solid) keeps planar faces.
  const Decomposition moved = decompose(holed->transformed(t), options);
  EXPECT_TRUE(moved.from_exact_solid);
  EXPECT_TRUE(moved.verified);
  EXPECT_EQ(moved.pieces.size(), exact.pieces.size());
}

// A torus of revolution about z as n × m quadrilaterals: each an isosceles trapezoid, planar
// within the rounding of its double corners, four of them with four planes at every vertex.
Body torus(double big, double small, int n, int m) {
  std::vector<Vec3> v;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double t = 2 * std::numbers::pi * i / n, f = 2 * std::numbers::pi * j / m;
      v.emplace_back((big + small * std::cos(f)) * std::cos(t), (big + small * std::cos(f)) * std::sin(t),
                     small * std::sin(f));
    }
  std::vector<Face> faces;
  const auto at = [&](int i, int j) { return (i % n) * m + j % m; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) faces.push_back(Face{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  return Body(v, faces);
}

// The L block with its sides in two courses (z 0–1, 1–2): each side two quadrilaterals on one
// plane, so a corner at z = 1 lies on two planes (the line where two sides meet), not three.
Body coursed_l() {
  const Polygon2 l = {{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}};
  const int n = static_cast<int>(l.size());
  std::vector<Vec3> v;
  for (double z : {0.0, 1.0, 2.0})
    for (const Vec2& p : l) v.emplace_back(p.x(), p.y(), z);
  std::vector<Face> faces;
  Face bottom, top;
  bottom.loops.emplace_back();
  top.loops.emplace_back();
  for (int i = n - 1; i >= 0; --i) bottom.loops[0].push_back(i);
  for (int i = 0; i < n; ++i) top.loops[0].push_back(2 * n + i);
  faces.push_back(bottom);
  faces.push_back(top);
  for (int course = 0; course < 2; ++course)
    for (int i = 0; i < n; ++i) {
      const int a = course * n + i, b = course * n + (i + 1) % n;
      faces.push_back(Face{a, b, b + n, a + n});
    }
  return Body(v, faces);
}

// Issue 14, "exact inside": a body read from a file of a rotated part (its corners rounded to
// doubles, no exact solid, faces planar only within rounding) was cut in the rounding guard's
// model, whose pieces fold by an ulp across the faces and were mostly not exactly convex: their
// consumers (`clip`'s midpoint method) fell back to the rounded pieces. Where exact pieces are
// preferred it is now cut from its plane solid (decompose.h): every exact piece exactly convex,
// the pieces' exact volumes summing to the solid's (verify), the pieces covering the body (point
// classification), their volumes the body's, and as many as the aligned twin's. Seeded random
// rotations of the L block, the drilled plate (box less a cylinder), a 12-point star prism and
// the L block with its sides in two courses (corners on two planes). Without the preference the
// guarded run stays, its cut budget not reached.
TEST(Decompose, FileBodyWithFacesOffPlaneIsCutFromItsPlaneSolid) {
  const std::optional<Body> plate = subtract(box({4.5, 3.5, 0}, {8.5, 7.5, 1}),
                                             cylinder(0.5, -1, 3, 0.01).transformed(Transform::translation({6.5, 5.5, 0})));
  ASSERT_TRUE(plate);
  const std::vector<std::pair<std::string, Body>> parts = {
      {"L", prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2)},
      {"drilled plate", *plate},
      {"star 12", prism(suite::star(12, 1, 0.5), 0, 1)},
      {"L in two courses", coursed_l()}};
  std::mt19937 random(20261208);
  std::uniform_real_distribution<double> u(-1, 1);
  int off_plane = 0;
  for (const auto& [name, aligned] : parts) {
    const size_t twin = decompose(aligned).pieces.size();
    for (int turn = 0; turn < 6; ++turn) {
      const Transform t = Transform::rotation(Vec3(u(random), u(random), u(random)), 180 * (u(random) + 1));
      const Body moved = aligned.transformed(t);
      const Body read(moved.vertices(), moved.faces());  // what `convert` to OFF then a reader gives
      ASSERT_FALSE(read.has_exact_solid());
      off_plane += !read.faces_off_plane().empty();
      DecomposeOptions options;
      options.verify = true;
      options.exact_pieces = true;
      const std::string where = name + ", turn " + std::to_string(turn);
      const Decomposition guarded = decompose(read, options);
      EXPECT_FALSE(guarded.from_exact_solid) << where;
      EXPECT_EQ(guarded.pieces.size(), twin) << where;
      options.prefer_exact_solid = true;
      const Decomposition d = decompose(read, options);
      EXPECT_EQ(d.from_exact_solid, !read.faces_off_plane().empty()) << where;
      EXPECT_TRUE(d.verified) << where;
      EXPECT_EQ(d.pieces.size(), twin) << where;
      ASSERT_EQ(d.exact_pieces.size(), d.pieces.size()) << where;
      for (size_t k = 0; k < d.pieces.size(); ++k) {
        EXPECT_GE(d.exact_pieces[k].faces.size(), 4u) << where << ", piece " << k;  // exactly convex
        EXPECT_TRUE(is_convex(d.pieces[k])) << where << ", piece " << k;
      }
      EXPECT_NEAR(total_volume(d.pieces), read.volume(), 1e-12 * read.volume()) << where;
      expect_partition(read, d.pieces, where);
    }
  }
  EXPECT_GE(off_plane, 20);
}

// The decomposition suite's shapes, rotated generically and read back: where exact pieces are
// preferred each is cut from its plane solid (all have one: three planes at every corner, or
// faces on one plane), verified exactly, every piece exactly convex, the aligned shape's count.
TEST(Decompose, SuiteReadBackIsCutFromItsPlaneSolid) {
  size_t off_plane = 0;
  const std::vector<suite::Shape> shapes = suite::shapes(false);
  for (const suite::Shape& shape : shapes) {
    const Body moved = suite::rotated(shape.body);
    const Body read(moved.vertices(), moved.faces());
    if (read.faces_off_plane().empty()) continue;
    ++off_plane;
    DecomposeOptions options;
    options.verify = true;
    options.exact_pieces = true;
    options.prefer_exact_solid = true;
    const Decomposition d = decompose(read, options);
    EXPECT_TRUE(d.from_exact_solid) << shape.name;
    EXPECT_TRUE(d.verified) << shape.name;
    EXPECT_EQ(d.pieces.size(), decompose(shape.body).pieces.size()) << shape.name;
    ASSERT_EQ(d.exact_pieces.size(), d.pieces.size()) << shape.name;
    for (size_t k = 0; k < d.pieces.size(); ++k) EXPECT_GE(d.exact_pieces[k].faces.size(), 4u) << shape.name << ", piece " << k;
    EXPECT_NEAR(total_volume(d.pieces), read.volume(), 1e-12 * read.volume()) << shape.name;
  }
  EXPECT_EQ(off_plane, shapes.size());
}

// Issue 14: a rotated 400-point star prism read back from a file took 112 s to decompose (and
// 250 MB): its caps, folded by rounding, are hundreds of triangles with planes of their own in
// the guarded run, which every cut crosses, so the exact cut points grow quadratically, as they
// did for the moved prism before its exact image was cut instead. A file's body has no image;
// its plane solid, whose caps are exactly planar, takes over past the guarded run's budget
// (3.5 s for 400 points). Here a 100-point star prism (1.5 s before, under a second now),
// checked exactly as any decomposition from an exact solid, against the aligned twin's count.
TEST(Decompose, ARotatedStarPrismReadBackIsCutFromItsPlaneSolidPastTheBudget) {
  const Body moved = prism(suite::star(100, 1, 0.5), 0, 1).transformed(Transform::rotation({1, 2, 3}, 37));
  const Body read(moved.vertices(), moved.faces());
  ASSERT_FALSE(read.has_exact_solid());
  ASSERT_FALSE(read.faces_off_plane().empty());
  DecomposeOptions options;
  options.verify = true;
  options.exact_pieces = true;
  const Decomposition d = decompose(read, options);
  EXPECT_TRUE(d.from_exact_solid);
  EXPECT_TRUE(d.verified);
  EXPECT_EQ(d.pieces.size(), 101u);  // the spikes and the core, as the aligned twin
  ASSERT_EQ(d.exact_pieces.size(), d.pieces.size());
  for (size_t k = 0; k < d.pieces.size(); ++k) EXPECT_GE(d.exact_pieces[k].faces.size(), 4u) << "piece " << k;
  EXPECT_NEAR(total_volume(d.pieces), read.volume(), 1e-12 * read.volume());
  expect_partition(read, d.pieces, "rotated star 200, read back");
}

// Where the planes of a vertex's faces do not meet in one point (a torus's quadrilaterals: four
// planes at every vertex), no plane solid stands within rounding of the body: it is cut in the
// rounding guard's model, as before, and the pieces still cover it.
TEST(Decompose, FileTorusWhosePlanesDoNotMeetInOnePointKeepsTheRoundingGuard) {
  const Body moved = torus(2, 0.75, 16, 8).transformed(Transform::rotation({1, 2, 3}, 37));
  const Body read(moved.vertices(), moved.faces());
  ASSERT_FALSE(read.faces_off_plane().empty());
  DecomposeOptions options;
  options.verify = true;
  const Decomposition d = decompose(read, options);
  EXPECT_FALSE(d.from_exact_solid);
  EXPECT_TRUE(d.verified);
  EXPECT_GE(d.pieces.size(), 8u);
  EXPECT_NEAR(total_volume(d.pieces), read.volume(), 1e-12 * read.volume());
  expect_partition(read, d.pieces, "torus");
}

// Issue 14: a rotated 400-point star prism took 29 s to decompose. Its caps, folded by the
// rounding of the rotation, are hundreds of triangles with planes of their own in the guarded
// run, which every cut crossed: the exact cut points grew quadratically with the points of the
// star. The rotated body is the exact image of the aligned one (a pending exact solid), whose
// caps are exactly planar; the guarded run gives way to it past a budget of cut points. Here a
// 64-point star prism (3113 cut points in the guarded run, 358 on the image; 0.7 s for 400
// points now), checked exactly as any decomposition from an exact solid.
TEST(Decompose, ARotatedStarPrismWhoseCutsMultiplyIsCutFromItsExactImage) {
  const Body aligned = prism(suite::star(64, 1, 0.5), 0, 1);
  const Body turned = aligned.transformed(Transform::rotation({1, 2, 3}, 37));
  ASSERT_TRUE(turned.has_exact_solid());
  DecomposeOptions options;
  options.verify = true;
  options.exact_pieces = true;
  const Decomposition d = decompose(turned, options);
  EXPECT_TRUE(d.from_exact_solid);
  EXPECT_TRUE(d.verified);  // the pieces' exact volumes sum to the image's exactly
  EXPECT_EQ(d.pieces.size(), 65u);  // the spikes and the core, as the aligned twin
  ASSERT_EQ(d.exact_pieces.size(), d.pieces.size());
  for (size_t k = 0; k < d.pieces.size(); ++k) {
    EXPECT_GE(d.exact_pieces[k].faces.size(), 4u) << "piece " << k;  // exactly convex
    EXPECT_TRUE(convexity(d.pieces[k]).convex) << "piece " << k;
  }
  EXPECT_NEAR(total_volume(d.pieces), turned.volume(), 1e-12 * turned.volume());
  expect_partition(turned, d.pieces, "rotated star 128");
  // The aligned twin has no image; it is cut as before.
  const Decomposition twin = decompose(aligned, options);
  EXPECT_FALSE(twin.from_exact_solid);
  EXPECT_EQ(twin.pieces.size(), 65u);
  // Without the image (DecomposeOptions::from_exact_solid off), the guarded run goes on past the
  // budget: the same pieces, only slower.
  options.from_exact_solid = false;
  const Decomposition guarded = decompose(turned, options);
  EXPECT_FALSE(guarded.from_exact_solid);
  EXPECT_TRUE(guarded.verified);
  EXPECT_EQ(guarded.pieces.size(), 65u);
  // A small rotated star stays under the budget: the guarded run, which is faster there.
  options.from_exact_solid = true;
  const Body small = prism(suite::star(8, 1, 0.5), 0, 1).transformed(Transform::rotation({1, 2, 3}, 37));
  const Decomposition s = decompose(small, options);
  EXPECT_FALSE(s.from_exact_solid);
  EXPECT_EQ(s.pieces.size(), 9u);
  // Its exact pieces fold by an ulp across the rotated quadrilaterals: some have no exact form.
  int folded = 0;
  for (const ExactConvex& e : s.exact_pieces) folded += e.faces.empty();
  EXPECT_GT(folded, 0);
  // Hidden lines and shadows prefer the image (DecomposeOptions::prefer_exact_solid): the same
  // pieces, every one exactly convex.
  options.prefer_exact_solid = true;
  const Decomposition p = decompose(small, options);
  EXPECT_TRUE(p.from_exact_solid);
  EXPECT_TRUE(p.verified);
  EXPECT_EQ(p.pieces.size(), 9u);
  for (const ExactConvex& e : p.exact_pieces) EXPECT_GE(e.faces.size(), 4u);
}

TEST(DecomposeFloat32, RotatedPartsDecomposeExactlyAndRoundOnce) {
  const Body drilled = *subtract(box({-2, -2, 0}, {2, 2, 1}), cylinder(0.5, -1, 2, 0.01));
  const std::vector<std::pair<std::string, Body>> parts = {
      {"L", prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2)},
      {"drilled plate", drilled},
      {"plate 2x2", suite::plate_with_holes(2)},
  };
  for (const auto& [name, part] : parts)
    for (const Vec3& axis : {Vec3(1, 2, 3), Vec3(-0.3, 0.9, 0.1)}) {
      SCOPED_TRACE(name);
      const Body input = suite::float32_soup(part.transformed(Transform::rotation(axis, 37)));
      DecomposeOptions options;
      options.verify = true;
      const Decomposition d = decompose(input, options);
      // The exact pieces are convex and their exact volumes add up to the input's exactly.
      EXPECT_TRUE(d.verified);
      ASSERT_FALSE(d.pieces.empty());
      // Rounded once: the bodies' volumes add up within rounding, slivers left out included.
      EXPECT_NEAR(total_volume(d.pieces), input.volume(), 1e-9 * input.volume());
      EXPECT_NEAR(d.exact_volume, input.volume(), 1e-12 * input.volume());
      expect_partition(input, d.pieces, name);
    }
}

// Regression: a float32 STL of a plate with 5 × 5 square holes under a generic rotation
// stopped every command with "internal error: split: the cut's boundary encloses no area"
// (exit 1), in all three runs of decompose. A cut met a sliver piece (from cuts through
// triangles coplanar only within float rounding) only along a segment, where the piece has no
// thickness: the cap's corners all lie on one line. Such a cap is now closed by zero-area
// triangles. Checked: verified exactly, the exact volume the input's, rounded volumes within
// rounding, the cover.
TEST(DecomposeFloat32, CutMeetingASliverAlongASegmentOnly) {
  std::vector<Polygon2> holes;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      const double x = -2.4 + 1.2 * i, y = -2.4 + 1.2 * j;
      holes.push_back({{x - 0.3, y - 0.3}, {x - 0.3, y + 0.3}, {x + 0.3, y + 0.3}, {x + 0.3, y - 0.3}});
    }
  const Body plate = prism({{-3, -3}, {3, -3}, {3, 3}, {-3, 3}}, -0.5, 0, holes);
  const Body input = suite::float32_soup(plate.transformed(Transform::rotation({0.3, 1, 2}, 23)));
  DecomposeOptions options;
  options.verify = true;
  const Decomposition d = decompose(input, options);
  EXPECT_TRUE(d.verified);
  EXPECT_GT(d.pieces.size(), 36u);
  EXPECT_NEAR(d.exact_volume, input.volume(), 1e-12 * input.volume());
  EXPECT_NEAR(total_volume(d.pieces), input.volume(), 1e-9 * input.volume());
  expect_partition(input, d.pieces, "plate 5x5");
}

// Regression: pieces rounded through their convex hull (a cut a few ulps off a float32 face)
// came out with their vertices and faces in a different order from run to run with two threads,
// and so did the hidden lines drawn with them (an outline end moved by an ulp). CGAL's
// quickhull orders its work by vertex addresses, which depend on the thread's allocations;
// the hull is now made canonical. Several runs, since a race shows only now and then.
TEST(DecomposeFloat32, HullRoundedPiecesDoNotDependOnTheThreads) {
  const Body drilled = *subtract(box({-2, -2, 0}, {2, 2, 1}), cylinder(0.5, -1, 2, 0.01));
  const Body input = suite::float32_soup(drilled.transformed(Transform::rotation({0.3, -0.7, 0.65}, 37.3)));
  DecomposeOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const Decomposition want = decompose(input, one);
  ASSERT_GT(want.pieces.size(), 10u);
#ifdef HEDRA_SANITIZED
  const int runs = 4;  // each decomposition takes about ten times as long
#else
  const int runs = 8;
#endif
  for (int run = 0; run < runs; ++run) {
    const Decomposition got = decompose(input, run % 2 ? one : two);
    ASSERT_EQ(got.pieces.size(), want.pieces.size());
    for (size_t i = 0; i < want.pieces.size(); ++i) {
      EXPECT_EQ(got.pieces[i].vertices(), want.pieces[i].vertices()) << "run " << run << " piece " << i;
      ASSERT_EQ(got.pieces[i].face_count(), want.pieces[i].face_count()) << "run " << run << " piece " << i;
      for (int f = 0; f < want.pieces[i].face_count(); ++f)
        EXPECT_EQ(got.pieces[i].faces()[static_cast<size_t>(f)].loops, want.pieces[i].faces()[static_cast<size_t>(f)].loops)
            << "run " << run << " piece " << i << " face " << f;
    }
  }
}

}  // namespace
}  // namespace hedra
