#include "hedra/mesh/boolean.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "hedra/mesh/convexity.h"
#include "hedra/decompose/decompose.h"
#include "hedra/core/error.h"
#include "hedra/core/primitives.h"

namespace hedra {
namespace {

Body cross(double a, double length) {
  const double h = a / 2, l = length / 2;
  Body x = box({-l, -h, -h}, {l, h, h});
  Body y = box({-h, -l, -h}, {h, l, h});
  Body z = box({-h, -h, -l}, {h, h, l});
  return unite(unite(x, y), z);
}

TEST(Boolean, CrossOfThreeBoxes) {
  Body c = cross(2, 6);
  EXPECT_EQ(c.volume(), 3 * 4 * 6 - 2 * 8);  // 3a²L − 2a³
  EXPECT_EQ(c.face_count(), 30);             // 6 arm ends + 24 arm sides
  EXPECT_FALSE(convexity(c).convex);
  EXPECT_EQ(c.classify({0, 0, 0}), Location::Inside);
  EXPECT_EQ(c.classify({2, 2, 0}), Location::Outside);
}

TEST(Boolean, PlateWithFiveByFiveHoles) {
  Body plate = box({0, 0, 0}, {11, 11, 1});
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      plate = *subtract(plate, box({1.0 + 2 * i, 1.0 + 2 * j, -1}, {2.0 + 2 * i, 2.0 + 2 * j, 2}));
  EXPECT_EQ(plate.volume(), 121 - 25);
  EXPECT_EQ(plate.face_count(), 2 + 4 + 25 * 4);
  int holes = 0;
  for (const Face& f : plate.faces()) holes += static_cast<int>(f.loops.size()) - 1;
  EXPECT_EQ(holes, 50);  // the top and the bottom each have 25
  EXPECT_EQ(plate.area(), 2 * (121 - 25) + 4 * 11 + 25 * 4);
}

TEST(Boolean, BoxMinusBoxSharingFaces) {
  Body a = box({0, 0, 0}, {2, 2, 2});
  std::optional<Body> half = subtract(a, box({1, 0, 0}, {2, 2, 2}));  // shares 5 face planes
  ASSERT_TRUE(half);
  EXPECT_EQ(half->volume(), 4);
  EXPECT_EQ(half->face_count(), 6);
  EXPECT_EQ(half->vertex_count(), 8);
  std::optional<Body> notch = subtract(a, box({0, 0, 0}, {1, 1, 1}));  // a corner cube
  ASSERT_TRUE(notch);
  EXPECT_EQ(notch->volume(), 7);
  EXPECT_EQ(notch->face_count(), 9);
  EXPECT_FALSE(subtract(a, box({-1, -1, -1}, {3, 3, 3})));  // nothing left
}

TEST(Boolean, TouchingBodies) {
  Body a = box({0, 0, 0}, {1, 1, 1});
  Body face_neighbour = box({1, 0, 0}, {2, 1, 1});
  Body u = unite(a, face_neighbour);
  EXPECT_EQ(u.volume(), 2);
  EXPECT_EQ(u.face_count(), 6);  // the shared face disappears, coplanar sides merge
  EXPECT_FALSE(intersect(a, face_neighbour));
  Body edge_neighbour = box({1, 1, 0}, {2, 2, 1});
  EXPECT_FALSE(intersect(a, edge_neighbour));
  std::optional<Body> same = subtract(a, edge_neighbour);
  ASSERT_TRUE(same);
  EXPECT_EQ(same->volume(), 1);
  EXPECT_EQ(same->face_count(), 6);
  EXPECT_THROW(unite(a, edge_neighbour), InvalidInput);  // not a manifold solid
}

TEST(Boolean, ConvexIntersectionByPlaneSetsEqualsBoolean) {
  Body a = box({0, 0, 0}, {4, 4, 4}).rotated_z(20, {2, 2, 0});
  Body b = pyramid({{1, 1}, {6, 1}, {6, 6}, {1, 6}}, -1, {3, 3, 7});
  std::optional<Body> by_planes = intersect_convex(a, b);
  std::optional<Body> by_boolean = intersect(a, b);
  ASSERT_TRUE(by_planes && by_boolean);
  EXPECT_NEAR(by_planes->volume(), by_boolean->volume(), 1e-12 * by_boolean->volume());
  EXPECT_EQ(by_planes->face_count(), by_boolean->face_count());
  EXPECT_EQ(by_planes->vertex_count(), by_boolean->vertex_count());
  EXPECT_TRUE(convexity(*by_planes).convex);
  // Axis-aligned: exact values.
  std::optional<Body> overlap = intersect_convex(box({0, 0, 0}, {2, 2, 2}), box({1, 1, 1}, {3, 3, 3}));
  ASSERT_TRUE(overlap);
  EXPECT_EQ(overlap->volume(), 1);
  EXPECT_EQ(overlap->face_count(), 6);
  EXPECT_FALSE(intersect_convex(box({0, 0, 0}, {1, 1, 1}), box({2, 0, 0}, {3, 1, 1})));
  EXPECT_FALSE(intersect_convex(box({0, 0, 0}, {1, 1, 1}), box({1, 0, 0}, {2, 1, 1})));  // a face
}

// ---- Curved primitives (issue 14): results are valid bodies, volumes add up exactly ----------

// Area of the regular n-gon of circumradius r that cylinder() inscribes.
double ngon_area(int n, double r) { return 0.5 * n * r * r * std::sin(2 * std::numbers::pi / n); }

// V(A − B) + V(A ∩ B) = V(A): exactly for the exact solids the results keep, and to 1e-9 of
// V(A) for the rounded bodies; both parts must be valid bodies.
void expect_volumes_add_up(const Body& a, const Body& b) {
  std::optional<Body> minus = subtract(a, b);
  std::optional<Body> common = intersect(a, b);
  ASSERT_TRUE(minus && common);
  EXPECT_TRUE(minus->has_exact_solid() && common->has_exact_solid());
  EXPECT_EQ(exact_volume_sign({{1, *minus}, {1, *common}, {-1, a}}), Sign::Zero);
  EXPECT_NEAR(minus->volume() + common->volume(), a.volume(), 1e-9 * a.volume());
}

// The face whose inner normal is (anti)parallel to `axis` and which has the most vertices.
int flat_face(const Body& b, const Vec3& inner) {
  int best = -1;
  for (int f = 0; f < b.face_count(); ++f)
    if (b.inner_normal(f).dot(inner) > 1 - 1e-12) best = f;
  return best;
}

TEST(Boolean, DrilledPlate) {
  const Body plate = box({-2, -2, 0}, {2, 2, 1});
  const Body drill = cylinder(0.5, -1, 2, 0.01);
  const int n = segments_for_tolerance(0.5, 0.01);
  std::optional<Body> drilled = subtract(plate, drill);
  ASSERT_TRUE(drilled);
  EXPECT_NEAR(drilled->volume(), 16 - ngon_area(n, 0.5) * 1, 1e-12 * 16);
  EXPECT_EQ(drilled->face_count(), 6 + n);  // 4 sides, top and bottom with a hole, n walls
  int holes = 0;
  for (const Face& f : drilled->faces()) holes += static_cast<int>(f.loops.size()) - 1;
  EXPECT_EQ(holes, 2);
  EXPECT_EQ(drilled->vertex_count(), 8 + 2 * n);  // no vertex only splitting an edge is left
  EXPECT_EQ(drilled->classify({0, 0, 0.5}), Location::Outside);
  EXPECT_EQ(drilled->classify({1.5, 1.5, 0.5}), Location::Inside);
  expect_volumes_add_up(plate, drill);
  // Exactly the box less the prism over the drill's polygon, one unit high: the part of the
  // drill inside the plate is, exactly, the drill cut to the plate's height.
  const Body plug = cylinder(0.5, 0, 1, 0.01);
  EXPECT_EQ(exact_volume_sign({{1, *drilled}, {1, plug}, {-1, plate}}), Sign::Zero);
  // Touching: the drill ends on the plate's faces.
  std::optional<Body> flush = subtract(plate, cylinder(0.5, 0, 1, 0.01));
  ASSERT_TRUE(flush);
  EXPECT_NEAR(flush->volume(), drilled->volume(), 1e-12 * 16);
}

TEST(Boolean, SphereCutThroughItsCentre) {
  const Body ball = sphere({0, 0, 0}, 1, 0.01);
  const Body upper = box({-2, -2, 0}, {2, 2, 2});
  std::optional<Body> dome = intersect(ball, upper);
  std::optional<Body> lower = subtract(ball, upper);
  ASSERT_TRUE(dome && lower);
  EXPECT_NEAR(dome->volume() + lower->volume(), ball.volume(), 1e-9 * ball.volume());
  // The tessellation is symmetric about the equator: each half has half the volume.
  EXPECT_NEAR(dome->volume(), ball.volume() / 2, 1e-9 * ball.volume());
  // Half a convex polyhedron is convex: the sphere's faces below the equator plus one flat
  // disk, not a thousand triangles.
  for (const Body* half : {&*dome, &*lower}) {
    EXPECT_TRUE(convexity(*half).convex);
    EXPECT_EQ(half->face_count(), ball.face_count() / 2 + 1);
  }
  const int disk = flat_face(*lower, {0, 0, -1});
  ASSERT_GE(disk, 0);
  int rings = 2;
  while (sphere_chordal_error(1, rings) > 0.01) ++rings;
  EXPECT_EQ(lower->faces()[disk].loops.size(), 1u);
  EXPECT_EQ(lower->faces()[disk].loops[0].size(), static_cast<size_t>(2 * rings));
  // A box through the centre but off the equator's ring: new vertices everywhere.
  const Body slanted = box({-2, -2, 0.1234567}, {2, 2, 2}).rotated_x(7);
  expect_volumes_add_up(ball, slanted);
  std::optional<Body> cap = subtract(ball, slanted);
  ASSERT_TRUE(cap);
  EXPECT_TRUE(convexity(*cap).convex);
  EXPECT_GE(flat_face(*cap, Transform::rotation_x(7).apply_vector({0, 0, -1})), 0);
}

TEST(Boolean, PipeTee) {
  const Body main_pipe = cylinder(0.5, -3, 3, 0.01).rotated_y(90);     // along x
  const Body branch = cylinder(0.3, 0, 2, 0.01);                      // along z, from the axis
  Body tee = unite(main_pipe, branch);
  std::optional<Body> common = intersect(main_pipe, branch);
  ASSERT_TRUE(common);
  EXPECT_NEAR(tee.volume(), main_pipe.volume() + branch.volume() - common->volume(),
              1e-9 * tee.volume());
  EXPECT_FALSE(convexity(tee).convex);
  EXPECT_EQ(tee.classify({0, 0, 1.5}), Location::Inside);
  EXPECT_EQ(tee.classify({2, 0, 0}), Location::Inside);
  EXPECT_EQ(tee.classify({0, 0.45, 0.6}), Location::Outside);
  expect_volumes_add_up(main_pipe, branch);
}

TEST(Boolean, NestedBooleans) {
  // A drilled plate with a dome on it, then cut by a slanted box: each step's result is the
  // next step's operand.
  Body part = *subtract(box({-2, -2, 0}, {2, 2, 1}), cylinder(0.5, -1, 2, 0.01));
  part = unite(part, *intersect(sphere({1, 1, 1}, 0.8, 0.02), box({-1, -1, 1}, {3, 3, 3})));
  const Body cutter = box({0, -3, -1}, {3, 3, 3}).rotated_z(20).rotated_x(5);
  expect_volumes_add_up(part, cutter);
  std::optional<Body> piece = subtract(part, cutter);
  ASSERT_TRUE(piece);
  std::optional<Body> again = subtract(*piece, cylinder(0.2, -1, 3, 0.01).translated({-1, -1, 0}));
  ASSERT_TRUE(again);
  EXPECT_NEAR(again->volume(), piece->volume() - ngon_area(segments_for_tolerance(0.2, 0.01), 0.2),
              1e-9 * piece->volume());
  // Exactly: each step started from the exact solid of the one before, not its rounding.
  const Body plug = cylinder(0.2, 0, 1, 0.01).translated({-1, -1, 0});
  EXPECT_EQ(exact_volume_sign({{1, *again}, {1, plug}, {-1, *piece}}), Sign::Zero);
}

// Regression: a Boolean's result was rounded to double before the next Boolean, an affine
// move or a volume saw it, so a chain of Booleans met volume identities only within rounding.
// The result keeps its exact solid.
TEST(Boolean, ResultsKeepTheirExactSolid) {
  const Body plate = box({-2, -2, 0}, {2, 2, 1}).transformed(Transform::rotation(Vec3(1, 2, 3), 37));
  const Body drill = cylinder(0.5, -1, 2, 0.01).transformed(Transform::rotation(Vec3(1, 2, 3), 37));
  std::optional<Body> drilled = subtract(plate, drill);
  ASSERT_TRUE(drilled && drilled->has_exact_solid());
  // The rotated box is the exact image of the box's corners (its faces are exactly planar),
  // and so is a rotated sphere (its quadrilaterals are exactly planar about its centre); a
  // body whose quadrilaterals are planar only within rounding (the rotated box's rounded
  // corners) has no exact image.
  EXPECT_TRUE(plate.has_exact_solid());
  EXPECT_TRUE(sphere({0, 0, 0}, 1, 0.05).transformed(Transform::rotation(Vec3(1, 2, 3), 37)).has_exact_solid());
  const Body rounded_plate(plate.vertices(), plate.faces());
  EXPECT_FALSE(rounded_plate.transformed(Transform::rotation(Vec3(3, 1, 2), 20)).has_exact_solid());
  EXPECT_FALSE(box({0, 0, 0}, {1, 1, 1}).has_exact_solid());  // its corners are its own
  // Rounded: the volume differs from the exact one, so the identity fails on the rounding of
  // the drilled plate (what a Boolean without its exact solid would have given).
  const Body rounded(drilled->vertices(), drilled->faces());
  EXPECT_FALSE(rounded.has_exact_solid());
  std::optional<Body> common = intersect(plate, drill);
  ASSERT_TRUE(common);
  EXPECT_EQ(exact_volume_sign({{1, *drilled}, {1, *common}, {-1, plate}}), Sign::Zero);
  EXPECT_NE(exact_volume_sign({{1, rounded}, {1, *common}, {-1, plate}}), Sign::Zero);
  // Moved by an affine map, it keeps an exact solid, moved exactly: the moved solid's
  // identities hold with the moved operands' results too.
  const Transform t = Transform::rotation(Vec3(-2, 1, 5), 23, Vec3(0.3, 0.1, 0.7));
  const Body moved = drilled->transformed(t);
  EXPECT_TRUE(moved.has_exact_solid());
  const Body cutter = box({-1, -3, -3}, {3, 3, 3}).rotated_z(11);
  expect_volumes_add_up(moved, cutter);
  // A reflection keeps the solid's orientation outward: its volume stays positive.
  const Body mirrored = drilled->scaled(Vec3(-1, 1, 1));
  EXPECT_TRUE(mirrored.has_exact_solid());
  EXPECT_EQ(exact_volume_sign({{1, mirrored}}), Sign::Positive);
  expect_volumes_add_up(mirrored, cutter);
  // A perspective map is not exact on rationals here: the body comes back without a solid.
  EXPECT_FALSE(drilled->translated({0, 0, -5}).transformed(Transform::perspective(10)).has_exact_solid());
}

// Body::exact_solid_bytes / with_exact_solid_bytes: what a process boundary (Python's pickle,
// the distributed engine) carries so that a body rebuilt there from its vertices and faces is
// decided on as here. Checked by the exact volume identity (exactly zero with the solid only),
// by the decomposition (from the solid, the same pieces bit for bit), for a made solid (a
// Boolean of rotated operands, rational corners), a pending image (a rotated L) and a Boolean
// whose body dropped points (ExactSolid::body_vertex); and by bytes that are not the format.
TEST(Boolean, ExactSolidBytesCarryTheSolidAcrossARebuild) {
  const Transform turn = Transform::rotation(Vec3(1, 2, 3), 37);
  const Body plate = box({-2, -2, 0}, {2, 2, 1}).transformed(turn);
  const Body drill = cylinder(0.5, -1, 2, 0.01).transformed(turn);
  const Body drilled = *subtract(plate, drill);
  const Body common = *intersect(plate, drill);
  const Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2).transformed(turn);
  const Body notched = *subtract(box({0, 0, 0}, {4, 4, 4}), box({1, 1, 3}, {3, 5, 5}).transformed(turn));
  for (const Body* b : {&drilled, &l, &notched}) {
    ASSERT_TRUE(b->has_exact_solid());
    const std::string bytes = b->exact_solid_bytes();
    ASSERT_FALSE(bytes.empty());
    const Body bare(b->vertices(), b->faces());
    EXPECT_TRUE(bare.exact_solid_bytes().empty());
    const Body back = bare.with_exact_solid_bytes(bytes);
    ASSERT_TRUE(back.has_exact_solid());
    EXPECT_FALSE(bare.has_exact_solid());  // a new body; the bare one is unchanged
    EXPECT_EQ(back.exact_solid_bytes(), bytes);
    DecomposeOptions options;
    options.exact_pieces = true;
    const Decomposition d0 = decompose(*b, options), d1 = decompose(back, options);
    EXPECT_EQ(d0.from_exact_solid, d1.from_exact_solid);
    ASSERT_EQ(d0.pieces.size(), d1.pieces.size());
    for (size_t k = 0; k < d0.pieces.size(); ++k) EXPECT_EQ(d0.pieces[k].vertices(), d1.pieces[k].vertices());
  }
  const Body rebuilt = Body(drilled.vertices(), drilled.faces()).with_exact_solid_bytes(drilled.exact_solid_bytes());
  EXPECT_EQ(exact_volume_sign({{1, rebuilt}, {1, common}, {-1, plate}}), Sign::Zero);
  EXPECT_NE(exact_volume_sign({{1, Body(drilled.vertices(), drilled.faces())}, {1, common}, {-1, plate}}), Sign::Zero);
  // Not the format, truncated, trailing bytes, another body: InvalidInput, the body unchanged.
  const std::string bytes = drilled.exact_solid_bytes();
  const Body bare(drilled.vertices(), drilled.faces());
  EXPECT_THROW(bare.with_exact_solid_bytes("HXS0" + bytes.substr(4)), InvalidInput);
  EXPECT_THROW(bare.with_exact_solid_bytes(bytes.substr(0, bytes.size() / 2)), InvalidInput);
  EXPECT_THROW(bare.with_exact_solid_bytes(bytes + "x"), InvalidInput);
  EXPECT_THROW(box({0, 0, 0}, {1, 1, 1}).with_exact_solid_bytes(bytes), InvalidInput);
  EXPECT_THROW(box({0, 0, 0}, {1, 1, 1}).with_exact_solid_bytes(l.exact_solid_bytes()), InvalidInput);
  EXPECT_EQ(bare.with_exact_solid_bytes("").has_exact_solid(), false);
}

TEST(Boolean, RandomRotationsOfCurvedOperands) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> unit(-1, 1), angle(0, 360);
  const Body plate = box({-2, -2, 0}, {2, 2, 1});
  const Body drill = cylinder(0.5, -1, 2, 0.01);
  const Body ball = sphere({0.3, 0.2, 0.5}, 1.1, 0.02);
  const double hole = ngon_area(segments_for_tolerance(0.5, 0.01), 0.5);
  for (int trial = 0; trial < 8; ++trial) {
    Vec3 axis(unit(rng), unit(rng), unit(rng));
    if (axis.norm() < 0.1) axis = Vec3(1, 2, 3);
    const Transform t = Transform::rotation(axis, angle(rng), Vec3(unit(rng), unit(rng), unit(rng)));
    SCOPED_TRACE("trial " + std::to_string(trial));
    const Body p = plate.transformed(t), d = drill.transformed(t), s = ball.transformed(t);
    std::optional<Body> drilled = subtract(p, d);
    ASSERT_TRUE(drilled);
    EXPECT_NEAR(drilled->volume(), 16 - hole, 1e-9 * 16);
    expect_volumes_add_up(p, s);
    expect_volumes_add_up(s, p);
    Body both = unite(*drilled, s);
    EXPECT_GT(both.volume(), drilled->volume());
  }
}

}  // namespace
}  // namespace hedra
