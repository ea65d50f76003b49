// The plane solid of a body whose faces are planar only within rounding (kernel/src/core/
// exact_solid.h, plane_solid): each face on one exact plane, each corner where its planes meet.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "core/exact_solid.h"
#include "hedra/core/primitives.h"
#include "hedra/core/tolerance.h"
#include "hedra/core/transform.h"

namespace hedra {
namespace {

using internal::ExactSolid;
using P3 = internal::ExactKernel::Point_3;

// A 2 × 2 × 1 box with its top in 2 × 2 quadrilaterals around a centre vertex: the centre lies on
// one plane (the top), the middles of the top's sides on two, the corners on three.
Body gridded_box() {
  std::vector<Vec3> v = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};  // bottom 0–3
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) v.emplace_back(i, j, 1);  // top grid 4 + 3j + i
  const auto top = [](int i, int j) { return 4 + 3 * j + i; };
  std::vector<Face> faces = {Face{0, 3, 2, 1}};
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) faces.push_back(Face{top(i, j), top(i + 1, j), top(i + 1, j + 1), top(i, j + 1)});
  faces.push_back(Face{0, 1, top(2, 0), top(1, 0), top(0, 0)});  // y = 0
  faces.push_back(Face{1, 2, top(2, 2), top(2, 1), top(2, 0)});  // x = 2
  faces.push_back(Face{2, 3, top(0, 2), top(1, 2), top(2, 2)});  // y = 2
  faces.push_back(Face{3, 0, top(0, 0), top(0, 1), top(0, 2)});  // x = 0
  return Body(v, faces);
}

// Every triangle of each face of the solid on one plane, exactly; every corner within 16
// rounding guards of its vertex; the solid's exact volume within rounding of the body's.
void expect_planar_within_rounding(const ExactSolid& solid, const Body& body, const std::string& name) {
  std::map<int, std::vector<std::array<int, 3>>> by_face;
  for (const ExactSolid::Tri& t : solid.triangles) by_face[t.face].push_back(t.v);
  ASSERT_EQ(by_face.size(), static_cast<size_t>(body.face_count())) << name;
  for (const auto& [face, tris] : by_face) {
    const auto& f = tris.front();
    const P3 &a = solid.points[static_cast<size_t>(f[0])], &b = solid.points[static_cast<size_t>(f[1])],
             &c = solid.points[static_cast<size_t>(f[2])];
    for (const auto& t : tris)
      for (int w : t) EXPECT_TRUE(CGAL::coplanar(a, b, c, solid.points[static_cast<size_t>(w)])) << name << " face " << face;
  }
  const double reach = 16 * kRoundingPlanarity * body.scale();
  for (size_t i = 0; i < solid.points.size(); ++i) {
    const P3& p = solid.points[i];
    const Vec3 q(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
    EXPECT_LE((q - body.vertices()[i]).norm(), reach) << name << " vertex " << i;
  }
  internal::ExactKernel::FT::ET six = 0;
  for (const ExactSolid::Tri& t : solid.triangles) {
    const auto &p = CGAL::exact(solid.points[static_cast<size_t>(t.v[0])]),
               &q = CGAL::exact(solid.points[static_cast<size_t>(t.v[1])]),
               &r = CGAL::exact(solid.points[static_cast<size_t>(t.v[2])]);
    six += p.x() * (q.y() * r.z() - q.z() * r.y()) - p.y() * (q.x() * r.z() - q.z() * r.x()) +
           p.z() * (q.x() * r.y() - q.y() * r.x());
  }
  EXPECT_NEAR(CGAL::to_double(six) / 6, body.volume(), 1e-12 * body.volume()) << name;
}

// Rotated and read back (its corners rounded, faces planar only within rounding): a plane solid
// with every face exactly planar, corners moved by rounding only; the centre of the gridded top
// (one plane) on the top's plane, the middles of its sides (two planes) on their line. Seeded
// rotations; the unrotated box (exactly planar faces) needs none.
TEST(ExactSolid, PlaneSolidPutsEveryCornerWhereItsPlanesMeet) {
  const Body aligned = gridded_box();
  EXPECT_TRUE(aligned.faces_off_plane().empty());
  EXPECT_EQ(internal::plane_solid(aligned), nullptr);
  int made = 0, centre_moved = 0, middle_moved = 0;
  for (int turn = 0; turn < 8; ++turn) {
    const Transform t = Transform::rotation(Vec3(1 + turn, 2 - turn, 3), 11 + 17 * turn);
    const Body read(aligned.transformed(t).vertices(), aligned.faces());
    if (read.faces_off_plane().empty()) continue;
    const auto solid = internal::plane_solid(read);
    ASSERT_NE(solid, nullptr) << "turn " << turn;
    ++made;
    EXPECT_TRUE(solid->rounded);
    EXPECT_TRUE(solid->body_vertex.empty());
    expect_planar_within_rounding(*solid, read, "turn " + std::to_string(turn));
    // The centre (vertex 8) and the top's four quadrilaterals' corners on one plane.
    const auto& pts = solid->points;
    EXPECT_TRUE(CGAL::coplanar(pts[4], pts[6], pts[12], pts[8])) << "turn " << turn;
    // A side's middle (vertex 5) on the line where the top and the side y = 0 meet.
    EXPECT_TRUE(CGAL::collinear(pts[4], pts[6], pts[5])) << "turn " << turn;
    const auto moved = [&](int i) {
      const Vec3& p = read.vertices()[static_cast<size_t>(i)];
      return pts[static_cast<size_t>(i)] != P3(p.x(), p.y(), p.z());
    };
    centre_moved += moved(8);
    middle_moved += moved(5) || moved(7) || moved(9) || moved(11);
  }
  EXPECT_GE(made, 6);
  EXPECT_GT(centre_moved, 0);  // the foot on one plane was taken
  EXPECT_GT(middle_moved, 0);  // the foot on the line of two
}

// A torus of revolution as quadrilaterals, rotated and read back: four planes at every vertex,
// which do not meet in one point. No plane solid.
TEST(ExactSolid, PlaneSolidOfATorusDoesNotExist) {
  const int n = 16, m = 8;
  std::vector<Vec3> v;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double a = 2 * std::numbers::pi * i / n, b = 2 * std::numbers::pi * j / m;
      v.emplace_back((2 + 0.75 * std::cos(b)) * std::cos(a), (2 + 0.75 * std::cos(b)) * std::sin(a), 0.75 * std::sin(b));
    }
  std::vector<Face> faces;
  const auto at = [&](int i, int j) { return (i % n) * m + j % m; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) faces.push_back(Face{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  const Body moved = Body(v, faces).transformed(Transform::rotation({1, 2, 3}, 37));
  const Body read(moved.vertices(), moved.faces());
  ASSERT_FALSE(read.faces_off_plane().empty());
  EXPECT_EQ(internal::plane_solid(read), nullptr);
}

// The rotated L block and a prism over a 40-gon read back: planar within rounding too.
TEST(ExactSolid, PlaneSolidOfRotatedPrismsReadBack) {
  Polygon2 ngon;
  for (int k = 0; k < 40; ++k) ngon.emplace_back(std::cos(2 * std::numbers::pi * k / 40), std::sin(2 * std::numbers::pi * k / 40));
  for (const Body& aligned : {prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2), prism(ngon, 0, 3)}) {
    const Body moved = aligned.transformed(Transform::rotation({0.3, -0.7, 0.65}, 37.3));
    const Body read(moved.vertices(), moved.faces());
    ASSERT_FALSE(read.faces_off_plane().empty());
    const auto solid = internal::plane_solid(read);
    ASSERT_NE(solid, nullptr);
    expect_planar_within_rounding(*solid, read, std::to_string(aligned.face_count()) + " faces");
  }
}

}  // namespace
}  // namespace hedra
