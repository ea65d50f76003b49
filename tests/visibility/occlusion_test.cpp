// Occlusion volumes against a direct segment–box test, and the exact boundary cases.
#include "hedra/visibility/occlusion.h"

#include <gtest/gtest.h>

#include <random>

#include "hedra/core/primitives.h"
#include "hedra/decompose/decompose.h"

namespace hedra {
namespace {

// Does the segment (or ray beyond for a direction) from the viewpoint to x meet the open box
// before x? Slab test in double; the test points stay away from the ties.
bool hidden_by_box(const Vec3& lo, const Vec3& hi, const Viewpoint& v, const Vec3& x) {
  const Vec3 from = v.at_infinity ? Vec3(x - 1e6 * v.direction) : v.point;
  double t0 = 0, t1 = 1;
  for (int i = 0; i < 3; ++i) {
    const double d = x[i] - from[i];
    if (d == 0) {
      if (from[i] <= lo[i] || from[i] >= hi[i]) return false;
      continue;
    }
    double a = (lo[i] - from[i]) / d, b = (hi[i] - from[i]) / d;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  return t0 < t1 && t0 < 1;
}

TEST(Occlusion, FacingOfTheUnitCube) {
  const Body cube = box({0, 0, 0}, {1, 1, 1});  // faces in course order: x=0, x=1, y=0, y=1, z=0, z=1
  const Viewpoint above = Viewpoint::towards({0, 0, -1});
  EXPECT_EQ(facing(cube, 5, above), Facing::Front);
  EXPECT_EQ(facing(cube, 4, above), Facing::Back);
  EXPECT_EQ(facing(cube, 0, above), Facing::EdgeOn);
  const Viewpoint eye = Viewpoint::at({0.5, 0.5, 10});
  EXPECT_EQ(facing(cube, 5, eye), Facing::Front);
  EXPECT_EQ(facing(cube, 0, eye), Facing::Back);  // x = 0 seen from x = 0.5: from inside its half-space
  const Viewpoint in_plane = Viewpoint::at({0, 0.5, 10});
  EXPECT_EQ(facing(cube, 0, in_plane), Facing::EdgeOn);
}

TEST(Occlusion, BoundaryIsNotHidden) {
  const Body cube = box({0, 0, 0}, {1, 1, 1});
  const OcclusionVolume down = occlusion_volume(cube, Viewpoint::towards({0, 0, -1}));
  ASSERT_TRUE(down.clipper);
  EXPECT_EQ(down.front_faces, std::vector<int>{5});
  EXPECT_EQ(down.silhouette.size(), 4u);
  EXPECT_TRUE(hides(down, {0.5, 0.5, -3}));
  EXPECT_TRUE(hides(down, {0.5, 0.5, 0.5}));   // inside the body
  EXPECT_FALSE(hides(down, {0.5, 0.5, 1}));    // on the front face
  EXPECT_FALSE(hides(down, {1, 0.5, -3}));     // on the silhouette plane x = 1
  EXPECT_FALSE(hides(down, {0.5, 0.5, 2}));    // in front
  // A stacked box sharing the face z = 0: its top face is not hidden.
  EXPECT_FALSE(hides(down, {0.25, 0.75, 1}));
  const OcclusionVolume inside = occlusion_volume(cube, Viewpoint::at({0.5, 0.5, 0.5}));
  EXPECT_FALSE(inside.clipper);
  EXPECT_FALSE(hides(inside, {0.5, 0.5, -3}));
}

TEST(Occlusion, ObliqueDirectionOnTheExactSilhouette) {
  // d = (1, 1, −1): the silhouette plane through the edge x = 1, z = 1 (y free) and d contains
  // (1, y, 1) + s·(1, 1, −1) exactly; such points are not hidden.
  const Body cube = box({0, 0, 0}, {1, 1, 1});
  const OcclusionVolume vol = occlusion_volume(cube, Viewpoint::towards({1, 1, -1}));
  EXPECT_FALSE(hides(vol, {3, 0.5 + 2, -1}));   // (1, .5, 1) + 2·d
  EXPECT_TRUE(hides(vol, {2.75, 2.5, -1}));
  EXPECT_EQ(vol.front_faces.size(), 3u);        // x = 0, y = 0, z = 1 face the light
}

TEST(Occlusion, AgreesWithASlabTestOnRandomPoints) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-6, 6);
  const Vec3 lo(-1, -0.5, 0), hi(1, 2, 1.5);
  const Body b = box(lo, hi);
  int checked = 0, hidden = 0;
  for (int k = 0; k < 40; ++k) {
    const Viewpoint v = k % 2 ? Viewpoint::towards({u(random), u(random), u(random)})
                              : Viewpoint::at({u(random) * 2, u(random) * 2, u(random) * 2});
    if (!v.at_infinity && (v.point.array() > lo.array() - 0.1).all() &&
        (v.point.array() < hi.array() + 0.1).all())
      continue;
    const OcclusionVolume vol = occlusion_volume(b, v);
    for (int i = 0; i < 500; ++i) {
      const Vec3 x(u(random), u(random), u(random));
      // Skip points near a tie of the double slab test (within 1e-6 of a changed answer).
      bool stable = true;
      const bool ref = hidden_by_box(lo, hi, v, x);
      for (int j = 0; j < 3 && stable; ++j)
        for (double e : {-1e-6, 1e-6}) {
          Vec3 y = x;
          y[j] += e;
          stable = stable && hidden_by_box(lo, hi, v, y) == ref;
        }
      if (!stable) continue;
      ASSERT_EQ(hides(vol, x), ref) << "view " << k << " point " << x.transpose();
      ++checked;
      hidden += ref;
    }
  }
  EXPECT_GT(checked, 15000);
  EXPECT_GT(hidden, 500);
}

// The Body-free volume of a triangle (Occluders::Faces, shadows) has the very planes of
// occlusion_volume on the two-sided triangle: same defining points, same sides, same order.
TEST(Occlusion, TriangleVolumeEqualsTheTwoSidedBodys) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int compared = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const std::array<Vec3, 3> t{Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)),
                                Vec3(u(rng), u(rng), u(rng))};
    const Body body = Body::two_sided_polygon({t[0], t[1], t[2]});
    const Viewpoint view = trial % 2 ? Viewpoint::at(Vec3(5 * u(rng), 5 * u(rng), 5 * u(rng)))
                                     : Viewpoint::towards(Vec3(u(rng), u(rng), u(rng)));
    const ExactPlane plane = exact_face_plane(body, 0);
    EXPECT_EQ(triangle_plane(t).points(), plane.points()) << trial;
    if (facing(plane, view) != Facing::Front) continue;
    const OcclusionVolume a = occlusion_volume(body, view), b = triangle_occlusion_volume(t, plane, view);
    ASSERT_TRUE(a.clipper && b.clipper);
    const auto &pa = a.clipper->planes(), &pb = b.clipper->planes();
    ASSERT_EQ(pa.size(), pb.size()) << trial;
    for (size_t i = 0; i < pa.size(); ++i) {
      EXPECT_EQ(pa[i].points(), pb[i].points()) << trial << " " << i;
      EXPECT_EQ(pa[i].negated(), pb[i].negated()) << trial << " " << i;
      EXPECT_EQ(pa[i].by_direction(), pb[i].by_direction()) << trial << " " << i;
    }
    EXPECT_EQ(a.silhouette, b.silhouette);
    ++compared;
  }
  EXPECT_GT(compared, 150);
}

// silhouette_volume is occlusion_volume without the front faces' planes: the same front faces
// and silhouette edges, and the same silhouette planes, in the same order.
TEST(Occlusion, SilhouetteVolumeIsTheVolumeLessItsFrontPlanes) {
  const Body ball = sphere({0.3, -0.2, 1}, 1.2, 1e-2);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 12; ++trial) {
    const Viewpoint view = trial % 2 ? Viewpoint::at(Vec3(6 * u(rng), 6 * u(rng), 6 + u(rng)))
                                     : Viewpoint::towards(Vec3(u(rng), u(rng), u(rng) - 1.5));
    std::vector<Facing> f(static_cast<size_t>(ball.face_count()));
    for (int i = 0; i < ball.face_count(); ++i) f[static_cast<size_t>(i)] = facing(ball, i, view);
    const OcclusionVolume full = occlusion_volume(ball, f, view), outer = silhouette_volume(ball, f, view);
    ASSERT_TRUE(full.clipper && outer.clipper) << trial;
    EXPECT_EQ(full.front_faces, outer.front_faces) << trial;
    EXPECT_EQ(full.silhouette, outer.silhouette) << trial;
    const auto &pf = full.clipper->planes(), &ps = outer.clipper->planes();
    ASSERT_EQ(pf.size(), full.front_faces.size() + ps.size()) << trial;
    for (size_t i = 0; i < ps.size(); ++i) {
      const ExactPlane& q = pf[full.front_faces.size() + i];
      EXPECT_EQ(q.points(), ps[i].points()) << trial << " " << i;
      EXPECT_EQ(q.negated(), ps[i].negated()) << trial << " " << i;
    }
  }
}

// The volume of an exact piece from its planes alone (pencil planes through its silhouette
// edges) against the volume of the same piece as a Body (planes through its corners), where
// the two are one polyhedron: the pieces of an axis-aligned non-convex prism, whose corners are
// all doubles. Exact sides of random points, of the pieces' corners and of points on their
// edges (the ties), for eyes and directions, must agree.
TEST(Occlusion, ExactPieceVolumeEqualsThePieceBodys) {
  const Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2);
  const Body holed = prism({{0, 0}, {4, 0}, {4, 3}, {0, 3}}, 0, 2, {{{1, 1}, {3, 1}, {3, 2}, {1, 2}}});
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1, 1);
  int hidden = 0, checked = 0;
  for (const Body& body : {l, holed}) {
    DecomposeOptions options;
    options.exact_pieces = true;
    const Decomposition d = decompose(body, options);
    ASSERT_GT(d.pieces.size(), 1u);
    for (int trial = 0; trial < 40; ++trial) {
      const Vec3 far(6 * u(rng), 6 * u(rng), 6 + 4 * u(rng));
      const Viewpoint view = trial % 2 ? Viewpoint::towards(-far) : Viewpoint::at(far + Vec3(2, 1.5, 1));
      for (size_t k = 0; k < d.pieces.size(); ++k) {
        ASSERT_FALSE(d.exact_pieces[k].faces.empty());
        const OcclusionVolume exact = occlusion_volume(d.exact_pieces[k], view);
        const OcclusionVolume rounded = occlusion_volume(d.pieces[k], view);
        ASSERT_EQ(exact.clipper.has_value(), rounded.clipper.has_value());
        EXPECT_EQ(exact.front_faces.size(), rounded.front_faces.size());
        if (exact.clipper) {
          EXPECT_EQ(exact.clipper->plane_count(), rounded.clipper->plane_count());
          for (const ExactPlane& f : exact.clipper->planes()) EXPECT_TRUE(f.by_points() || f.by_exact());
        }
        std::vector<Vec3> points;
        const auto& v = d.pieces[k].vertices();
        for (int i = 0; i < 200; ++i) points.push_back(Vec3(2 + 3 * u(rng), 1.5 + 3 * u(rng), 1 + 3 * u(rng)));
        for (const Vec3& p : v) points.push_back(p);
        for (const Edge& e : d.pieces[k].edges()) {
          const Vec3 &a = v[static_cast<size_t>(e.v0)], &b = v[static_cast<size_t>(e.v1)];
          points.push_back(0.5 * (a + b));
          // Beyond the edge, away from the viewpoint: on its silhouette plane when it is one.
          const Vec3 ray = view.ray_to(0.5 * (a + b));
          points.push_back(0.5 * (a + b) + 0.5 * ray);
        }
        for (const Vec3& p : points) {
          const bool h = hides(exact, p);
          EXPECT_EQ(h, hides(rounded, p)) << "piece " << k << " trial " << trial;
          hidden += h;
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(hidden, checked / 20);
}

}  // namespace
}  // namespace hedra
