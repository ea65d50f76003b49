// Shadows: analytic cases, exact boundary cases, non-convex casters, several lights, the sun,
// and agreement with independent oracles (ray casting, CGAL's exact union of shadow hulls).
#include "hedra/visibility/shadows.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>
#include <random>

#include "hedra/decompose/decompose.h"
#include "hedra/core/error.h"
#include "hedra/visibility/polygon_union.h"
#include "hedra/core/primitives.h"
#include "testing/decomposition_suite.h"
#include "hedra/mesh/boolean.h"
#include "hedra/mesh/convexity.h"

namespace hedra {
namespace {

// Box faces in course order (docs/algorithms.md §1): x = min, x = max, y = min, y = max,
// z = min, z = max.
constexpr int kXMin = 0, kXMax = 1, kYMin = 2, kYMax = 3, kZMin = 4, kZMax = 5;

Scene ground_scene(double half = 10) {
  Scene s;
  s.add("ground", box({-half, -half, -1}, {half, half, 0}));
  return s;
}

// The face of `body` whose plane is coordinate `axis` = value with outward normal sign `out`.
int face_on(const Body& body, int axis, double value, int out) {
  for (int f = 0; f < body.face_count(); ++f) {
    const Vec3 n = -body.inner_normal(f);
    if (std::abs(std::abs(n[axis]) - 1) > 1e-12 || (n[axis] > 0) != (out > 0)) continue;
    const auto& v =
        body.vertices()[static_cast<size_t>(body.faces()[static_cast<size_t>(f)].loops[0][0])];
    if (v[axis] == value) return f;
  }
  return -1;
}

double total_area(const std::vector<ShadowPolygon>& polys) {
  double a = 0;
  for (const ShadowPolygon& p : polys) a += p.area;
  return a;
}

bool has_vertex(const Polygon3& ring, const Vec3& v, double tol = 1e-14) {
  for (const Vec3& p : ring)
    if ((p - v).norm() <= tol) return true;
  return false;
}

// Independent reference for bodies standing on the ground z = 0 under a directional light:
// each convex body's ground shadow is the 2D convex hull of its vertices projected along the
// light onto z = 0; the ground's shadow is their union clipped to the ground square, computed
// with CGAL's exact Boolean operations.
Ring2 hull(std::vector<Vec2> pts) {
  std::sort(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  Ring2 h(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && orient2d(h[k - 2], h[k - 1], pts[i]) != Sign::Positive) --k;
    h[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && orient2d(h[k - 2], h[k - 1], pts[i]) != Sign::Positive) --k;
    h[k++] = pts[i];
  }
  h.resize(k - 1);
  return h;
}

Ring2 ground_hull(const Body& convex, const Vec3& d) {
  std::vector<Vec2> pts;
  for (const Vec3& p : convex.vertices()) {
    const double t = -p.z() / d.z();
    pts.emplace_back(p.x() + t * d.x(), p.y() + t * d.y());
  }
  return hull(pts);
}

double reference_ground_area(const std::vector<Body>& casters, const Vec3& d, double half) {
  std::vector<Ring2> hulls;
  for (const Body& b : casters) {
    const auto pieces = decompose(b).pieces;
    for (const Body& p : pieces) hulls.push_back(ground_hull(p, d));
  }
  const double big = 1e3;
  const std::vector<Ring2> frame = {{{-big, -big}, {big, -big}, {big, -half}, {-big, -half}},
                                    {{-big, half}, {big, half}, {big, big}, {-big, big}},
                                    {{-big, -half}, {-half, -half}, {-half, half}, {-big, half}},
                                    {{half, -half}, {big, -half}, {big, half}, {half, half}}};
  return cgal_difference(hulls, frame).area;
}

// ---- Analytic cases ----

TEST(Shadows, BoxOnPlaneUnderDirectionalLightCastsTheKnownHexagon) {
  Scene s = ground_scene();
  s.add("box", box({0, 0, 0}, {1, 1, 1}));
  s.lights.push_back(Light::directional({-1, -2, -4}));
  const ShadowResult r = compute_shadows(s);
  ASSERT_EQ(r.lights.size(), 1u);
  // The hull of the base and the top moved by (−1/4, −1/2): area 1 + 1/4 + 1/2.
  const FaceShadow& g = r.face(0, 0, kZMax);
  EXPECT_EQ(g.to_light, Facing::Front);
  EXPECT_NEAR(g.shadow_area, 1.75, 1e-14);
  ASSERT_EQ(g.polygons.size(), 1u);
  const ShadowPolygon& hex = g.polygons[0];
  EXPECT_TRUE(hex.holes.empty());
  ASSERT_EQ(hex.outer.size(), 6u);
  for (const Vec3& v : {Vec3(-0.25, -0.5, 0), Vec3(0.75, -0.5, 0), Vec3(1, 0, 0), Vec3(1, 1, 0),
                        Vec3(0, 1, 0), Vec3(-0.25, 0.5, 0)})
    EXPECT_TRUE(has_vertex(hex.outer, v)) << v.transpose();
  EXPECT_GT(polygon_normal(hex.outer).z(), 0);  // counter-clockwise seen from outside (above)
  // The box: lit faces turned to the light, self-shadowed ones wholly in shadow.
  for (int f : {kXMax, kYMax, kZMax}) {
    EXPECT_EQ(r.face(0, 1, f).to_light, Facing::Front) << f;
    EXPECT_EQ(r.face(0, 1, f).shadow_area, 0) << f;
  }
  for (int f : {kXMin, kYMin, kZMin}) {
    const FaceShadow& fs = r.face(0, 1, f);
    EXPECT_TRUE(fs.self_shadowed()) << f;
    EXPECT_EQ(fs.shadow_area, fs.area) << f;
    EXPECT_EQ(fs.lit_fraction(), 0);
    ASSERT_EQ(fs.polygons.size(), 1u);
    EXPECT_EQ(fs.polygons[0].area, fs.area);
  }
  // The polygon agrees with the exact point test.
  for (const Vec3& p :
       {Vec3(-0.2, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.8, -0.3, 0), Vec3(-0.2, -0.49, 0)}) {
    EXPECT_TRUE(in_shadow(s, s.lights[0], 0, kZMax, p)) << p.transpose();
    EXPECT_TRUE(point_in_polygons(g.polygons, p));
  }
  for (const Vec3& p : {Vec3(1.1, 0.5, 0), Vec3(-0.2, 0.7, 0), Vec3(0.5, -0.6, 0)}) {
    EXPECT_FALSE(in_shadow(s, s.lights[0], 0, kZMax, p)) << p.transpose();
    EXPECT_FALSE(point_in_polygons(g.polygons, p));
  }
  // The boundary is lit.
  EXPECT_FALSE(in_shadow(s, s.lights[0], 0, kZMax, Vec3(1, 0.5, 0)));
}

TEST(Shadows, PointLightAboveASquareCastsAScaledSquare) {
  for (bool spot : {false, true}) {
    Scene s = ground_scene();
    s.add("plate", box({-1, -1, 1.5}, {1, 1, 2}));
    s.lights.push_back(spot ? Light::spot({0, 0, 4}, {0, 0, -1}, 60) : Light::point({0, 0, 4}));
    const ShadowResult r = compute_shadows(s);
    // The top square from the light at height 4 onto z = 0: scaled by 4 / (4 − 2) = 2.
    const FaceShadow& g = r.face(0, 0, kZMax);
    EXPECT_NEAR(g.shadow_area, 16, 1e-13);
    ASSERT_EQ(g.polygons.size(), 1u);
    ASSERT_EQ(g.polygons[0].outer.size(), 4u);
    for (const Vec3& v : {Vec3(-2, -2, 0), Vec3(2, -2, 0), Vec3(2, 2, 0), Vec3(-2, 2, 0)})
      EXPECT_TRUE(has_vertex(g.polygons[0].outer, v));
    // The light is inside the inner half-spaces of the plate's sides: they turn their backs.
    for (int f : {kXMin, kXMax, kYMin, kYMax, kZMin}) EXPECT_TRUE(r.face(0, 1, f).self_shadowed());
    EXPECT_EQ(r.face(0, 1, kZMax).to_light, Facing::Front);
  }
}

TEST(Shadows, SunPositionGivesTheAnalyticShadow) {
  Scene s = ground_scene();
  s.add("box", box({0, 0, 0}, {1, 1, 1}));
  const Light sun = Light::sun(52.52, 13.40, UtcTime::parse("2026-06-21T10:00:00Z"));
  s.lights.push_back(sun);
  const Vec3 d = sunlight_direction(52.52, 13.40, UtcTime::parse("2026-06-21T10:00:00Z"));
  EXPECT_EQ(sun.direction, d);
  const ShadowResult r = compute_shadows(s);
  // Unit cube: the base swept by the top's offset (dx, dy) / (−dz).
  const double expected = 1 + std::abs(d.x() / d.z()) + std::abs(d.y() / d.z());
  EXPECT_NEAR(r.face(0, 0, kZMax).shadow_area, expected, 1e-13 * expected);
}

TEST(Shadows, SunBelowTheHorizonIsRejected) {
  try {
    Light::sun(52.52, 13.40, UtcTime::parse("2026-06-21T22:00:00Z"));
    FAIL() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("below the horizon"), std::string::npos) << e.what();
  }
}

// ---- Exact boundary cases ----

TEST(Shadows, GrazingLightInTheFacePlane) {
  Scene s = ground_scene();
  s.add("box", box({0, 0, 0}, {1, 1, 1}));
  s.add("wall", box({3, 5, 0}, {10, 6, 3}));
  s.add("post", box({0, 4, 0}, {1, 5.5, 1}));
  s.lights.push_back(Light::directional({1, 0, 0}));
  const ShadowResult r = compute_shadows(s);
  // Horizontal light: the ground and every top and bottom are grazed; the boundary of an
  // occlusion volume is lit, so the box standing on the ground casts nothing onto it.
  EXPECT_TRUE(r.face(0, 0, kZMax).grazing());
  EXPECT_EQ(r.face(0, 0, kZMax).shadow_area, 0);
  EXPECT_TRUE(r.face(0, 1, kZMax).grazing());
  EXPECT_TRUE(r.face(0, 1, kYMin).grazing());
  EXPECT_EQ(r.face(0, 1, kXMin).to_light, Facing::Front);
  EXPECT_TRUE(r.face(0, 1, kXMax).self_shadowed());
  // The post straddles the wall's plane y = 5: the grazed wall face gets the post's shadow
  // in its own plane (x ≥ 3, 0 ≤ z ≤ 1: 7 × 1), the wall's end x = 3 the part y ≤ 5.5, z ≤ 1.
  const FaceShadow& wall_side = r.face(0, 2, kYMin);
  EXPECT_TRUE(wall_side.grazing());
  EXPECT_NEAR(wall_side.shadow_area, 7, 1e-14);
  EXPECT_NEAR(r.face(0, 2, kXMin).shadow_area, 0.5, 1e-14);
}

TEST(Shadows, PointLightExactlyAboveAnEdge) {
  Scene s = ground_scene();
  s.add("box", box({0, 0, 0}, {1, 1, 1}));
  s.add("low", box({1, 0, 0}, {2, 1, 0.5}));  // touches the box along its face x = 1
  s.lights.push_back(Light::point({1, 0.5, 3}));
  const ShadowResult r = compute_shadows(s);
  // The light lies in the plane x = 1 of both touching faces: both are grazed.
  EXPECT_TRUE(r.face(0, 1, kXMax).grazing());
  EXPECT_TRUE(r.face(0, 2, kXMin).grazing());
  // The low box's top is not shadowed: rays from it to the light never enter x < 1.
  EXPECT_EQ(r.face(0, 2, kZMax).shadow_area, 0);
  // Ground: the box's top scaled by 3/2 about (1, 0.5): [−0.5, 1] × [−0.25, 1.25], and the low
  // box's top scaled by 6/5: [1, 2.2] × [−0.1, 1.1]; they meet along x = 1 only.
  const FaceShadow& g = r.face(0, 0, kZMax);
  EXPECT_NEAR(g.shadow_area, 2.25 + 1.44, 1e-13);
  ASSERT_EQ(g.polygons.size(), 1u);
  EXPECT_TRUE(g.polygons[0].holes.empty());
  EXPECT_EQ(g.polygons[0].outer.size(), 8u);
  EXPECT_FALSE(in_shadow(s, s.lights[0], 2, kZMax, Vec3(1.5, 0.5, 0.5)));
}

TEST(Shadows, TouchingBodies) {
  Scene s = ground_scene();
  s.add("a", box({0, 0, 0}, {1, 1, 1}));
  s.add("b", box({0, 0, 1}, {1, 1, 2}));  // stacked on a
  s.add("c", box({1, 0, 0}, {2, 1, 1}));  // beside a, sharing the face x = 1
  s.add("d", box({2, 1, 0}, {3, 2, 1}));  // touching c along an edge
  const Vec3 dir(-1, -2, -4);
  s.lights.push_back(Light::directional(dir));
  const ShadowResult r = compute_shadows(s);
  // a's top lies under b: wholly shadowed; b's bottom turns its back.
  EXPECT_NEAR(r.face(0, 1, kZMax).shadow_area, 1, 1e-15);
  EXPECT_TRUE(r.face(0, 2, kZMin).self_shadowed());
  // a's face x = 1 lies against c, which the light (coming from +x) crosses first.
  EXPECT_NEAR(r.face(0, 1, kXMax).shadow_area, 1, 1e-15);
  // c's face x = 1 turns its back; c's top is lit except where the column a+b shades it.
  EXPECT_TRUE(r.face(0, 3, kXMin).self_shadowed());
  std::vector<Body> casters;
  for (const char* n : {"a", "b", "c", "d"}) casters.push_back(s.get(n).body);
  const double ref = reference_ground_area(casters, dir, 10);
  EXPECT_NEAR(r.face(0, 0, kZMax).shadow_area, ref, 1e-12 * ref);
}

// Issue 14, "exact inside": two boxes stacked and rotated, read back from a file (rounded corners,
// faces planar only within rounding), the lower's top face with the very corners of the upper's
// bottom. Each occludes by the convex polyhedron its faces bound, cut into exactly planar faces
// (exactly_planar_convex), not by its faces' support planes an ulp off it. Reference: the stack
// is a convex block, so no face the light reaches receives a cast shadow (exactly 0) but the
// lower's top, wholly under the upper box.
// The stack of `make(0, 1)` and `make(1, 2)` (convex bodies about the axis x = y = 0.5, faces
// numbered `bottom` and `top` under and over each), rotated and read back, under a directional
// and a point light for each of 8 seeded rotations.
template <typename Make>
void expect_stack_shadowed_as_one_block(const Make& make, int bottom, int top) {
  std::mt19937 random(20261207);
  std::uniform_real_distribution<double> u(-1, 1);
  int off_plane = 0;
  for (int turn = 0; turn < 8; ++turn) {
    const Transform t = Transform::rotation(Vec3(u(random), u(random), u(random)), 90 * (u(random) + 1.2),
                                            Vec3(0.5, 0.5, 1));
    const Body lower = make(0, 1).transformed(t);
    const Body upper = make(1, 2).transformed(t);
    Scene s;
    s.add("lower", Body(lower.vertices(), lower.faces()));
    s.add("upper", Body(upper.vertices(), upper.faces()));
    off_plane += static_cast<int>(s.get("lower").body.faces_off_plane().size() + s.get("upper").body.faces_off_plane().size());
    s.lights.push_back(Light::directional(Vec3(u(random), u(random), -1.5)));
    s.lights.push_back(Light::point(Vec3(u(random), u(random), 6)));
    const ShadowResult r = compute_shadows(s);
    for (int l = 0; l < 2; ++l)
      for (int b = 0; b < 2; ++b)
        for (int f = 0; f < lower.face_count(); ++f) {
          const FaceShadow& fs = r.face(l, b, f);
          if (fs.to_light != Facing::Front) continue;
          const bool covered = (b == 0 && f == top) || (b == 1 && f == bottom);
          if (covered)
            EXPECT_NEAR(fs.shadow_area, fs.area, 1e-12) << "turn " << turn << " light " << l;
          else
            EXPECT_EQ(fs.shadow_area, 0) << "turn " << turn << " light " << l << " body " << b << " face " << f;
        }
  }
  EXPECT_GT(off_plane, 0);
}

TEST(Shadows, StackedRotatedBoxesReadBackCastNoShadowOnTheirLitFaces) {
  expect_stack_shadowed_as_one_block([](double z0, double z1) { return box({0, 0, z0}, {1, 1, z1}); }, kZMin, kZMax);
}

// The same for prisms over a regular 12-gon, whose caps are planar only within rounding after
// the turn: each cap occludes and receives as its 10 triangles (convex_polygon_split). Before,
// on its support plane: 20 lit faces received ulp debris (1.4e-32, 1.6e-17, 3.8e-17 among them).
TEST(Shadows, StackedRotatedPrismsReadBackCastNoShadowOnTheirLitFaces) {
  Polygon2 dodecagon;
  for (int i = 0; i < 12; ++i) {
    const double a = 2 * std::numbers::pi * i / 12;
    dodecagon.emplace_back(0.5 + 0.5 * std::cos(a), 0.5 + 0.5 * std::sin(a));
  }
  expect_stack_shadowed_as_one_block([&](double z0, double z1) { return prism(dodecagon, z0, z1); }, 0, 1);
}

// Issue 14, "exact inside": a drilled plate (a Boolean, rounded corners, cut into its exact
// solid's pieces), rotated, lit from above into its hole. A lit wall face next to a wall face
// of another piece received an occlusion volume that only touches it an ulp off its rounded
// corners: shadow areas of 2e-16 … 5.5e-16 with no polygon (faces 7 and 8 under the point light,
// 9 under the sun), which output drops as debris. Such pieces are dropped before the union now
// (kShadowDebris), so every face's area and polygons agree: a face has a shadow area exactly
// when it has a shadow polygon, and the real shadows on the wall keep their areas.
TEST(Shadows, RotatedDrilledPlateHasNoShadowAreaWithoutAPolygon) {
  const Transform move = Transform::rotation({-0.3, 0.9, 0.1}, 23).then(Transform::translation({2, -3, 1}));
  const Body plate = subtract(box({-2, -2, 0}, {2, 2, 1}), cylinder(0.5, -1, 2, 0.01))->transformed(move);
  Scene s;
  s.add("slab", box({-6, -6, -1}, {6, 6, 0}));
  s.add("plate", plate);
  s.lights.push_back(Light::point({3, -2, 10}));
  s.lights.push_back(Light::directional({-1, 0.6, -1.4}));
  const ShadowResult r = compute_shadows(s);
  int walls_shadowed = 0;
  for (int l = 0; l < 2; ++l)
    for (int f = 0; f < plate.face_count(); ++f) {
      const FaceShadow& fs = r.face(l, 1, f);
      EXPECT_EQ(fs.shadow_area > 0, !fs.polygons.empty()) << "light " << l << " face " << f << ": " << fs.shadow_area;
      double polygons = 0;
      for (const ShadowPolygon& p : fs.polygons) polygons += p.area;
      EXPECT_NEAR(fs.shadow_area, polygons, 1e-12) << "light " << l << " face " << f;
      walls_shadowed += f >= 6 && !fs.self_shadowed() && fs.shadow_area > 1e-3;
    }
  EXPECT_GE(walls_shadowed, 3);  // the rim's shadow inside the hole stays
  EXPECT_EQ(r.face(0, 1, 7).shadow_area, 0);
  EXPECT_EQ(r.face(0, 1, 8).shadow_area, 0);
  EXPECT_EQ(r.face(1, 1, 9).shadow_area, 0);
}

// ---- Non-convex casters ----

TEST(Shadows, LPrismShadowsItselfAndTheGround) {
  Scene s = ground_scene();
  const Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2);
  s.add("L", l);
  const Vec3 dir(1, -1, -1);
  s.lights.push_back(Light::directional(dir));
  const ShadowResult r = compute_shadows(s);
  // The inner face y = 1 (x from 1 to 4) is shaded by the arm x < 1: the triangle
  // x ≥ 1, z ≥ 0, x + z ≤ 3 of area 2.
  const int inner = face_on(l, 1, 1, +1);
  ASSERT_GE(inner, 0);
  const FaceShadow& fs = r.face(0, 1, inner);
  EXPECT_EQ(fs.to_light, Facing::Front);
  EXPECT_NEAR(fs.shadow_area, 2, 1e-14);
  ASSERT_EQ(fs.polygons.size(), 1u);
  EXPECT_EQ(fs.polygons[0].outer.size(), 3u);
  // The other inner face x = 1 turns its back to the light.
  EXPECT_TRUE(r.face(0, 1, face_on(l, 0, 1, +1)).self_shadowed());
  // The non-convex bottom is wholly in shadow; the top is lit.
  const int bottom = face_on(l, 2, 0, -1), top = face_on(l, 2, 2, +1);
  EXPECT_EQ(r.face(0, 1, bottom).shadow_area, r.face(0, 1, bottom).area);
  EXPECT_EQ(r.face(0, 1, top).shadow_area, 0);
  // Ground: against the exact union of the pieces' shadow hulls.
  const double ref = reference_ground_area({l}, dir, 10);
  const FaceShadow& g = r.face(0, 0, kZMax);
  EXPECT_NEAR(g.shadow_area, ref, 1e-12 * ref);
  EXPECT_EQ(g.polygons.size(), 1u);
  EXPECT_TRUE(g.polygons[0].holes.empty());
}

TEST(Shadows, RotatedLPrismKeepsItsAreas) {
  // The same configuration turned by 30° about z: rounded coordinates, the same areas.
  const Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2);
  const double a = 30 * std::numbers::pi / 180;
  const Vec3 dir(1, -1, -1);
  const Vec3 turned(dir.x() * std::cos(a) - dir.y() * std::sin(a),
                    dir.x() * std::sin(a) + dir.y() * std::cos(a), dir.z());
  Scene s0 = ground_scene(), s1 = ground_scene();
  s0.add("L", l);
  s1.add("L", l.rotated_z(30));
  s0.lights.push_back(Light::directional(dir));
  s1.lights.push_back(Light::directional(turned));
  const ShadowResult r0 = compute_shadows(s0), r1 = compute_shadows(s1);
  for (int f = 0; f < l.face_count(); ++f)
    EXPECT_NEAR(r1.face(0, 1, f).shadow_area, r0.face(0, 1, f).shadow_area, 1e-12) << f;
  EXPECT_NEAR(r1.face(0, 0, kZMax).shadow_area, r0.face(0, 0, kZMax).shadow_area, 1e-11);
  const double ref = reference_ground_area({s1.get("L").body}, turned, 10);
  EXPECT_NEAR(r1.face(0, 0, kZMax).shadow_area, ref, 1e-12 * ref);
}

TEST(Shadows, AWholeSceneRotatedKeepsItsAreas) {
  // Touching, stacked and non-convex bodies, then the whole scene and the light turned by 37°
  // about x: every coordinate rounded, faces that coincided now coincide only within rounding.
  // Each face's shadow area stays within 1e-9 of its area.
  auto build = [](bool turn) {
    Scene s;
    auto add = [&](const std::string& name, const Body& b) {
      s.add(name, turn ? b.rotated_x(37) : b);
    };
    add("ground", box({-10, -10, -1}, {10, 10, 0}));
    add("a", box({0, 0, 0}, {1, 1, 1}));
    add("b", box({0, 0, 1}, {1, 1, 2}));
    add("c", box({1, 0, 0}, {2, 1, 1}));
    add("L", prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2).translated({-6, -5, 0}));
    add("plate", prism({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 1, 1.5, {{{1, 1}, {3, 1}, {3, 3}, {1, 3}}})
                     .translated({3, 3, 0}));
    const Vec3 d(-1, -0.7, -2);
    const double a = 37 * std::numbers::pi / 180;
    s.lights.push_back(
        Light::directional(turn ? Vec3(d.x(), d.y() * std::cos(a) - d.z() * std::sin(a),
                                       d.y() * std::sin(a) + d.z() * std::cos(a))
                                : d));
    return s;
  };
  const Scene s0 = build(false), s1 = build(true);
  const ShadowResult r0 = compute_shadows(s0), r1 = compute_shadows(s1);
  ASSERT_EQ(r0.lights[0].faces.size(), r1.lights[0].faces.size());
  for (size_t i = 0; i < r0.lights[0].faces.size(); ++i) {
    const FaceShadow &f0 = r0.lights[0].faces[i], &f1 = r1.lights[0].faces[i];
    EXPECT_EQ(f0.to_light, f1.to_light) << f0.body << " " << f0.face;
    EXPECT_NEAR(f0.shadow_area, f1.shadow_area, 1e-9 * f0.area) << f0.body << " " << f0.face;
  }
}

TEST(Shadows, LightThroughTheHoleOfAPlate) {
  Scene s = ground_scene();
  s.add("plate",
        prism({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 1, 1.5, {{{1, 1}, {3, 1}, {3, 3}, {1, 3}}}));
  s.lights.push_back(Light::directional({-1, 0, -2}));
  const ShadowResult r = compute_shadows(s);
  // Outer: x from −0.75 to 3.5, y from 0 to 4 (17). Lit through the hole: the points whose rays
  // stay inside it at both heights, x + z/2 in [1, 3] for z = 1 and 1.5: x from 0.5 to 2.25,
  // y from 1 to 3 (3.5).
  const FaceShadow& g = r.face(0, 0, kZMax);
  EXPECT_NEAR(g.shadow_area, 13.5, 1e-13);
  ASSERT_EQ(g.polygons.size(), 1u);
  ASSERT_EQ(g.polygons[0].holes.size(), 1u);
  EXPECT_NEAR(g.polygons[0].area, 13.5, 1e-13);
  EXPECT_EQ(g.polygons[0].outer.size(), 4u);
  EXPECT_EQ(g.polygons[0].holes[0].size(), 4u);
  EXPECT_FALSE(point_in_polygons(g.polygons, Vec3(1.25, 2, 0)));
  EXPECT_TRUE(point_in_polygons(g.polygons, Vec3(0.25, 2, 0)));
  EXPECT_TRUE(point_in_polygons(g.polygons, Vec3(2.5, 2, 0)));
  EXPECT_FALSE(in_shadow(s, s.lights[0], 0, kZMax, Vec3(1.25, 2, 0)));
  EXPECT_TRUE(in_shadow(s, s.lights[0], 0, kZMax, Vec3(2.5, 2, 0)));
  EXPECT_FALSE(in_shadow(s, s.lights[0], 0, kZMax, Vec3(0.5, 2, 0)));  // the hole's edge: lit
  // The vertical light passes the hole unchanged.
  s.lights = {Light::directional({0, 0, -1})};
  EXPECT_NEAR(compute_shadows(s).face(0, 0, kZMax).shadow_area, 12, 1e-13);
}

TEST(Shadows, ShadowOnAFaceWithAHole) {
  // A wall north of a plate with a hole: the top face (with its hole) receives the shadow
  // y ≥ 4 − (2.5 − 0.5) = 2 under the light (0, −1, −1): 4 × 2 less the hole's 2 × 1.
  Scene s = ground_scene();
  const Body plate =
      prism({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, 0.5, {{{1, 1}, {3, 1}, {3, 3}, {1, 3}}});
  s.add("plate", plate);
  s.add("wall", box({-1, 4, 0}, {5, 5, 2.5}));
  s.lights.push_back(Light::directional({0, -1, -1}));
  const ShadowResult r = compute_shadows(s);
  const int top = face_on(plate, 2, 0.5, +1);
  ASSERT_GE(top, 0);
  const FaceShadow& fs = r.face(0, 1, top);
  EXPECT_NEAR(fs.shadow_area, 6, 1e-14);
  ASSERT_EQ(fs.polygons.size(), 1u);
  EXPECT_TRUE(point_in_polygons(fs.polygons, {0.5, 2.5, 0.5}));
  EXPECT_FALSE(point_in_polygons(fs.polygons, {2, 2.5, 0.5}));  // in the hole
  EXPECT_FALSE(point_in_polygons(fs.polygons, {2, 1.5, 0.5}));  // south of the shadow
  // A taller wall shades the whole top: the face itself, hole included.
  s = ground_scene();
  s.add("plate", plate);
  s.add("wall", box({-1, 4, 0}, {5, 5, 10}));
  s.lights.push_back(Light::directional({0, -1, -1}));
  const ShadowResult walled = compute_shadows(s);  // keep the result alive: face() returns a reference
  const FaceShadow& all = walled.face(0, 1, top);
  EXPECT_NEAR(all.shadow_area, 12, 1e-13);
  ASSERT_EQ(all.polygons.size(), 1u);
  EXPECT_EQ(all.polygons[0].holes.size(), 1u);
}

// ---- Several lights ----

TEST(Shadows, TwoLightsGiveUmbraAndPartialShadow) {
  Scene s = ground_scene();
  s.add("box", box({0, 0, 0}, {1, 1, 1}));
  s.lights.push_back(Light::directional({-1, 0, -1}));
  s.lights.push_back(Light::directional({1, 0, -1}));
  const ShadowResult r = compute_shadows(s);
  EXPECT_NEAR(r.face(0, 0, kZMax).shadow_area, 2, 1e-14);
  EXPECT_NEAR(r.face(1, 0, kZMax).shadow_area, 2, 1e-14);
  double umbra = -1, partial = -1;
  for (const ShadowCount& c : r.counts) {
    if (c.body != 0 || c.face != kZMax) continue;
    (c.count == 2 ? umbra : partial) = c.area;
    EXPECT_NEAR(total_area(c.polygons), c.area, 1e-13);
  }
  EXPECT_NEAR(umbra, 1, 1e-14);    // the footprint
  EXPECT_NEAR(partial, 2, 1e-14);  // a strip on each side
  // The box's face x = 0 turns its back to the first light only: partial.
  for (const ShadowCount& c : r.counts)
    if (c.body == 1 && c.face == kXMin) {
      EXPECT_EQ(c.count, 1);
      EXPECT_NEAR(c.area, 1, 1e-15);
    }
}

// ---- Visible shadows ----

TEST(Shadows, VisiblePartsExcludeWhatTheViewerCannotSee) {
  Scene s = ground_scene();
  s.add("box", box({0, 0, 0}, {1, 1, 1}));
  s.lights.push_back(Light::directional({-1, -2, -4}));
  s.camera = Camera::parallel({0, 0, -1}, {0, 1, 0});  // from straight above
  ShadowOptions o;
  o.visible_parts = true;
  const ShadowResult r = compute_shadows(s, o);
  const FaceShadow& g = r.face(0, 0, kZMax);
  EXPECT_TRUE(g.visible);
  // The footprint is under the box: 1.75 − 1 is seen.
  EXPECT_NEAR(g.visible_shadow_area, 0.75, 1e-14);
  EXPECT_NEAR(total_area(g.visible_polygons), 0.75, 1e-14);
  // The box's self-shadowed sides are edge-on to this viewer: not visible.
  EXPECT_FALSE(r.face(0, 1, kXMin).visible);
  EXPECT_EQ(r.face(0, 1, kXMin).visible_shadow_area, 0);
  // From the side the self-shadowed face x = 0 is a visible shadow.
  s.camera = Camera::parallel({1, 0.1, -0.2});
  const ShadowResult side = compute_shadows(s, o);
  EXPECT_TRUE(side.face(0, 1, kXMin).visible);
  EXPECT_TRUE(side.face(0, 1, kXMin).self_shadowed());
  EXPECT_NEAR(side.face(0, 1, kXMin).visible_shadow_area, 1, 1e-14);
}

// ---- Oracles on random scenes ----

// Does the open box (rotated about z by `deg` around `c`) meet the segment from p towards
// the light (a ray for a direction)? Slab test in the box's frame, in double.
struct Caster {
  Vec3 lo, hi, c;
  double deg;
};

bool blocks(const Caster& k, const Vec3& p, const Light& light) {
  const double a = -k.deg * std::numbers::pi / 180;
  auto local = [&](const Vec3& q) {
    const Vec3 r = q - k.c;
    return Vec3(k.c.x() + r.x() * std::cos(a) - r.y() * std::sin(a),
                k.c.y() + r.x() * std::sin(a) + r.y() * std::cos(a), q.z());
  };
  const Vec3 from = local(p);
  const Vec3 to = light.at_infinity() ? local(p - 1e4 * light.direction) : local(light.position);
  double t0 = 1e-12, t1 = 1;
  for (int i = 0; i < 3; ++i) {
    const double d = to[i] - from[i];
    if (d == 0) {
      if (from[i] <= k.lo[i] || from[i] >= k.hi[i]) return false;
      continue;
    }
    double u = (k.lo[i] - from[i]) / d, v = (k.hi[i] - from[i]) / d;
    if (u > v) std::swap(u, v);
    t0 = std::max(t0, u);
    t1 = std::min(t1, v);
  }
  return t0 < t1;
}

double distance_to_boundary(const std::vector<ShadowPolygon>& polys, const Vec3& p) {
  double best = 1e300;
  auto ring = [&](const Polygon3& r) {
    for (size_t i = 0; i < r.size(); ++i) {
      const Vec3 a = r[i], b = r[(i + 1) % r.size()];
      const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      best = std::min(best, (a + t * (b - a) - p).norm());
    }
  };
  for (const ShadowPolygon& q : polys) {
    ring(q.outer);
    for (const Polygon3& h : q.holes) ring(h);
  }
  return best;
}

TEST(Shadows, AgreeWithRayCastingOnRandomScenes) {
  std::mt19937 rng(20240607);
  std::uniform_real_distribution<double> u(0, 1);
  int compared = 0, disagreements = 0;
  for (int scene_no = 0; scene_no < 12; ++scene_no) {
    Scene s = ground_scene();
    std::vector<Caster> casters;
    for (int k = 0; k < 6; ++k) {
      const Vec3 lo(-6 + 10 * u(rng), -6 + 10 * u(rng), u(rng) < 0.3 ? 1 + u(rng) : 0);
      const Vec3 hi = lo + Vec3(0.5 + 2 * u(rng), 0.5 + 2 * u(rng), 0.5 + 3 * u(rng));
      const double deg = u(rng) < 0.5 ? 0 : 90 * u(rng);
      const Vec3 c = 0.5 * (lo + hi);
      Body b = box(lo, hi);
      if (deg != 0) b = b.rotated_z(deg, c);
      // Skip overlapping casters (the oracle treats each box on its own; overlaps are fine for
      // hedra but make the test's choice of sample faces ambiguous).
      bool overlap = false;
      for (const SceneBody* o : s.visible_bodies())
        if (o->name != "ground" && o->body.bbox().intersects(b.bbox())) overlap = true;
      if (overlap) continue;
      s.add("b" + std::to_string(k), b);
      casters.push_back({lo, hi, c, deg});
    }
    Light light = scene_no % 2 == 0
                      ? Light::directional({u(rng) - 0.5, u(rng) - 0.5, -0.3 - u(rng)})
                      : Light::point({-4 + 8 * u(rng), -4 + 8 * u(rng), 7 + 5 * u(rng)});
    s.lights.push_back(light);
    const ShadowResult r = compute_shadows(s);
    // Sample the ground's top and every lit face of every caster.
    for (size_t b = 0; b < s.bodies().size(); ++b) {
      const Body& body = s.bodies()[b].body;
      for (int f = 0; f < body.face_count(); ++f) {
        const FaceShadow& fs = r.face(0, static_cast<int>(b), f);
        if (fs.to_light != Facing::Front || (b == 0 && f != kZMax)) continue;
        const auto& loop = body.faces()[static_cast<size_t>(f)].loops[0];
        const Vec3 o = body.vertices()[static_cast<size_t>(loop[0])];
        const Vec3 e1 = body.vertices()[static_cast<size_t>(loop[1])] - o;
        const Vec3 e2 = body.vertices()[static_cast<size_t>(loop[3])] - o;
        for (int k = 0; k < (b == 0 ? 400 : 40); ++k) {
          const double a = b == 0 ? 0.2 + 0.6 * u(rng) : u(rng),
                       c = b == 0 ? 0.2 + 0.6 * u(rng) : u(rng);
          const Vec3 p = o + a * e1 + c * e2;
          if (distance_to_boundary(fs.polygons, p) < 1e-7) continue;
          bool ray = false;
          for (size_t k2 = 0; k2 < casters.size(); ++k2)
            if (static_cast<int>(k2) + 1 != static_cast<int>(b) && blocks(casters[k2], p, light))
              ray = true;
          const bool poly = point_in_polygons(fs.polygons, p);
          ++compared;
          if (ray != poly) {
            ++disagreements;
            ADD_FAILURE() << "scene " << scene_no << " body " << b << " face " << f << " at "
                          << p.transpose() << ": ray " << ray << ", polygons " << poly;
          }
          if (k % 10 == 0) {
            EXPECT_EQ(in_shadow(s, light, static_cast<int>(b), f, p), ray);
          }
        }
      }
    }
  }
  EXPECT_GT(compared, 3000);
  EXPECT_EQ(disagreements, 0);
}

TEST(Shadows, GroundAreaMatchesTheExactUnionOfShadowHulls) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 6; ++trial) {
    Scene s = ground_scene();
    std::vector<Body> bodies;
    for (int k = 0; k < 25; ++k) {  // overlapping and rotated boxes, all on the ground
      const Vec3 lo(-9 + 16 * u(rng), -9 + 16 * u(rng), 0);
      Body b = box(lo, lo + Vec3(0.3 + 2 * u(rng), 0.3 + 2 * u(rng), 0.2 + 3 * u(rng)));
      if (k % 3 == 0) b = b.rotated_z(70 * u(rng), lo);
      s.add("b" + std::to_string(k), b);
      bodies.push_back(b);
    }
    const Vec3 d(u(rng) - 0.5, u(rng) - 0.5, -0.4 - u(rng));
    s.lights.push_back(Light::directional(d));
    const ShadowResult r = compute_shadows(s);
    const FaceShadow& g = r.face(0, 0, kZMax);
    const double ref = reference_ground_area(bodies, d, 10);
    EXPECT_NEAR(g.shadow_area, ref, 1e-11 * ref) << trial;
    EXPECT_NEAR(total_area(g.polygons), g.shadow_area, 1e-11 * ref);
  }
}

TEST(Shadows, ResultsDoNotDependOnThreads) {
  Scene s = ground_scene();
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      s.add("b" + std::to_string(i) + std::to_string(j),
            box({-8.0 + 3 * i, -8.0 + 3 * j, 0},
                {-6.5 + 3 * i, -6.5 + 3 * j, 1.0 + (i * 7 + j * 3) % 4}));
  s.lights.push_back(Light::directional({-1, -2, -3}));
  s.lights.push_back(Light::point({0, 0, 12}));
  ShadowOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const ShadowResult a = compute_shadows(s, one), b = compute_shadows(s, two);
  for (size_t l = 0; l < 2; ++l)
    for (size_t i = 0; i < a.lights[l].faces.size(); ++i)
      EXPECT_EQ(a.lights[l].faces[i].shadow_area, b.lights[l].faces[i].shadow_area);
  ASSERT_EQ(a.counts.size(), b.counts.size());
}

// ---- Sun studies ----

TEST(Shadows, SunStudyOverADay) {
  Scene s = ground_scene();
  s.add("tower", box({0, 0, 0}, {1, 1, 6}));
  SunStudyOptions o;
  o.latitude = 52.52;
  o.longitude = 13.40;
  o.start = UtcTime::parse("2026-06-21T00:00:00Z");
  o.end = UtcTime::parse("2026-06-21T23:50:00Z");
  o.step_minutes = 10;
  o.grid_body = "ground";
  o.grid_face = kZMax;
  o.grid_spacing = 1;
  const SunStudy st = sun_study(s, o);
  ASSERT_EQ(st.steps.size(), 144u);
  EXPECT_FALSE(st.steps.front().sun_up);  // midnight
  double up_hours = 0;
  for (size_t k = 1; k < st.steps.size(); ++k)
    up_hours += 0.5 * (st.steps[k - 1].sun_up + st.steps[k].sun_up) / 6.0;
  // Berlin at midsummer: the sun's centre is up about 16 h 40 min.
  EXPECT_NEAR(up_hours, 16.7, 0.25);
  for (const SunStep& step : st.steps)
    if (!step.sun_up) {
      for (double f : step.lit_fraction) EXPECT_EQ(f, 0);
    }
  // The tower's roof is never shaded: lit whenever the sun is up.
  const int roof = st.first_face[1] + kZMax;
  EXPECT_NEAR(st.sun_hours[static_cast<size_t>(roof)], up_hours, 1e-9);
  // Its north face sees the sun only early and late; the ground loses a little to the tower.
  EXPECT_LT(st.sun_hours[static_cast<size_t>(st.first_face[1] + kYMax)], 0.5 * up_hours);
  const double ground = st.sun_hours[static_cast<size_t>(st.first_face[0] + kZMax)];
  EXPECT_LT(ground, up_hours);
  EXPECT_GT(ground, up_hours - 1);
  // Grid: 20 × 20 points; those just north of the tower lose hours, far ones none.
  ASSERT_EQ(st.grid_points.size(), 400u);
  double least = 1e9, most = 0;
  for (double h : st.grid_hours) {
    least = std::min(least, h);
    most = std::max(most, h);
  }
  EXPECT_NEAR(most, up_hours, 1e-9);
  EXPECT_LT(least, up_hours - 2);
  // Night only: no sun.
  o.start = UtcTime::parse("2026-06-21T21:00:00Z");
  o.end = UtcTime::parse("2026-06-22T01:00:00Z");
  const SunStudy night = sun_study(s, o);
  for (double h : night.sun_hours) EXPECT_EQ(h, 0);
  o.step_minutes = 0;
  EXPECT_THROW(sun_study(s, o), InvalidInput);
}

TEST(Shadows, TimeArithmetic) {
  const UtcTime t = UtcTime::parse("2026-12-31T23:30:00Z");
  const UtcTime u = add_minutes(t, 45);
  EXPECT_EQ(u.to_string().substr(0, 16), "2027-01-01T00:15");
  EXPECT_DOUBLE_EQ(minutes_between(t, u), 45);
  EXPECT_EQ(add_minutes(UtcTime::parse("2028-02-28T12:00:00Z"), 1440).day, 29);
}

// ---- The union engine against CGAL ----

Ring2 square(double x, double y, double s) {
  return {{x, y}, {x + s, y}, {x + s, y + s}, {x, y + s}};
}

TEST(PolygonUnion, DegenerateConfigurations) {
  // Identical squares.
  UnionResult r = unite_convex({square(0, 0, 1), square(0, 0, 1), square(0, 0, 1)}, true);
  EXPECT_EQ(r.area, 1);
  ASSERT_EQ(r.polygons.size(), 1u);
  EXPECT_EQ(r.polygons[0].outer.size(), 4u);
  // Sharing an edge, and an edge partly.
  r = unite_convex({square(0, 0, 1), square(1, 0, 1), square(2, 0.5, 1)}, true);
  EXPECT_EQ(r.area, 3);
  ASSERT_EQ(r.polygons.size(), 1u);
  EXPECT_EQ(r.polygons[0].outer.size(), 8u);
  // Touching at a corner: two polygons.
  r = unite_convex({square(0, 0, 1), square(1, 1, 1)}, true);
  EXPECT_EQ(r.area, 2);
  EXPECT_EQ(r.polygons.size(), 2u);
  // A frame: a polygon with a hole.
  r = unite_convex({{{0, 0}, {4, 0}, {4, 1}, {0, 1}},
                    {{3, 0}, {4, 0}, {4, 4}, {3, 4}},
                    {{0, 3}, {4, 3}, {4, 4}, {0, 4}},
                    {{0, 0}, {1, 0}, {1, 4}, {0, 4}}},
                   true);
  EXPECT_EQ(r.area, 12);
  ASSERT_EQ(r.polygons.size(), 1u);
  ASSERT_EQ(r.polygons[0].holes.size(), 1u);
  EXPECT_EQ(r.polygons[0].area, 12);
  // A checkerboard: squares meeting only at corners.
  std::vector<Ring2> board;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      if ((i + j) % 2 == 0) board.push_back(square(i, j, 1));
  r = unite_convex(board, true);
  EXPECT_EQ(r.area, 18);
  double sum = 0;
  for (const auto& p : r.polygons) sum += p.area;
  EXPECT_EQ(sum, 18);
  // A square inside another, a triangle with a vertex on another's edge.
  r = unite_convex({square(0, 0, 4), square(1, 1, 1), {{4, 2}, {6, 1}, {6, 3}}}, true);
  EXPECT_EQ(r.area, 18);
  EXPECT_EQ(r.polygons.size(), 2u);
}

bool inside_ring(const Ring2& r, const Vec2& q) {
  bool in = false;
  for (size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
    if ((r[i].y() > q.y()) != (r[j].y() > q.y()) &&
        q.x() < (r[j].x() - r[i].x()) * (q.y() - r[i].y()) / (r[j].y() - r[i].y()) + r[i].x())
      in = !in;
  return in;
}

bool inside(const std::vector<PolygonWithHoles2>& polys, const Vec2& q) {
  for (const auto& p : polys) {
    if (!inside_ring(p.outer, q)) continue;
    bool hole = false;
    for (const Ring2& h : p.holes) hole = hole || inside_ring(h, q);
    if (!hole) return true;
  }
  return false;
}

bool near_boundary(const std::vector<PolygonWithHoles2>& polys, const Vec2& q, double eps) {
  auto ring = [&](const Ring2& r) {
    for (size_t i = 0; i < r.size(); ++i) {
      const Vec2 a = r[i], b = r[(i + 1) % r.size()];
      const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      if ((a + t * (b - a) - q).norm() < eps) return true;
    }
    return false;
  };
  for (const auto& p : polys) {
    if (ring(p.outer)) return true;
    for (const Ring2& h : p.holes)
      if (ring(h)) return true;
  }
  return false;
}

TEST(PolygonUnion, RandomConvexPolygonsAgreeWithCgal) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(0, 1);
  int chained = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Ring2> pieces;
    const int m = 2 + trial * 3;
    for (int k = 0; k < m; ++k) {
      const Vec2 c(10 * u(rng), 10 * u(rng));
      std::vector<Vec2> pts;
      for (int q = 0; q < 7; ++q) pts.push_back(c + Vec2(3 * u(rng) - 1.5, 3 * u(rng) - 1.5));
      // Some pieces snapped to a coarse grid: shared edges and vertices on edges.
      if (trial % 2)
        for (Vec2& p : pts) p = (p * 2).array().round() / 2;
      Ring2 h = hull(pts);
      if (h.size() >= 3 && ring_area(h) > 0) pieces.push_back(h);
    }
    const UnionResult mine = unite_convex(pieces, true);
    const UnionResult ref = cgal_union(pieces, true);
    EXPECT_NEAR(mine.area, ref.area, 1e-12 * ref.area) << trial;
    double sum = 0;
    for (const auto& p : mine.polygons) sum += p.area;
    EXPECT_NEAR(sum, ref.area, 1e-12 * ref.area) << trial;
    // The same region (polygons touching at a vertex may be grouped differently): compare
    // membership of sample points away from the boundary.
    for (int k = 0; k < 300; ++k) {
      const Vec2 q(-2 + 14 * u(rng), -2 + 14 * u(rng));
      if (near_boundary(ref.polygons, q, 1e-9)) continue;
      EXPECT_EQ(inside(mine.polygons, q), inside(ref.polygons, q)) << trial << " " << q.transpose();
    }
    chained += mine.chained;
  }
  EXPECT_EQ(chained, 40);
}

// Long thin pieces across the whole grid, crossing each other at shallow angles (the shadows
// of a star's spikes under a low light): the grid lists each in the cells its polygon meets,
// not every cell of its box, and must still find every pair that meets.
TEST(PolygonUnion, LongThinCrossingPiecesAgreeWithCgal) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
#ifdef HEDRA_SANITIZED
  const int trials = 2;  // CGAL's exact unions under ASan + UBSan: 28 s for all six
#else
  const int trials = 6;
#endif
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<Ring2> pieces;
    for (int k = 0; k < 40 + 20 * trial; ++k) {
      // A chord of a circle of radius 20 (chords cross all over the grid), 0.02 to 0.4 wide.
      const double a = 2 * std::numbers::pi * u(rng), b = a + 0.3 + 2 * u(rng), w = 0.01 + 0.2 * u(rng);
      const Vec2 c(20 * std::cos(a), 20 * std::sin(a)), e(20 * std::cos(b), 20 * std::sin(b));
      const double len = (e - c).norm();
      const Vec2 d = (e - c) / len, n(-d.y(), d.x());
      Ring2 r{c - w * n, c + len * d, c + w * n};
      if (trial % 2) r = {c - w * n, c + len * d - w * n, c + len * d + w * n, c + w * n};
      pieces.push_back(r);
    }
    const UnionResult mine = unite_convex(pieces, true);
    const UnionResult ref = cgal_union(pieces, true);
    EXPECT_TRUE(mine.chained) << trial;  // else the polygons would be CGAL's own
    EXPECT_NEAR(mine.area, ref.area, 1e-12 * ref.area) << trial;
    for (int k = 0; k < 2000; ++k) {
      const Vec2 q(-25 + 50 * u(rng), -25 + 50 * u(rng));
      if (near_boundary(ref.polygons, q, 1e-9)) continue;
      EXPECT_EQ(inside(mine.polygons, q), inside(ref.polygons, q)) << trial << " " << q.transpose();
    }
  }
}

}  // namespace
}  // namespace hedra

namespace hedra {
namespace {

// A sphere whose quads are split into triangles along a diagonal: quads planar only within
// rounding make some diagonals reflex by an ulp, so the mesh is exactly non-convex (as every
// float export of a sphere), and with more than kFaceOccluderFaces faces it occludes by its
// faces (Occluders::Auto), with no decomposition.
Body triangulated(const Body& body) {
  std::vector<Face> faces;
  for (const Triangle& t : body.triangles()) faces.emplace_back(std::vector<int>{t.v[0], t.v[1], t.v[2]});
  return Body(body.vertices(), std::move(faces));
}

TEST(Shadows, TriangulatedSphereCastsTheShadowOfItsConvexTwin) {
  // Rotated and rounded: the triangles of a quadrilateral fold by ulps (a sphere's own
  // quadrilaterals are exactly planar).
  const Body ball = sphere({0, 0, 2}, 1.5, 1e-3).transformed(Transform::rotation({1, 2, 3}, 37, {0, 0, 2}));
  const Body mesh = triangulated(ball);
  ASSERT_GT(mesh.face_count(), kFaceOccluderFaces);
  ASSERT_FALSE(is_convex(mesh));
  for (const Light& light : {Light::point({6, 4, 10}), Light::directional({-1, -0.5, -2})}) {
    double area[2];
    int k = 0;
    for (const Body& b : {ball, mesh}) {
      Scene scene;
      scene.add("ground", box({-10, -10, -1}, {10, 10, 0}));
      scene.add("ball", b);
      scene.lights.push_back(light);
      const ShadowResult r = compute_shadows(scene);
      const FaceShadow& top = r.face(0, 0, 5);  // z = 0
      EXPECT_GT(top.shadow_area, 1);
      ASSERT_FALSE(top.polygons.empty());
      double polygons = 0;
      for (const ShadowPolygon& p : top.polygons) polygons += p.area;
      EXPECT_NEAR(polygons, top.shadow_area, 1e-9 * top.shadow_area);
      area[k++] = top.shadow_area;
    }
    // The same surface up to the rounding of its vertices.
    EXPECT_NEAR(area[1], area[0], 1e-9 * area[0]);
  }
}

// Regression (stability.md, "exact shadow polygons"): the union of a face's shadow pieces,
// each clipped by rounded planes, chained crossings that are one point in exact arithmetic but
// came out a few ulps apart (rings with vertices 1e-16 … 5e-15 apart, in 155 of 947 polygons of
// 20 random scenes), spikes (slits of no width between pieces whose edges are an ulp apart: 15
// of 1062 rings) and rings of no width (area 1e-16) where an occlusion volume only touches a
// face. Output polygons now drop that debris (kShadowDebris): every ring has distinct vertices,
// no spike and a width far above rounding, and the polygons' areas still sum to the face's
// shadow area.
// Issue 14, "exact inside": shadows of a moved body whose guarded run multiplies its cuts (a
// rotated star prism of 64 points) and of a Boolean that rounds its corners (a plate drilled
// after both operands were rotated) come from the pieces of their exact solids (Decomposition::
// from_exact_solid), with the bodies' faces on the solids' planes by construction. Reference:
// the aligned twin under the correspondingly rotated light casts the same areas, face by face
// (the star, the ground) and in all (the plate, whose Boolean numbers its faces its own way).
TEST(Shadows, MovedAndBooleanBodiesShadowWithTheirExactSolidsPieces) {
  const Transform turn = Transform::rotation({1, 2, 3}, 37);
  const Body ground = box({-6, -6, -1}, {6, 6, 0});
  const Body star = prism(suite::star(64, 1, 0.5), 0, 1).translated({-3, 0, 0});
  const Body slab = box({0.5, -2, 0}, {4.5, 2, 1});
  const Body drill = cylinder(0.5, -1, 2, 0.01).translated({2.5, 0, 0});
  const auto build = [&](bool turned) {
    Scene s;
    const auto move = [&](const Body& b) { return turned ? b.transformed(turn) : b; };
    s.add("ground", move(ground));
    s.add("star", move(star));
    s.add("plate", *subtract(move(slab), move(drill)));
    const Vec3 d(-1, -0.7, -2);
    s.lights.push_back(Light::directional(turned ? turn.apply_vector(d) : d));
    return s;
  };
  const Scene s0 = build(false), s1 = build(true);
  DecomposeOptions exact;
  exact.exact_pieces = true;
  EXPECT_TRUE(decompose(s1.get("star").body, exact).from_exact_solid);
  EXPECT_TRUE(decompose(s1.get("plate").body, exact).from_exact_solid);
  const ShadowResult r0 = compute_shadows(s0), r1 = compute_shadows(s1);
  ASSERT_EQ(r0.lights[0].faces.size(), r1.lights[0].faces.size());
  double plate0 = 0, plate1 = 0, plate_area = 0;
  for (size_t i = 0; i < r0.lights[0].faces.size(); ++i) {
    const FaceShadow &f0 = r0.lights[0].faces[i], &f1 = r1.lights[0].faces[i];
    if (f0.body == 2) {
      plate0 += f0.shadow_area;
      plate1 += f1.shadow_area;
      plate_area += f0.area;
      continue;
    }
    EXPECT_EQ(f0.to_light, f1.to_light) << f0.body << " " << f0.face;
    EXPECT_NEAR(f0.shadow_area, f1.shadow_area, 1e-9 * f0.area) << f0.body << " " << f0.face;
  }
  EXPECT_GT(r0.face(0, 0, kZMax).shadow_area, 1);  // the star and the plate shade the ground
  EXPECT_GT(plate0, 1);                             // the hole's wall shades itself
  EXPECT_NEAR(plate1, plate0, 1e-9 * plate_area);
}

TEST(Shadows, RotatedNonConvexBodiesGiveShadowPolygonsWithoutRoundingDebris) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2);
  const Body plate = prism({{0, 0}, {5, 0}, {5, 3}, {0, 3}}, 0, 0.5,
                           {{{1, 1}, {1, 2}, {2, 2}, {2, 1}}, {{3, 1}, {3, 2}, {4, 2}, {4, 1}}});
  const auto ring_area3 = [](const Polygon3& r) {
    Vec3 c = Vec3::Zero();
    for (size_t k = 0; k < r.size(); ++k) c += (r[k] - r[0]).cross(r[(k + 1) % r.size()] - r[0]);
    return c.norm() / 2;
  };
  int polygons = 0;
  for (int it = 0; it < 12; ++it) {
    Scene s;
    s.add("ground", box({-10, -10, -1}, {10, 10, 0}));
    const auto turn = [&](const Body& b) {
      const Vec3 axis(u(rng), u(rng), u(rng) + 1e-3);
      return b.transformed(Transform::rotation(axis, 180 * (u(rng) + 1), {2, 1.5, 0.5}));
    };
    s.add("L", turn(l).translated({-4, -3, 1}));
    s.add("plate", turn(plate).translated({1, 0, 1.5}));
    s.lights.push_back(Light::directional({0.5 * u(rng), 0.5 * u(rng), -1}));
    s.lights.push_back(Light::point({3 * u(rng), 3 * u(rng), 9}));
    s.camera = Camera::parallel({-1, -1, -1});
    ShadowOptions options;
    options.visible_parts = true;
    const ShadowResult r = compute_shadows(s, options);
    for (const LightShadows& ls : r.lights)
      for (const FaceShadow& f : ls.faces) {
        double sum = 0;
        for (const ShadowPolygon& p : f.polygons) {
          ++polygons;
          std::vector<const Polygon3*> rings{&p.outer};
          for (const Polygon3& h : p.holes) rings.push_back(&h);
          for (const Polygon3* ring : rings) {
            ASSERT_GE(ring->size(), 3u);
            double shortest = std::numeric_limits<double>::infinity(), perimeter = 0;
            for (size_t k = 0; k < ring->size(); ++k) {
              const double e = ((*ring)[(k + 1) % ring->size()] - (*ring)[k]).norm();
              shortest = std::min(shortest, e);
              perimeter += e;
            }
            EXPECT_GT(shortest, 1e-10) << "scene " << it << " body " << f.body << " face " << f.face;
            for (size_t k = 0; k < ring->size(); ++k) {  // no spike: out and back along a line
              const Vec3 a = (*ring)[k] - (*ring)[(k + ring->size() - 1) % ring->size()];
              const Vec3 b = (*ring)[(k + 1) % ring->size()] - (*ring)[k];
              EXPECT_FALSE(a.dot(b) < 0 && a.cross(b).norm() <= 1e-9 * a.norm() * b.norm())
                  << "spike, scene " << it << " body " << f.body << " face " << f.face;
            }
            EXPECT_GT(2 * ring_area3(*ring) / perimeter, 1e-10)
                << "scene " << it << " body " << f.body << " face " << f.face;
          }
          sum += ring_area3(p.outer);
          for (const Polygon3& h : p.holes) sum -= ring_area3(h);
        }
        EXPECT_NEAR(sum, f.shadow_area, 1e-9 * std::max(1.0, f.area))
            << "scene " << it << " body " << f.body << " face " << f.face;
        for (const ShadowPolygon& p : f.visible_polygons) {
          double shortest = std::numeric_limits<double>::infinity();
          for (size_t k = 0; k < p.outer.size(); ++k)
            shortest = std::min(shortest, (p.outer[(k + 1) % p.outer.size()] - p.outer[k]).norm());
          EXPECT_GT(shortest, 1e-10) << "visible, scene " << it << " face " << f.face;
        }
      }
  }
  EXPECT_GT(polygons, 300);
}

}  // namespace
}  // namespace hedra
