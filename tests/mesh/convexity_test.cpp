#include "hedra/mesh/convexity.h"

#include "hedra/core/parallel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "hedra/core/primitives.h"
#include "testing/clip_fixtures.h"
#include "testing/convexity_oracle.h"

namespace hedra {
namespace {

Body comb(int teeth) {
  // A comb seen from the side: a spine along x with `teeth` teeth pointing up.
  Polygon2 p{{0, 0}, {2.0 * teeth - 1, 0}};
  for (int i = teeth - 1; i >= 0; --i) {
    p.emplace_back(2.0 * i + 1, 3);
    p.emplace_back(2.0 * i, 3);
    if (i > 0) {
      p.emplace_back(2.0 * i, 1);
      p.emplace_back(2.0 * i - 1, 1);
    }
  }
  // Counter-clockwise: the bottom edge, then the teeth from right to left.
  return prism(p, 0, 1);
}

Body star(int points) {
  Polygon2 p;
  for (int i = 0; i < 2 * points; ++i) {
    double r = i % 2 ? 1.0 : 2.5, t = std::numbers::pi * i / points;
    p.emplace_back(r * std::cos(t), r * std::sin(t));
  }
  return prism(p, 0, 1);
}

Body staircase(int steps) {
  Polygon2 p{{0, 0}, {double(steps), 0}};
  for (int i = steps; i >= 1; --i) {
    p.emplace_back(i, i);
    p.emplace_back(i - 1, i);
  }
  return prism(p, 0, 2).rotated_x(90);  // standing up, to exercise rounded coordinates too
}

struct Case {
  const char* name;
  Body body;
  bool convex;
};

std::vector<Case> cases() {
  return {
      {"box", box({0, 0, 0}, {1, 2, 3}), true},
      {"rotated box", box({0, 0, 0}, {1, 2, 3}).transformed(Transform::rotation({1, 1, 0}, 33)), true},
      {"pyramid", pyramid({{0, 0}, {2, 0}, {2, 2}, {0, 2}}, 0, {1, 1, 3}), true},
      {"frustum", frustum({{0, 0}, {3, 0}, {1.5, 2}}, 0, {1.5, 0.7, 4}, 2), true},
      {"hexagonal prism", regular_prism(6, 1, 0, 1), true},
      {"sphere", sphere({0, 0, 0}, 1, 0.01), true},
      {"L prism", prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2), false},
      {"comb", comb(5), false},
      {"star prism", star(5), false},
      {"box with a hole", prism({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, 1, {{{1, 1}, {3, 1}, {3, 3}, {1, 3}}}), false},
      {"staircase", staircase(4), false},
  };
}

TEST(Convexity, ExactAndRotationFormulationsAgree) {
  for (const Case& c : cases()) {
    ConvexityReport exact = convexity(c.body);
    ConvexityReport course = convexity_by_rotation(c.body);
    EXPECT_EQ(exact.convex, c.convex) << c.name;
    EXPECT_FALSE(exact.flat) << c.name;
    EXPECT_EQ(exact.nonconvex_faces, course.nonconvex_faces) << c.name;
    EXPECT_EQ(exact.convex, course.convex) << c.name;
    // The raw-data overload agrees with the Body overload.
    EXPECT_EQ(convexity(c.body.vertices(), c.body.faces()).nonconvex_faces, exact.nonconvex_faces)
        << c.name;
  }
}

TEST(Convexity, VerdictSurvivesRandomRigidMotionsAndScales) {
  // Seeded property test over wide coordinate ranges: the convex/non-convex verdict and the
  // volume (relative 1e-12) do not change under rotation, translation and scaling.
  std::mt19937 random(20261122);
  std::uniform_real_distribution<double> unit(-1, 1), exponent(-8, 8);
  for (const Case& c : cases()) {
    for (int trial = 0; trial < 12; ++trial) {
      const double s = std::pow(10.0, exponent(random));
      Transform t = Transform::rotation({unit(random), unit(random), unit(random)}, 360 * unit(random)) *
                    Transform::scaling(s) *
                    Transform::translation(s * Vec3(unit(random), unit(random), unit(random)) * 100);
      Body moved = c.body.transformed(t);
      EXPECT_EQ(convexity(moved).convex, c.convex) << c.name << " trial " << trial;
      EXPECT_NEAR(moved.volume() / (s * s * s), c.body.volume(), 1e-12 * c.body.volume())
          << c.name << " trial " << trial;
    }
  }
}

TEST(Convexity, LPrismNonConvexFacesAreTheReflexSides) {
  Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2);
  // Faces: bottom, top, then sides (0,0)-(4,0), (4,0)-(4,1), (4,1)-(1,1), (1,1)-(1,3), ...
  // The two sides meeting at the reflex edge x = 1, y = 1 are the non-convex ones.
  EXPECT_EQ(convexity(l).nonconvex_faces, (std::vector<int>{4, 5}));
}

TEST(Convexity, BoxWithHoleIsNonConvexOnlyAtTheHoleWalls) {
  Body b = prism({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, 1, {{{1, 1}, {3, 1}, {3, 3}, {1, 3}}});
  EXPECT_EQ(convexity(b).nonconvex_faces, (std::vector<int>{6, 7, 8, 9}));
}

TEST(Convexity, FlatDataIsReportedAsDegenerate) {
  std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<Face> f = {{0, 1, 2, 3}, {3, 2, 1, 0}};
  EXPECT_TRUE(convexity(v, f).flat);
  EXPECT_FALSE(convexity(v, f).convex);
  EXPECT_TRUE(convexity_by_rotation(v, f).flat);
}


// ---- The O(V + E) certificate of is_convex() against the O(F·V) definition ----

void expect_matches_oracle(const Body& body, const std::string& name) {
  const std::vector<int> oracle = testing::nonconvex_faces_oracle(body);
  EXPECT_EQ(is_convex(body), oracle.empty()) << name;
  ConvexityReport report = convexity(body);
  EXPECT_EQ(report.convex, oracle.empty()) << name;
  EXPECT_EQ(report.nonconvex_faces, oracle) << name;
}

std::vector<Vec3> random_points(std::mt19937_64& rng, int n, bool on_sphere) {
  std::normal_distribution<double> normal(0, 1);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i) {
    Vec3 d(normal(rng), normal(rng), normal(rng));
    d.normalize();
    points.push_back(on_sphere ? d : d * std::cbrt(unit(rng)));
  }
  return points;
}

TEST(IsConvex, RandomConvexHullsAreConvex) {
  std::mt19937_64 rng(151);
#ifdef HEDRA_SANITIZED
  const int step = 10;  // up to 394 points: the O(F·V) oracle took 17 s under ASan + UBSan at 25
#else
  const int step = 25;
#endif
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 4 + trial * step;
    Body hull = testing::convex_hull_body(random_points(rng, n, trial % 2 == 0));
    expect_matches_oracle(hull, "hull " + std::to_string(trial));
    EXPECT_EQ(certify_convexity(hull), ConvexityCertificate::Convex) << trial;
  }
}

TEST(IsConvex, DentedHullsAgreeWithTheDefinition) {
  // A hull with one vertex pulled towards the centre: non-convex unless the dent is shallow
  // enough to stay inside every neighbouring plane; the definition decides which.
  std::mt19937_64 rng(152);
  std::uniform_real_distribution<double> depth(0.0, 1.0);
  int nonconvex = 0;
#ifdef HEDRA_SANITIZED
  const int trials = 30;  // 13 s under ASan + UBSan with 60
#else
  const int trials = 60;
#endif
  for (int trial = 0; trial < trials; ++trial) {
    Body hull = testing::convex_hull_body(random_points(rng, 30 + trial * 7, true));
    std::vector<Vec3> v = hull.vertices();
    v[static_cast<size_t>(trial) % v.size()] *= 1 - 0.2 * depth(rng) * depth(rng);
    Body dented(v, hull.faces());
    expect_matches_oracle(dented, "dented " + std::to_string(trial));
    nonconvex += !is_convex(dented);
  }
  EXPECT_GT(nonconvex, trials / 2);  // most dents are deep enough to show
}

TEST(IsConvex, RotatedAndRoundedBodiesAgreeWithTheDefinition) {
  // Rotations round coordinates, so quadrilaterals and caps are no longer exactly planar: the
  // certificate splits quadrilaterals and leaves larger rounded faces to the definition.
  std::mt19937 random(153);
  std::uniform_real_distribution<double> unit(-1, 1);
#ifdef HEDRA_SANITIZED
  const double sphere_tolerance = 0.006;  // the O(F·V) oracle under ASan + UBSan
#else
  const double sphere_tolerance = 0.002;
#endif
  std::vector<std::pair<std::string, Body>> bodies = {
      {"sphere", sphere({0.3, -0.2, 0.1}, 1.5, sphere_tolerance)},
      {"cylinder", cylinder(1, 0, 2, 0.001)},
      {"star", star(7)},
      {"comb", comb(4)},
      {"box", box({0, 0, 0}, {1, 2, 3})},
  };
  for (const auto& [name, body] : bodies) {
    expect_matches_oracle(body, name);
#ifdef HEDRA_SANITIZED
    const int trials = 1;  // the O(F·V) oracle under ASan + UBSan
#else
    const int trials = 4;
#endif
    for (int trial = 0; trial < trials; ++trial) {
      Transform t = Transform::rotation({unit(random), unit(random), unit(random)}, 180 * unit(random)) *
                    Transform::translation(Vec3(unit(random), unit(random), unit(random)) * 10);
      expect_matches_oracle(body.transformed(t), name + " rotated " + std::to_string(trial));
    }
  }
}

// A rounded quadrilateral q0 q1 q2 q3 (q2 lowered by 8e-15, within rounding planarity) folded
// along q1–q3, next to a triangle q3 q2 w across q2–q3. The surface is convex, but the face's
// support triple (q0, q1, q2: its smallest vertex and the farthest one) is not one of its two
// pieces, and w can lie outside that plane while every edge stays convex. Then the body is not
// convex by the definition (a vertex off the face outside its plane). The certificate finds it
// only around q3, the face's own vertex outside that plane.
Body folded_roof(double w_height) {
  const double e = -8e-15;
  const std::vector<Vec3> v = {{0, 0, 0},    {1, 0, 0},    {1, 1, e},      {0, 1, 0},
                               {0.5, 1.5, w_height * e},   {0, 0, -1},     {1, 0, -1},
                               {1, 1, -1},   {0.5, 1.5, -1}, {0, 1, -1}};
  const std::vector<Face> f = {{0, 1, 2, 3}, {3, 2, 4},    {0, 5, 6, 1}, {1, 6, 7, 2},
                               {2, 7, 8, 4}, {4, 8, 9, 3}, {3, 9, 5, 0}, {5, 9, 8, 7, 6}};
  return Body(v, f);
}

TEST(IsConvex, RoundedQuadrilateralWhoseSupportPlaneCutsItsNeighbourIsNotConvex) {
  // w at 1.25e: below the piece (q1, q2, q3) (at e there), above plane (q0, q1, q2) (1.5e).
  const Body cut = folded_roof(1.25);
  EXPECT_EQ(certify_convexity(cut), ConvexityCertificate::NotConvex);
  expect_matches_oracle(cut, "w outside the support plane");
  EXPECT_FALSE(is_convex(cut));
  // w at 2e: below both, convex.
  const Body kept = folded_roof(2);
  EXPECT_EQ(certify_convexity(kept), ConvexityCertificate::Convex);
  expect_matches_oracle(kept, "w inside the support plane");
  EXPECT_TRUE(is_convex(kept));
}

TEST(IsConvex, ReflexEdgesSettleNonConvexBodiesAtOnce) {
  for (const Case& c : cases())
    if (!c.convex) EXPECT_EQ(certify_convexity(c.body), ConvexityCertificate::NotConvex) << c.name;
    else EXPECT_EQ(certify_convexity(c.body), ConvexityCertificate::Convex) << c.name;
}

TEST(IsConvex, CoplanarSplitFacesAreConvex) {
  // A cube whose top is an L-shaped face and a square face in one plane: flat edges and a
  // non-convex face on a convex body.
  std::vector<Vec3> v = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2}, {2, 0, 2},
                         {2, 2, 2}, {0, 2, 2}, {1, 0, 2}, {1, 1, 2}, {0, 1, 2}, {2, 1, 2}};
  // Top: square (0,0)-(1,1) at vertices 4, 8, 9, 10; L = the rest: 8, 5, 11, 6, 7, 10, 9.
  std::vector<Face> f = {{0, 3, 2, 1},        {4, 8, 9, 10},        {8, 5, 11, 6, 7, 10, 9},
                         {0, 1, 5, 8, 4},     {1, 2, 6, 11, 5},     {2, 3, 7, 6},
                         {3, 0, 4, 10, 7}};
  Body cube(v, f);
  expect_matches_oracle(cube, "split cube");
  EXPECT_TRUE(is_convex(cube));
  EXPECT_EQ(certify_convexity(cube), ConvexityCertificate::Convex);
}

TEST(IsConvex, CollinearVerticesAndFilledHolesAreCertified) {
  // A box whose edges carry midpoints (every face has collinear vertices), and a box whose
  // top is a face with a hole filled by a coplanar face (edges along a hole loop are flat).
  std::vector<Vec3> v;
  auto id = [&](double x, double y, double z) {
    for (size_t i = 0; i < v.size(); ++i)
      if (v[i] == Vec3(x, y, z)) return static_cast<int>(i);
    v.emplace_back(x, y, z);
    return static_cast<int>(v.size()) - 1;
  };
  // Each face: its corners counter-clockwise from outside with the edge midpoints between.
  auto face = [&](std::vector<Vec3> corners) {
    std::vector<int> loop;
    for (size_t i = 0; i < corners.size(); ++i) {
      const Vec3 a = corners[i], b = corners[(i + 1) % corners.size()], m = (a + b) / 2;
      loop.push_back(id(a.x(), a.y(), a.z()));
      loop.push_back(id(m.x(), m.y(), m.z()));
    }
    return Face(loop);
  };
  std::vector<Face> f = {
      face({{0, 0, 0}, {0, 2, 0}, {2, 2, 0}, {2, 0, 0}}), face({{0, 0, 2}, {2, 0, 2}, {2, 2, 2}, {0, 2, 2}}),
      face({{0, 0, 0}, {2, 0, 0}, {2, 0, 2}, {0, 0, 2}}), face({{2, 0, 0}, {2, 2, 0}, {2, 2, 2}, {2, 0, 2}}),
      face({{2, 2, 0}, {0, 2, 0}, {0, 2, 2}, {2, 2, 2}}), face({{0, 2, 0}, {0, 0, 0}, {0, 0, 2}, {0, 2, 2}})};
  Body midpoints(v, f);
  expect_matches_oracle(midpoints, "box with edge midpoints");
  EXPECT_EQ(certify_convexity(midpoints), ConvexityCertificate::Convex);

  Body plate = prism({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, 1, {{{1, 1}, {3, 1}, {3, 3}, {1, 3}}});
  std::vector<Vec3> pv = plate.vertices();
  std::vector<Face> pf;
  for (const Face& g : plate.faces()) {
    if (g.loops.size() == 2 && plate.inner_normal(static_cast<int>(&g - &plate.faces()[0])).z() < 0) {
      pf.push_back(g);  // the top face with its hole
      std::vector<int> fill(g.loops[1].rbegin(), g.loops[1].rend());
      pf.push_back(Face(fill));  // the hole, filled flush
    } else if (g.loops.size() == 2) {
      pf.push_back(Face(g.loops[0]));  // the bottom without its hole
    }
  }
  ASSERT_EQ(pf.size(), 3u);
  // Keep the outer walls; drop the hole walls and the vertices only they used.
  for (const Face& g : plate.faces())
    if (g.loops.size() == 1) {
      bool outer = true;
      for (int x : g.loops[0]) outer = outer && (pv[x].x() == 0 || pv[x].x() == 4 || pv[x].y() == 0 || pv[x].y() == 4);
      if (outer) pf.push_back(g);
    }
  // The bottom's hole vertices are no longer used: rebuild with used vertices only.
  std::vector<int> remap(pv.size(), -1);
  std::vector<Vec3> used;
  for (Face& g : pf)
    for (auto& loop : g.loops)
      for (int& x : loop) {
        if (remap[x] < 0) { remap[x] = static_cast<int>(used.size()); used.push_back(pv[x]); }
        x = remap[x];
      }
  Body filled(used, pf);
  expect_matches_oracle(filled, "plate with a filled hole");
  EXPECT_EQ(certify_convexity(filled), ConvexityCertificate::Convex);
}

// A bipyramid over the heptagram {7/2}: the equator runs twice around the axis, every edge
// is convex and the centre lies inside every face plane, yet the surface wraps twice around it.
Body heptagram_bipyramid() {
  std::vector<Vec3> v = {{0, 0, 1}, {0, 0, -1}};
  for (int i = 0; i < 7; ++i) {
    const double a = 4 * std::numbers::pi * i / 7;
    v.emplace_back(std::cos(a), std::sin(a), 0);
  }
  std::vector<Face> f;
  for (int i = 0; i < 7; ++i) {
    const int p = 2 + i, q = 2 + (i + 1) % 7;
    f.push_back(Face{p, q, 0});
    f.push_back(Face{q, p, 1});
  }
  return Body(v, f);
}

TEST(IsConvex, LocallyConvexSurfaceWoundTwiceIsNotConvex) {
  // Only the winding number tells the heptagram bipyramid from a convex body.
  const Body wound = heptagram_bipyramid();
  expect_matches_oracle(wound, "heptagram bipyramid");
  EXPECT_FALSE(is_convex(wound));
  EXPECT_NE(certify_convexity(wound), ConvexityCertificate::Convex);
  // Its edges are all convex: every face's neighbours across an edge lie inside its plane.
  for (const Edge& e : wound.edges())
    for (int x : wound.faces()[static_cast<size_t>(e.right_face)].loops[0])
      EXPECT_NE(wound.face_side(e.left_face, wound.vertices()[static_cast<size_t>(x)]), Sign::Negative);
}

TEST(IsConvex, WindingCountedAlongARayThroughEdgesAndCornersFallsBackToTheSolidAngle) {
  // The certificate counts how many faces one ray from the centre crosses (exact); a ray
  // through an edge or a corner cannot be counted, and the floating-point solid-angle sum
  // decides instead. Both must give the same verdicts.
  const Body cube = box({-1, -1, -1}, {1, 1, 1});
  const Body ball = sphere({0, 0, 0}, 1, 1e-2);
  for (const Vec3& ray : {Vec3(0.3, 0.2, 1), Vec3(1, 1, 0), Vec3(1, 1, 1), Vec3(0, 0, 1), Vec3(1, 0, 0)}) {
    SCOPED_TRACE(::testing::Message() << "ray " << ray.transpose());
    EXPECT_EQ(internal::certify_convexity_along(cube, ray), ConvexityCertificate::Convex);
    EXPECT_EQ(internal::certify_convexity_along(ball, ray), ConvexityCertificate::Convex);
  }
  // The heptagram bipyramid winds twice: two crossings along a generic ray; along the axis
  // the ray meets the apex, and along (1, 0, 0) an equator vertex.
  const Body wound = heptagram_bipyramid();
  for (const Vec3& ray : {Vec3(0.3, 0.2, 0.5), Vec3(0, 0, 1), Vec3(1, 0, 0)}) {
    SCOPED_TRACE(::testing::Message() << "ray " << ray.transpose());
    EXPECT_EQ(internal::certify_convexity_along(wound, ray), ConvexityCertificate::Undecided);
  }
}

// A sphere's triangles (chordal tolerance `tolerance`) with coordinates rounded to float, as
// binary STL stores them.
Body float_triangle_sphere(double tolerance) {
  const Body s = sphere({0.1, 0.2, 0.3}, 1, tolerance);
  std::vector<Vec3> v;
  for (const Vec3& p : s.vertices())
    v.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  std::vector<Face> f;
  for (const Triangle& t : s.triangles()) f.push_back(Face{t.v[0], t.v[1], t.v[2]});
  return Body(v, f);
}

TEST(IsConvex, FloatRoundedTriangleSphereListsTheSameFacesAsTheDefinition) {
  // A sphere's triangles with coordinates rounded to float (as binary STL stores them): many
  // diagonals of the former quadrilaterals become slightly reflex, so the body is not convex,
  // and the non-convex faces come from the hull-based listing.
  const Body rounded = float_triangle_sphere(2e-3);
  expect_matches_oracle(rounded, "float sphere");
  EXPECT_FALSE(convexity(rounded).nonconvex_faces.empty());
}

TEST(IsConvex, ThousandsOfFloatRoundedFacesListTheDefinitionsFacesWhateverTheThreads) {
  // Enough faces for several parallel blocks of the hull-based listing.
  const Body rounded = float_triangle_sphere(6e-4);
  ASSERT_GT(rounded.face_count(), 3 * 2048) << rounded.face_count();
#ifndef HEDRA_SANITIZED  // the O(F·V) oracle on 6000 faces: 55 s under ASan + UBSan
  expect_matches_oracle(rounded, "float sphere, thousands of faces");
#endif
  const std::vector<int> all_threads = convexity(rounded).nonconvex_faces;
  std::vector<int> one_thread;
  with_threads(1, [&] { one_thread = convexity(rounded).nonconvex_faces; });
  EXPECT_FALSE(all_threads.empty());
  EXPECT_EQ(all_threads, one_thread);
}

TEST(IsConvex, HullsOfSeveralPartsListTheDefinitionsFaces) {
  // The hull-based listing splits the vertices into slabs with a hull each (in parallel) on
  // large bodies; the list must be the definition's whatever the number of slabs. A float
  // sphere (faces listed through the hulls' neighbours), and a comb, where the vertex outside
  // a face's plane lies in another slab than the face (a climb).
  const Body rounded = float_triangle_sphere(2e-3);
  const std::vector<int> oracle = testing::nonconvex_faces_oracle(rounded);
  ASSERT_FALSE(oracle.empty());
  const Body teeth = comb(12);
  const std::vector<int> teeth_oracle = testing::nonconvex_faces_oracle(teeth);
  ASSERT_FALSE(teeth_oracle.empty());
  for (int parts : {1, 2, 3, 5, 16}) {
    SCOPED_TRACE(parts);
    EXPECT_EQ(internal::nonconvex_faces_in_parts(rounded, parts), oracle);
    EXPECT_EQ(internal::nonconvex_faces_in_parts(teeth, parts), teeth_oracle);
  }
}

TEST(IsConvex, FineSphereIsConvex) {
#ifdef HEDRA_SANITIZED
  Body s = sphere({10, 20, 30}, 2, 2e-4, 1000000);  // about 49 000 faces under ASan + UBSan
#else
  Body s = sphere({10, 20, 30}, 2, 2e-5, 1000000);  // 494 018 faces: above the default budget
#endif
  // So far from the origin that the move rounds: quadrilaterals planar only within rounding.
  ASSERT_FALSE(s.faces_off_plane().empty());
  ASSERT_GT(s.face_count(), 20000);
  // Settled by the certificate (rounded quadrilaterals split), not by the O(F·V) fallback.
  EXPECT_EQ(certify_convexity(s), ConvexityCertificate::Convex);
  EXPECT_EQ(certify_convexity(s.transformed(Transform::rotation({1, 2, 3}, 40))),
            ConvexityCertificate::Convex);
  EXPECT_TRUE(convexity(s).convex);
}

}  // namespace
}  // namespace hedra
