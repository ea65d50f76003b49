#include "hedra/mesh/merge_coplanar.h"

#include <gtest/gtest.h>

#include "hedra/core/error.h"
#include "hedra/core/predicates.h"
#include "hedra/core/primitives.h"
#include "hedra/core/triangulate.h"
#include "hedra/mesh/convexity.h"
#include "hedra/mesh/self_intersection.h"
#include "testing/decomposition_suite.h"

#include <algorithm>
#include <array>
#include <map>

namespace hedra {
namespace {

// Every face of a body as its triangles: what an STL file holds.
PolygonSoup triangulated(const Body& b) {
  PolygonSoup s{b.vertices(), {}};
  for (const Triangle& t : b.triangles()) s.polygons.push_back({t.v[0], t.v[1], t.v[2]});
  return s;
}

TEST(MergeCoplanar, TriangulatedBoxHasSixFaces) {
  Body b = box({0, 0, 0}, {1, 2, 3});
  std::vector<Body> merged = bodies_from_soup(triangulated(b));
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_EQ(merged[0].face_count(), 6);
  EXPECT_EQ(merged[0].vertex_count(), 8);
  EXPECT_EQ(merged[0].volume(), 6);
}

TEST(MergeCoplanar, PlateWithHoleCapBecomesOneFaceWithAHole) {
  Body plate = prism({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, 1, {{{1, 1}, {3, 1}, {3, 3}, {1, 3}}});
  std::vector<Body> merged = bodies_from_soup(triangulated(plate));
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_EQ(merged[0].face_count(), 10);
  int with_holes = 0;
  for (const Face& f : merged[0].faces()) with_holes += f.loops.size() == 2;
  EXPECT_EQ(with_holes, 2);
  EXPECT_EQ(merged[0].volume(), 12);
}

TEST(MergeCoplanar, InteriorVertexIsDropped) {
  // A box whose top is a fan around a centre vertex.
  Body b = box({0, 0, 0}, {2, 2, 2});
  PolygonSoup s{b.vertices(), {}};
  for (int f = 0; f < 5; ++f) s.polygons.push_back(b.faces()[f].loops[0]);
  s.vertices.emplace_back(1, 1, 2);
  const auto& top = b.faces()[5].loops[0];
  for (size_t i = 0; i < 4; ++i) s.polygons.push_back({top[i], top[(i + 1) % 4], 8});
  std::vector<Body> merged = bodies_from_soup(s);
  EXPECT_EQ(merged[0].face_count(), 6);
  EXPECT_EQ(merged[0].vertex_count(), 8);
}

TEST(MergeCoplanar, NearlyCoplanarNeedsTheTolerance) {
  Body b = box({0, 0, 0}, {1, 1, 1});
  PolygonSoup s = triangulated(b);
  // Lift one top vertex of a triangulated top by 1e-9: two triangles no longer coplanar.
  s.vertices[7].z() += 1e-9;
  auto exact = bodies_from_soup(s);
  EXPECT_GT(exact[0].face_count(), 6);
  MergeOptions loose;
  loose.coplanar_tolerance = 1e-6;
  loose.planarity_tolerance = 1e-6;
  EXPECT_EQ(bodies_from_soup(s, loose)[0].face_count(), 6);
}

TEST(MergeCoplanar, ComponentsBecomeBodies) {
  PolygonSoup a = triangulated(box({0, 0, 0}, {1, 1, 1}));
  PolygonSoup b = triangulated(box({3, 0, 0}, {4, 1, 1}));
  const int offset = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto p : b.polygons) {
    for (int& v : p) v += offset;
    a.polygons.push_back(p);
  }
  std::vector<Body> bodies = bodies_from_soup(a);
  ASSERT_EQ(bodies.size(), 2u);
  EXPECT_EQ(bodies[1].bbox().min().x(), 3);
}

TEST(MergeCoplanar, ErrorsNameInputPolygons) {
  PolygonSoup s = triangulated(box({0, 0, 0}, {1, 1, 1}));
  std::reverse(s.polygons[3].begin(), s.polygons[3].end());
  try {
    bodies_from_soup(s);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("face 3 is flipped"), std::string::npos) << e.what();
  }
}

// A box with every side cut into k × k squares, each split into two triangles: 12k² polygons.
PolygonSoup gridded_box(int k) {
  PolygonSoup s;
  std::map<std::array<int, 3>, int> id;
  auto vertex = [&](std::array<int, 3> g) {
    auto [it, fresh] = id.emplace(g, static_cast<int>(s.vertices.size()));
    if (fresh) s.vertices.emplace_back(g[0], g[1], g[2]);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          auto at = [&](int u, int w) {
            std::array<int, 3> g{};
            g[axis] = side * k;
            g[(axis + 1) % 3] = u;
            g[(axis + 2) % 3] = w;
            return vertex(g);
          };
          const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
          // Counter-clockwise from outside: (u, w) turns positively on the far side.
          if (side) {
            s.polygons.push_back({a, b, c});
            s.polygons.push_back({a, c, d});
          } else {
            s.polygons.push_back({a, c, b});
            s.polygons.push_back({a, d, c});
          }
        }
  return s;
}

TEST(MergeCoplanar, GriddedBoxMergesToSixFacesWithItsSoupNotCopied) {
  const PolygonSoup s = gridded_box(30);  // 10 800 triangles: the parallel per-polygon pass
  std::vector<Body> merged = bodies_from_soup(s);
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_EQ(merged[0].face_count(), 6);
  EXPECT_EQ(merged[0].vertex_count(), 8);
  EXPECT_EQ(merged[0].volume(), 27000);
}

TEST(MergeCoplanar, FirstZeroAreaPolygonIsNamedWhateverTheThreads) {
  PolygonSoup s = gridded_box(30);
  // Two grid vertices far apart in polygon order moved onto a neighbour: the triangles on the
  // edge between them have two corners at one point; the lowest such polygon must be named.
  // (Moved onto the midpoint of two neighbours instead, a corner makes a needle of three
  // distinct collinear corners, which is mended: NeedleTrianglesAreDropped… below.)
  auto flatten = [&](size_t polygon) {
    const auto& t = s.polygons[polygon];
    s.vertices[static_cast<size_t>(t[0])] = s.vertices[static_cast<size_t>(t[1])];
  };
  flatten(9000);
  flatten(150);
  int expected = -1;
  for (size_t p = 0; p < s.polygons.size() && expected < 0; ++p) {
    const auto& t = s.polygons[p];
    if (collinear(s.vertices[t[0]], s.vertices[t[1]], s.vertices[t[2]])) expected = static_cast<int>(p);
  }
  ASSERT_GE(expected, 0);
  try {
    bodies_from_soup(s);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("polygon " + std::to_string(expected) + " has zero area"),
              std::string::npos)
        << e.what();
  }
}

// A box 2 × 2 × 1 whose top edge from (0, 0, 1) to (2, 0, 1) has a vertex m = (1, 0, 1) on the
// top's side (a T-junction) and, on the front's side, a needle (0,0,1)–(2,0,1)–m filling it, as a
// mesher or float32 rounding leaves them; `offset` moves every coordinate (float32-exact).
PolygonSoup box_with_needle(const Vec3& offset) {
  PolygonSoup s;
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0, 2, 0), Vec3(0, 0, 1), Vec3(2, 0, 1),
                        Vec3(2, 2, 1), Vec3(0, 2, 1), Vec3(1, 0, 1)})
    s.vertices.push_back(p + offset);
  s.polygons = {{0, 3, 2}, {0, 2, 1}, {4, 8, 7}, {8, 6, 7}, {8, 5, 6}, {0, 1, 5}, {0, 5, 4}, {4, 5, 8},
                {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  return s;
}

// Issue 14 ("never fail on a valid closed mesh"): a needle, a triangle of three distinct
// collinear corners, has no plane, and the soup was rejected ("polygon 7 has zero area"). The
// surface is the same without it: it is dropped and its middle corner joins the edge across its
// long side. Reference: the box itself (6 faces, volume 4, area 16, convex).
TEST(MergeCoplanar, NeedleTrianglesAreDroppedAndTheirMiddleCornerJoinsTheEdgeAcross) {
  for (const Vec3& offset : {Vec3(0, 0, 0), Vec3(1000, -250, 8)}) {
    const std::vector<Body> bodies = bodies_from_soup(box_with_needle(offset));
    ASSERT_EQ(bodies.size(), 1u);
    EXPECT_EQ(bodies[0].face_count(), 6);
    EXPECT_EQ(bodies[0].volume(), 4);
    EXPECT_EQ(bodies[0].area(), 16);
    EXPECT_TRUE(is_convex(bodies[0]));
  }
  // A second needle, on the bottom edge 0–1: the front's side of it is split at 9 = (1, 0, 0),
  // the bottom's is not, and the needle 0–1–9 fills the gap. Both go.
  PolygonSoup two = box_with_needle(Vec3::Zero());
  two.vertices.emplace_back(1, 0, 0);  // 9, on the bottom edge 0–1
  two.polygons[5] = {0, 9, 5};         // the front's lower triangle now ends at 9 …
  two.polygons.push_back({9, 1, 5});   // … and a triangle from 9 reaches 1
  two.polygons.push_back({0, 1, 9});   // the needle between them and the bottom's edge 1 → 0
  const std::vector<Body> twice = bodies_from_soup(two);
  ASSERT_EQ(twice.size(), 1u);
  EXPECT_EQ(twice[0].volume(), 4);
  EXPECT_EQ(twice[0].face_count(), 6);
}

// Where mending does not make a valid soup (here the mesh is broken elsewhere: a flipped face),
// the error is the input's own, naming the input's polygon.
TEST(MergeCoplanar, NeedleThatCannotBeMendedKeepsTheInputsError) {
  PolygonSoup s = box_with_needle(Vec3::Zero());
  std::reverse(s.polygons[12].begin(), s.polygons[12].end());  // a flipped face elsewhere
  try {
    bodies_from_soup(s);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("face 12 is flipped"), std::string::npos) << e.what();
  }
}

// A needle in a surface that lies on itself elsewhere: the top's fan about a corner 9 put outside
// the top, at (3, 1, 1), so that triangle 5 6 9 turns over. Mended, the soup merges, as it would
// without the needle, and the self-intersection test that readers run on every body finds it.
TEST(MergeCoplanar, NeedleInASurfaceLyingOnItselfLeavesItToTheSelfIntersectionTest) {
  PolygonSoup fold = box_with_needle(Vec3::Zero());
  fold.vertices.emplace_back(3, 1, 1);  // 9
  fold.polygons[2] = {4, 8, 9};
  fold.polygons[3] = {8, 5, 9};
  fold.polygons[4] = {5, 6, 9};
  fold.polygons.push_back({6, 7, 9});
  fold.polygons.push_back({7, 4, 9});
  const std::vector<Body> bodies = bodies_from_soup(fold);
  ASSERT_EQ(bodies.size(), 1u);
  EXPECT_TRUE(find_self_intersection(bodies[0]).has_value());
}

TEST(CheckPolygonMesh, PolygonsGiveTheFaceMessagesAndEachHalfEdgesTwin) {
  PolygonSoup s = triangulated(box({0, 0, 0}, {1, 1, 1}));
  std::vector<int> twin = check_polygon_mesh(s.vertices, s.polygons);
  std::vector<std::pair<int, int>> half_edges;  // (from, to) polygon by polygon
  for (const auto& poly : s.polygons)
    for (size_t i = 0; i < poly.size(); ++i)
      half_edges.emplace_back(poly[i], poly[(i + 1) % poly.size()]);
  ASSERT_EQ(twin.size(), half_edges.size());
  for (size_t h = 0; h < twin.size(); ++h) {
    const auto [a, b] = half_edges[h];
    EXPECT_EQ(half_edges[static_cast<size_t>(twin[h])], std::make_pair(b, a));
  }
  std::reverse(s.polygons[3].begin(), s.polygons[3].end());
  std::vector<Face> faces;
  for (const auto& poly : s.polygons) faces.emplace_back(poly);
  std::string from_faces, from_polygons;
  try { check_polygon_mesh(s.vertices, faces); } catch (const InvalidInput& e) { from_faces = e.what(); }
  try { check_polygon_mesh(s.vertices, s.polygons); } catch (const InvalidInput& e) { from_polygons = e.what(); }
  EXPECT_NE(from_faces.find("face 3 is flipped"), std::string::npos) << from_faces;
  EXPECT_EQ(from_polygons, from_faces);
}

// The `--tolerance D` of the command: nearly coplanar faces merged and snapped planar, every
// vertex moved by at most D, and the result a valid body without any planarity tolerance.
TEST(MergeCoplanar, ToleranceSnapsAFloat32RotatedPartToItsFaces) {
  const Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2)
                     .transformed(Transform::rotation({1, 2, 3}, 37));
  PolygonSoup s = triangulated(l);
  for (Vec3& p : s.vertices)
    p = Vec3(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  EXPECT_EQ(bodies_from_soup(s)[0].face_count(), 20);  // exact: the triangles stay apart
  MergeOptions options;
  options.coplanar_tolerance = 1e-5;
  std::vector<Body> snapped = bodies_from_soup(s, options);
  ASSERT_EQ(snapped.size(), 1u);
  EXPECT_EQ(snapped[0].face_count(), 8);
  EXPECT_EQ(snapped[0].vertex_count(), 12);
  // Certified: every vertex within D of an input vertex (the same one: order is kept).
  for (int i = 0; i < 12; ++i)
    EXPECT_LE((snapped[0].vertices()[i] - s.vertices[i]).norm(), 1e-5);
  EXPECT_NEAR(snapped[0].volume(), 12, 1e-4);
  // Valid as it is: rebuilt with the default (rounding-level) planarity check.
  EXPECT_NO_THROW(Body(snapped[0].vertices(), snapped[0].faces()));
  // A tolerance smaller than the float rounding merges nothing and moves nothing.
  options.coplanar_tolerance = 1e-12;
  EXPECT_EQ(bodies_from_soup(s, options)[0].face_count(), 20);
}

// A convex loop with a straight run (a vertex splitting an edge in two): the fan from a
// strictly convex corner would make a flat triangle; every loop edge must still be a triangle
// edge, or the body's triangles are not closed (a float32 plate with 5×5 holes failed so).
TEST(Triangulate, ConvexLoopWithAStraightRunKeepsEveryEdge) {
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 2, 0}};
  for (int start = 0; start < 4; ++start) {
    std::vector<int> loop;
    for (int k = 0; k < 4; ++k) loop.push_back((start + k) % 4);
    const auto tris = triangulate_polygon(v, {loop}, Vec3(0, 0, 1));
    std::map<std::pair<int, int>, int> edges;
    double area = 0;
    for (const auto& t : tris) {
      for (int i = 0; i < 3; ++i) ++edges[{t[i], t[(i + 1) % 3]}];
      area += (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).z() / 2;
    }
    for (int k = 0; k < 4; ++k) {
      const std::pair<int, int> edge(loop[k], loop[(k + 1) % 4]);
      EXPECT_EQ(edges[edge], 1) << start;
    }
    EXPECT_EQ(area, 2) << start;
  }
}

// The body of a float32 STL of a rotated plate with 5×5 holes: its triangles are closed.
TEST(MergeCoplanar, Float32PlateWithHolesHasClosedTriangles) {
  for (const Vec3& axis : {Vec3(1, 2, 3), Vec3(0.3, -0.7, 0.2), Vec3(-2, 3, 1)}) {
    const Body plate = suite::plate_with_holes(5).transformed(Transform::rotation(axis, 37));
    PolygonSoup s = triangulated(plate);
    for (Vec3& p : s.vertices)
      p = Vec3(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    const Body b = bodies_from_soup(s).at(0);
    std::map<std::pair<int, int>, int> directed;
    for (const Triangle& t : b.triangles())
      for (int i = 0; i < 3; ++i) ++directed[{t.v[i], t.v[(i + 1) % 3]}];
    for (const auto& [e, n] : directed) {
      EXPECT_EQ(n, 1);
      const std::pair<int, int> back(e.second, e.first);
      EXPECT_EQ(directed.count(back), 1u) << e.first << " " << e.second;
    }
  }
}

}  // namespace
}  // namespace hedra
