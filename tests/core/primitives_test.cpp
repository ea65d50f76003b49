#include "hedra/core/primitives.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hedra/core/error.h"
#include "hedra/core/predicates.h"
#include "hedra/mesh/boolean.h"
#include "hedra/mesh/convexity.h"

namespace hedra {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Primitives, BoxMeasures) {
  Body b = box({1, 2, 3}, {4, 6, 8});
  EXPECT_EQ(b.volume(), 60);
  EXPECT_EQ(b.area(), 2 * (12 + 15 + 20));
  EXPECT_LT((b.centroid() - Vec3(2.5, 4, 5.5)).norm(), 1e-14);
  EXPECT_THROW(box({0, 0, 0}, {1, 0, 1}), InvalidInput);
}

TEST(Primitives, LPrismExact) {
  Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2);
  EXPECT_EQ(l.face_count(), 8);
  EXPECT_EQ(l.vertex_count(), 12);
  EXPECT_EQ(l.edge_count(), 18);
  EXPECT_EQ(l.volume(), 12);  // (4 + 2) · 2
  EXPECT_EQ(l.area(), 2 * 6 + 2 * (4 + 1 + 3 + 1 + 2 + 3));
  // Centroid of the L: area-weighted mean of 4×1 at (2, 0.5) and 1×2 at (0.5, 2).
  EXPECT_LT((l.centroid() - Vec3((4 * 2 + 2 * 0.5) / 6, (4 * 0.5 + 2 * 2) / 6.0, 1)).norm(), 1e-14);
}

TEST(Primitives, PrismDropsCollinearVerticesAndAcceptsClockwise) {
  Body b = prism({{0, 0}, {0, 2}, {2, 2}, {2, 1}, {2, 0}, {1, 0}}, 0, 1);  // clockwise
  EXPECT_EQ(b.face_count(), 6);
  EXPECT_EQ(b.volume(), 4);
}

TEST(Primitives, PyramidAndFrustum) {
  Body p = pyramid({{0, 0}, {2, 0}, {2, 2}, {0, 2}}, 0, {1, 1, 3});
  EXPECT_EQ(p.face_count(), 5);
  EXPECT_DOUBLE_EQ(p.volume(), 4.0 * 3 / 3);
  EXPECT_LT((p.centroid() - Vec3(1, 1, 0.75)).norm(), 1e-14);
  Body upside_down = pyramid({{0, 0}, {2, 0}, {2, 2}, {0, 2}}, 0, {1, 1, -3});
  EXPECT_DOUBLE_EQ(upside_down.volume(), 4);
  // Frustum cut halfway: V = h/3 (A1 + A2 + sqrt(A1 A2)) = 1.5/3 (4 + 1 + 2).
  Body f = frustum({{0, 0}, {2, 0}, {2, 2}, {0, 2}}, 0, {1, 1, 3}, 1.5);
  EXPECT_EQ(f.face_count(), 6);
  EXPECT_NEAR(f.volume(), 3.5, 1e-14);
  EXPECT_THROW(frustum({{0, 0}, {2, 0}, {2, 2}}, 0, {1, 1, 3}, 3), InvalidInput);
}

TEST(Primitives, RegularPrismVolume) {
  const int n = 7;
  Body b = regular_prism(n, 2, 0, 3);
  EXPECT_EQ(b.face_count(), n + 2);
  EXPECT_NEAR(b.volume(), 0.5 * n * 4 * std::sin(2 * kPi / n) * 3, 1e-12);
}

TEST(Primitives, CylinderMeetsChordalTolerance) {
  for (double tol : {0.1, 0.01, 0.001}) {
    const double r = 1;
    int n = segments_for_tolerance(r, tol);
    EXPECT_LE(r * (1 - std::cos(kPi / n)), tol);
    EXPECT_GT(r * (1 - std::cos(kPi / (n - 1))), tol);  // one fewer side would not do
    Body c = cylinder(r, 0, 2, tol);
    EXPECT_EQ(c.face_count(), n + 2);
    EXPECT_NEAR(c.volume(), 0.5 * n * std::sin(2 * kPi / n) * 2, 1e-12);
  }
}

TEST(Primitives, ConeVolume) {
  Body c = cone(1, 0, 3, 0.01);
  int n = segments_for_tolerance(1, 0.01);
  EXPECT_EQ(c.face_count(), n + 1);
  EXPECT_NEAR(c.volume(), 0.5 * n * std::sin(2 * kPi / n) * 3 / 3, 1e-12);
}

TEST(Primitives, SphereMeetsChordalToleranceWithFewestBands) {
  for (double tol : {0.1, 0.01, 0.001}) {
    const double r = 2;
    Body s = sphere({1, 2, 3}, r, tol);
    // Independent check: the distance from the centre to every face plane is >= r − tol.
    double worst = 0;
    for (int f = 0; f < s.face_count(); ++f)
      worst = std::max(worst, r - s.plane(f).value(Vec3(1, 2, 3)));
    EXPECT_LE(worst, tol * (1 + 1e-9));
    // Fewest bands: the next coarser sphere misses the tolerance.
    const int rings = (s.face_count() + 0) / 1;  // faces = 2·rings·rings
    int bands = static_cast<int>(std::lround(std::sqrt(rings / 2.0)));
    EXPECT_EQ(2 * bands * bands, s.face_count());
    EXPECT_GT(sphere_chordal_error(r, bands - 1), tol);
    EXPECT_LT(std::abs(s.volume() - 4.0 / 3 * kPi * r * r * r), 4.0 * kPi * r * r * tol);
    EXPECT_LT((s.centroid() - Vec3(1, 2, 3)).norm(), 1e-12);
  }
}

// Issue 14 ("exact inside"): a latitude–longitude sphere with vertices rounded to the sphere
// had quadrilaterals planar only within rounding, so its exact image was no polyhedron, and a
// Boolean with it had no exactly planar solid. Reference: exact orientation tests on every
// quadrilateral's fourth corner, and exact convexity.
TEST(Primitives, SphereFacesAreExactlyPlanarAndItIsExactlyConvex) {
  for (double tol : {0.1, 0.01, 1e-3, 1e-4}) {
    const double r = 1.7;
    const Body s = sphere({0, 0, 0}, r, tol);
    int quads = 0;
    for (const Face& f : s.faces()) {
      const auto& l = f.loops[0];
      if (l.size() != 4) continue;
      ++quads;
      const auto& v = s.vertices();
      ASSERT_EQ(orient3d(v[l[0]], v[l[1]], v[l[2]], v[l[3]]), Sign::Zero) << "tolerance " << tol;
    }
    EXPECT_GT(quads, 0);
    for (const Vec3& p : s.vertices()) EXPECT_NEAR(p.norm(), r, kSphereSnap * r);
    EXPECT_TRUE(is_convex(s));
    // Symmetric to the bit: the centroid is the centre.
    EXPECT_LT(s.centroid().norm(), 1e-15);
  }
  // About a centre near the origin (within about 4r) whose coordinates lie on the grid of the
  // moved coordinates: snapped to a grid that the move keeps exact, so the body itself is
  // exactly planar, with no exact solid of its own to carry. Reference: exact orientation of
  // every quadrilateral, exact convexity, the distance to the centre.
  for (const Vec3& c : {Vec3(1, 2, 3), Vec3(-1.5, 0, 1.5), Vec3(0.5, -0.25, 0)}) {
    const double r = c.x() == -1.5 ? 1.5 : 1.7;
    const Body s = sphere(c, r, 1e-3);
    EXPECT_FALSE(s.has_exact_solid());
    EXPECT_TRUE(s.faces_off_plane().empty());
    const auto& v = s.vertices();
    for (const Face& f : s.faces()) {
      const auto& l = f.loops[0];
      if (l.size() == 4) ASSERT_EQ(orient3d(v[l[0]], v[l[1]], v[l[2]], v[l[3]]), Sign::Zero) << c.transpose();
    }
    for (const Vec3& p : v) EXPECT_NEAR((p - c).norm(), r, kSphereSnap * r);
    EXPECT_EQ(s.face_count(), sphere({0, 0, 0}, r, 1e-3).face_count());
    EXPECT_TRUE(is_convex(s));
  }
  // Further away (or about a centre off that grid): the rounding of the translated corners,
  // with the exact image of the planar sphere (what Booleans and the exact decompositions use).
  EXPECT_TRUE(sphere({0.1, -0.3, 0}, 1.7, 0.01).has_exact_solid());  // 0.1: below that grid
  const Body moved = sphere({10, 20, 30}, 1.7, 0.01);
  EXPECT_TRUE(moved.has_exact_solid());
  // The same exact solid as the sphere about the origin moved by transformed().
  const Body reference = sphere({0, 0, 0}, 1.7, 0.01).transformed(Transform::translation({10, 20, 30}));
  EXPECT_EQ(moved.vertices(), reference.vertices());
  EXPECT_EQ(exact_volume_sign({{1, moved}, {-1, reference}}), Sign::Zero);
  EXPECT_NE(exact_volume_sign({{1, Body(moved.vertices(), moved.faces())}, {-1, reference}}), Sign::Zero);
  EXPECT_FALSE(sphere({0, 0, 0}, 1.7, 0.01).has_exact_solid());
}

}  // namespace
}  // namespace hedra
