// Differential random tests (issue 17 item 7): seeded random solids and scenes — rotated boxes
// and prisms over convex, L, star and comb outlines — each result checked against an
// independent reference. A failure prints its seed; HEDRA_STRESS_SEED=<seed> reruns that case
// alone, HEDRA_STRESS_CASES=N runs N cases per test (`make stress`; `make test` runs the
// default counts below, a few hundred cases in all).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hedra/clip/convex_clipper.h"
#include "hedra/clip/cyrus_beck.h"
#include "hedra/core/error.h"
#include "hedra/decompose/decompose.h"
#include "hedra/mesh/boolean.h"
#include "hedra/scene/camera.h"
#include "hedra/scene/scene.h"
#include "hedra/visibility/roberts.h"
#include "hedra/visibility/shadows.h"
#include "testing/clip_fixtures.h"
#include "testing/convexity_oracle.h"
#include "testing/decomposition_suite.h"
#include "testing/differential.h"
#include "testing/hlr_reference.h"

namespace hedra {
namespace {

using testing::for_each_case;
using testing::Rational;

Vec3 random_point(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  return {u(rng), u(rng), u(rng)};
}

// Decomposition: exact verification (every exact piece convex, exact volumes summing exactly
// to the input's), every rounded piece convex by the course's definition evaluated exactly
// (testing/convexity_oracle.h), rounded volumes within 1e-9, cover by sampling. Half of the
// cases are triangle soups perturbed by δ = 10^-15 … 10^-6 of the size.
TEST(Differential, DecompositionPiecesAreExactConvexAndCover) {
  for_each_case(1, 150, [](std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    Body body = testing::random_solid(rng, static_cast<int>(seed % 5), 4, {0, 0, 0});
    if (seed % 2) body = suite::perturbed_soup(body, std::pow(10.0, -15 + static_cast<double>(rng() % 10)), rng);
    DecomposeOptions o;
    o.verify = true;
    o.threads = 1;
    const Decomposition d = decompose(body, o);
    EXPECT_TRUE(d.verified);
    double volume = 0;
    for (const Body& piece : d.pieces) {
      volume += piece.volume();
      EXPECT_TRUE(testing::nonconvex_faces_oracle(piece).empty());
    }
    EXPECT_NEAR(volume, body.volume(), 1e-9 * body.volume());
    EXPECT_EQ(testing::cover_error(body, d.pieces, rng), "");
  });
}

// Clipping through the decomposition of a random solid: each piece's clip_segment equals the
// exact rational Cyrus–Beck on the same planes (decision, bounding planes, t within the
// documented bound), and the total clipped length equals the exact one. Segments: random,
// vertex to vertex (edges and diagonals of the pieces), and through vertices.
TEST(Differential, ClippingMatchesExactRationalCyrusBeck) {
  for_each_case(2, 100, [](std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    const Body body = testing::random_solid(rng, static_cast<int>(seed % 5), 2, {0, 0, 0});
    const std::vector<Body> pieces = decompose(body).pieces;
    std::vector<ConvexClipper> clippers;
    std::vector<Vec3> corners;
    for (const Body& p : pieces) {
      clippers.emplace_back(p);
      corners.insert(corners.end(), p.vertices().begin(), p.vertices().end());
    }
    std::uniform_int_distribution<size_t> pick(0, corners.size() - 1);
    for (int s = 0; s < 30; ++s) {
      Vec3 p1 = random_point(rng, -2, 2), p2 = random_point(rng, -2, 2);
      if (s % 3 == 1) p1 = corners[pick(rng)], p2 = corners[pick(rng)];
      if (s % 3 == 2) p2 = corners[pick(rng)] + (corners[pick(rng)] - p1);
      double exact_length = 0, length = 0, bound = 0;
      for (const ConvexClipper& c : clippers) {
        const testing::ExactClip exact = testing::exact_clip(c, p1, p2);
        const std::optional<ClipPart> part = clip_segment(c, p1, p2);
        ASSERT_EQ(part.has_value(), exact.visible) << p1.transpose() << " -> " << p2.transpose();
        if (!part) continue;
        EXPECT_EQ(part->point, exact.point);
        EXPECT_EQ(part->start.plane, exact.low_plane);
        EXPECT_EQ(part->end.plane, exact.up_plane);
        const double e_low = exact.low_plane < 0 ? 0 : crossing(c.plane(exact.low_plane), p1, p2).error;
        const double e_up = exact.up_plane < 0 ? 0 : crossing(c.plane(exact.up_plane), p1, p2).error;
        EXPECT_LE(std::abs(testing::to_double(Rational(part->start.t) - exact.t_low)), e_low);
        EXPECT_LE(std::abs(testing::to_double(Rational(part->end.t) - exact.t_up)), std::max(e_low, e_up));
        exact_length += testing::to_double(exact.t_up - exact.t_low);
        length += part->end.t - part->start.t;
        bound += e_low + std::max(e_low, e_up);
      }
      // A segment along a face of a piece (vertex to vertex) can have an ill-conditioned
      // crossing whose bound is large; the sum of the bounds covers the total.
      EXPECT_LE(std::abs(length - exact_length), bound + 1e-12 * static_cast<double>(clippers.size()));
    }
  });
}

// Booleans of two overlapping random solids against the volume identities
// V(A − B) + V(A ∩ B) = V(A) and V(A ∪ B) + V(A ∩ B) = V(A) + V(B). The results' vertices are
// rounded once from exact constructions, so the identities hold to rounding: 1e-12 of V(A).
TEST(Differential, BooleansKeepTheVolumeIdentities) {
  for_each_case(3, 60, [](std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    const Body a = testing::random_solid(rng, static_cast<int>(seed % 5), 3, {0, 0, 0});
    const Body b = testing::random_solid(rng, static_cast<int>(seed / 5 % 5), 3, random_point(rng, -0.7, 0.7));
    const std::optional<Body> difference = subtract(a, b);
    const std::optional<Body> common = intersect(a, b);
    const Body both = unite(a, b);
    const double vd = difference ? difference->volume() : 0, vi = common ? common->volume() : 0;
    const double scale = a.volume() + b.volume();
    EXPECT_NEAR(vd + vi, a.volume(), 1e-12 * scale);
    EXPECT_NEAR(both.volume() + vi, a.volume() + b.volume(), 1e-12 * scale);
    EXPECT_GE(vi, 0);
    // Exactly, on the exact solids the results keep (the rounded bodies only within rounding).
    std::vector<std::pair<int, Body>> first = {{-1, a}}, second = {{1, both}, {-1, a}, {-1, b}};
    if (difference) first.emplace_back(1, *difference);
    if (common) {
      first.emplace_back(1, *common);
      second.emplace_back(1, *common);
    }
    EXPECT_EQ(exact_volume_sign(first), Sign::Zero);
    EXPECT_EQ(exact_volume_sign(second), Sign::Zero);
  });
}

// Hidden lines of random scenes (5 rotated solids of every family: boxes, convex, L, star and
// comb prisms, some interpenetrating) from a random parallel or perspective camera: the total
// visible edge length equals the ray-cast reference's (testing/hlr_reference.h: samples on each
// edge, rays to the eye tested against the open interiors of the bodies' convex parts), to
// 1e-9. The reference's parts are the exact pieces as plane sets (testing::exact_parts: the
// input's own face planes), not the pieces rounded to double, whose faces can be an ulp off a
// reflex edge (or, from the convex-hull fallback, sliver faces); hidden lines decide incidence
// with the exact pieces too (docs/design.md, "Exact incidence of pieces").
void check_hidden_lines(std::uint64_t seed, Occluders occluders = Occluders::Auto) {
  std::mt19937_64 rng(seed);
  std::vector<Body> bodies;
  std::vector<std::pair<std::vector<Plane>, std::vector<Vec3>>> parts;
  for (int i = 0; i < 5; ++i) {
    bodies.push_back(testing::random_solid(rng, static_cast<int>((seed + i) % 5), 2, random_point(rng, 0, 6)));
    for (auto& p : testing::exact_parts(bodies.back())) parts.push_back(std::move(p));
  }
  const Vec3 centre(3, 3, 3);
  std::uniform_real_distribution<double> u(-1, 1);
  Vec3 d = testing::draw3(rng, u);
  d.z() = -0.3 - std::abs(d.z());
  const Camera camera = seed % 2 ? Camera::parallel(d, Vec3(0, 0, 1))
                                 : Camera::perspective(centre - 12 * d.normalized(), centre, 60);
  HlrOptions o;
  o.merge_coincident = false;
  o.crease_angle = 0;  // every edge is drawn as an edge (the reference knows no line classes)
  o.occluders = occluders;
  const HlrResult r = hidden_lines(bodies, camera, o);
  const testing::RayCastReference reference(std::span<const std::pair<std::vector<Plane>, std::vector<Vec3>>>(parts), camera);
  double expected = 0;
  for (size_t i = 0; i < bodies.size(); ++i)
    for (int k = 0; k < bodies[i].edge_count(); ++k) {
      const Edge& e = bodies[i].edges()[static_cast<size_t>(k)];
      expected += reference.visible_length(bodies[i].vertices()[e.v0], bodies[i].vertices()[e.v1], 200,
                                           testing::part_hints(r, bodies[i], static_cast<int>(i), k));
    }
  EXPECT_NEAR(r.length(LineKind::Edge), expected, 1e-9 * expected);
}

TEST(Differential, HiddenLinesMatchRayCasting) {
  for_each_case(4, 40, [](std::uint64_t seed) { check_hidden_lines(seed); });
}

// The same scenes with every non-convex body occluding by its faces' triangles
// (Occluders::Faces, which bodies of more than kFaceOccluderFaces faces get): the same lengths.
TEST(Differential, HiddenLinesByFacesMatchRayCasting) {
  for_each_case(7, 40, [](std::uint64_t seed) { check_hidden_lines(seed, Occluders::Faces); });
}

// Seeds `make stress` found with the non-convex families: 4000015, an edge of a comb on a face
// coplanar with another face of its body, hidden by an ulp of a rounded piece (the old
// within-rounding matching took the other face); 4000541, a star whose central piece took the
// convex-hull fallback, whose sliver faces misled a reference built on the rounded pieces.
TEST(Differential, HiddenLinesRegressionSeeds) {
  for (const std::uint64_t seed : {4000015ULL, 4000541ULL}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    check_hidden_lines(seed);
  }
}

// Shadows: random solids above a ground slab under a random directional light; the ground's
// shadow area equals CGAL's exact union of the projected hulls of the solids' convex pieces,
// clipped to the ground (testing::ground_shadow_reference), to 1e-11.
TEST(Differential, GroundShadowAreaMatchesTheExactPolygonUnion) {
  for_each_case(5, 40, [](std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    Scene scene;
    const double half = 10;
    scene.add("ground", box({-half, -half, -1}, {half, half, 0}));
    std::vector<Body> casters;
    for (int i = 0; i < 6; ++i) {
      Body b = testing::random_solid(rng, static_cast<int>((seed + i) % 5), 2, random_point(rng, -6, 6));
      b = b.translated({0, 0, 0.1 - b.bbox().min().z() + 2 * std::abs(random_point(rng, 0, 1).z())});
      scene.add("b" + std::to_string(i), b);
      casters.push_back(b);
    }
    std::uniform_real_distribution<double> u(-1, 1);
    Vec3 d = testing::draw3(rng, u);
    d.z() = -0.4 - std::abs(d.z());
    scene.lights.push_back(Light::directional(d));
    const ShadowResult r = compute_shadows(scene);
    const double reference = testing::ground_shadow_reference(casters, d, half);
    EXPECT_NEAR(r.face(0, 0, 5).shadow_area, reference, 1e-11 * reference);  // face 5: the top, z = 0
  });
}

// Shadows with non-convex bodies occluding by their faces' triangles (Occluders::Faces) equal
// those by their exact convex pieces, face by face, under a point light (the angular caster
// index) and a directional one: both are exact for the same polyhedra.
TEST(Differential, ShadowsByFacesEqualShadowsByPieces) {
  for_each_case(8, 20, [](std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    Scene scene;
    scene.add("ground", box({-10, -10, -1}, {10, 10, 0}));
    for (int i = 0; i < 5; ++i) {
      Body b = testing::random_solid(rng, static_cast<int>((seed + i) % 5), 2, random_point(rng, -5, 5));
      b = b.translated({0, 0, 0.1 - b.bbox().min().z() + 2 * std::abs(random_point(rng, 0, 1).z())});
      scene.add("b" + std::to_string(i), b);
    }
    std::uniform_real_distribution<double> u(-1, 1);
    Vec3 d = testing::draw3(rng, u);
    d.z() = -0.4 - std::abs(d.z());
    scene.lights.push_back(seed % 2 ? Light::directional(d) : Light::point(Vec3(0, 0, 2) - 12 * d.normalized()));
    ShadowOptions pieces, faces;
    pieces.occluders = Occluders::Pieces;
    faces.occluders = Occluders::Faces;
    const ShadowResult a = compute_shadows(scene, pieces), b = compute_shadows(scene, faces);
    ASSERT_EQ(a.lights[0].faces.size(), b.lights[0].faces.size());
    int shaded = 0;
    for (size_t i = 0; i < a.lights[0].faces.size(); ++i) {
      const FaceShadow &x = a.lights[0].faces[i], &y = b.lights[0].faces[i];
      EXPECT_NEAR(x.shadow_area, y.shadow_area, 1e-9 * x.area) << "body " << x.body << " face " << x.face;
      shaded += x.shadow_area > 0 && x.shadow_area < x.area;
    }
    EXPECT_GT(shaded, 0);
  });
}

}  // namespace
}  // namespace hedra
