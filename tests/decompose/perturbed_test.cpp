// Regression tests of the perturbation study (docs/benchmarks.md, "Under perturbation"): the
// benchmark's own inputs that made the exact decomposition fail, each named after its bug.
// Root cause of all of them: the rounding guard (faces within 64 ulps of one plane share it,
// input vertices that close to a plane count as on it) is a model of the input, and a triangle
// soup perturbed by 1e-14…1e-12 of its size has real folds at the guard's scale, where the
// model contradicts itself. decompose() now detects that and decomposes the input itself,
// with exact planes and exact sides only (kernel/src/decompose/decompose.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hedra/baselines/decompose_baselines.h"
#include "hedra/core/error.h"
#include "hedra/decompose/decompose.h"
#include "hedra/mesh/convexity.h"
#include "testing/convexity_oracle.h"
#include "testing/decomposition_suite.h"
#include "testing/differential.h"

namespace hedra {
namespace {

// Input `copy` (0–2) of suite shape `name` at `delta`, as the full benchmark makes it (seed
// 1234, three copies per shape, in suite order).
Body study_input(double delta, const std::string& name, int copy) {
  std::mt19937 random(1234);
  for (const suite::Shape& s : suite::shapes(false)) {
    if (s.name == "cross" || s.name.rfind("plate", 0) == 0) continue;
    for (int k = 0; k < 3; ++k) {
      Body b = suite::perturbed_soup(suite::rotated(s.body), delta, random);
      if (s.name == name && k == copy) return b;
    }
  }
  ADD_FAILURE() << "no shape " << name;
  return box({0, 0, 0}, {1, 1, 1});
}

// Decomposes and checks the result exactly: verified (exact pieces convex, exact volumes
// summing exactly to the input's), every rounded piece convex by the course's definition
// evaluated exactly, volumes within 1e-9, cover by sampling.
void expect_exact_decomposition(const Body& body, const std::string& what) {
  SCOPED_TRACE(what);
  DecomposeOptions o;
  o.verify = true;
  o.threads = 1;
  Decomposition d;
  ASSERT_NO_THROW(d = decompose(body, o));
  EXPECT_TRUE(d.verified);
  double volume = 0;
  for (const Body& piece : d.pieces) {
    volume += piece.volume();
    EXPECT_TRUE(testing::nonconvex_faces_oracle(piece).empty());
  }
  EXPECT_NEAR(volume, body.volume(), 1e-9 * body.volume());
  std::mt19937_64 rng(5);
  EXPECT_EQ(testing::cover_error(body, d.pieces, rng), "");
}

// "the plane of a reflex edge does not cut its piece": a reflex edge between two triangles
// that the guard keeps apart, whose piece lies below the edge's plane only within the guard.
// At δ = 1e-13 this was the 12 % of docs/benchmarks.md (comb 16); the full run also hit the
// L prism at 1e-14 and comb 4 at 1e-13.
TEST(DecomposePerturbed, ReflexEdgePlaneThatCutsItsPieceOnlyWithinTheGuard) {
  expect_exact_decomposition(study_input(1e-14, "L prism", 2), "L prism, 1e-14, copy 2");
  expect_exact_decomposition(study_input(1e-13, "comb 4", 2), "comb 4, 1e-13, copy 2");
  expect_exact_decomposition(study_input(1e-13, "comb 16", 0), "comb 16, 1e-13, copy 0");
}

// "internal error: decompose: a piece is not closed": a cap built from points the guard puts
// on the cutting plane although they are not (thin star 8 at 1e-14).
TEST(DecomposePerturbed, PieceNotClosedAfterACutThroughGuardedPoints) {
  expect_exact_decomposition(study_input(1e-14, "thin star 8", 1), "thin star 8, 1e-14, copy 1");
}

// "split: the cut's boundary crosses itself": the cap's boundary, projected, crosses itself
// when points within the guard count as on the plane (staircase 10 at 1e-13).
TEST(DecomposePerturbed, CutBoundaryThatCrossesItselfWithinTheGuard) {
  expect_exact_decomposition(study_input(1e-13, "staircase 10", 1), "staircase 10, 1e-13, copy 1");
}

// Found by Differential.DecompositionPiecesAreExactConvexAndCover (seed 1000003): a convex
// hexagonal prism as a triangle soup perturbed by 1e-14 has folds within the guard; no reflex
// edge within the guard, so it came back whole and "verified", but it is not convex by the
// exact test. Now it is decomposed exactly.
TEST(DecomposePerturbed, FoldWithinTheGuardIsNotConvexity) {
  std::mt19937_64 rng(1000003);
  Body body = testing::random_solid(rng, 3, 4, {0, 0, 0});
  const double delta = std::pow(10.0, -15 + static_cast<double>(rng() % 10));
  ASSERT_DOUBLE_EQ(delta, 1e-14);
  std::vector<Vec3> v = body.vertices();
  std::uniform_real_distribution<double> u(-1, 1);
  for (Vec3& p : v) p += delta * body.scale() * Vec3{u(rng), u(rng), u(rng)};  // braces: in order
  std::vector<Face> faces;
  for (const Triangle& t : body.triangles()) faces.push_back(Face{t.v[0], t.v[1], t.v[2]});
  BodyOptions o;
  o.planarity_tolerance = 1;
  const Body soup(std::move(v), std::move(faces), o);
  ASSERT_FALSE(is_convex(soup));
  expect_exact_decomposition(soup, "hexagonal prism soup, 1e-14");
}

}  // namespace
}  // namespace hedra

namespace hedra {
namespace {

// The floating-point variant on the full study's 24 inputs at δ = 1e-9 crashed (segmentation
// fault in the cap's constrained triangulation: two rounded cut points on one spot made a
// zero-length boundary edge). It may fail, but only with DecompositionFailed; where it
// finishes, its volume is right.
TEST(DecomposePerturbed, FloatCapWithCoincidentRoundedCutPointsFailsCleanly) {
  std::mt19937 random(1234);
  int inputs = 0;
  for (const suite::Shape& s : suite::shapes(false)) {
    if (s.name == "cross" || s.name.rfind("plate", 0) == 0) continue;
    for (int k = 0; k < 3; ++k) {
      const Body b = suite::perturbed_soup(suite::rotated(s.body), 1e-9, random);
      ++inputs;
      try {
        DecomposeOptions o;
        o.threads = 1;
        const Decomposition d = decompose_float(b, 1e-9, o);
        double volume = 0;
        for (const Body& p : d.pieces) volume += p.volume();
        EXPECT_NEAR(volume, b.volume(), 1e-6 * b.volume()) << s.name << " " << k;
      } catch (const DecompositionFailed&) {
      }
    }
  }
  EXPECT_EQ(inputs, 24);
}

}  // namespace
}  // namespace hedra
