#include "hedra/visibility/outline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>

#include "hedra/core/primitives.h"

namespace hedra {
namespace {

constexpr double kPi = std::numbers::pi;

// Unit vectors u, w spanning the plane perpendicular to d.
std::pair<Vec3, Vec3> picture_axes(const Vec3& d) {
  Vec3 u = d.unitOrthogonal();
  return {u, d.normalized().cross(u)};
}

// Every end point shared by exactly two segments: the outline is closed.
bool closed_chains(const std::vector<OutlineSegment>& segments) {
  std::map<std::tuple<double, double, double>, int> count;
  for (const auto& s : segments) {
    ++count[{s.a.x(), s.a.y(), s.a.z()}];
    ++count[{s.b.x(), s.b.y(), s.b.z()}];
  }
  for (const auto& [p, n] : count)
    if (n != 2) return false;
  return !segments.empty();
}

TEST(Outline, SphereSeenInParallelIsACircleOfItsRadius) {
  // The projected outline of a sphere of radius r is a closed curve whose points lie between
  // r − t and r from the centre (t the chordal tolerance), and whose length is 2πr within
  // the same relative error. Analytic normals and area-weighted normals alike.
  std::mt19937 random(15);
  std::uniform_real_distribution<double> unit(-1, 1);
  const Vec3 centre(1, -2, 0.5);
  for (double t : {1e-2, 1e-3}) {
    const double r = 2;
    Body s = sphere(centre, r, t);
    for (bool analytic : {true, false}) {
      SmoothSurface surface = analytic ? SmoothSurface::sphere(centre, r) : SmoothSurface();
      for (int trial = 0; trial < 3; ++trial) {
        const Vec3 d(unit(random), unit(random), unit(random));
        auto segments = outline(s, Viewpoint::towards(d), 30, surface);
        ASSERT_TRUE(closed_chains(segments)) << t << " " << analytic;
        auto [u, w] = picture_axes(d);
        double length = 0;
        for (const auto& seg : segments) {
          const Vec2 a((seg.a - centre).dot(u), (seg.a - centre).dot(w));
          const Vec2 b((seg.b - centre).dot(u), (seg.b - centre).dot(w));
          length += (b - a).norm();
          EXPECT_LE(a.norm(), r + 1e-12);
          EXPECT_GE(a.norm(), r - 2 * t);
        }
        EXPECT_NEAR(length, 2 * kPi * r, 2 * kPi * 2 * t) << t << " analytic " << analytic;
      }
    }
  }
}

TEST(Outline, CylinderSeenFromTheSideIsTwoGeneratorsOfItsHeight) {
  // Seen along a direction oblique to the axis, a cylinder's outline is two straight
  // generators (the rims are sharp edges, not outline): every outline point lies on a
  // vertical line through the tangent points, and the total length is twice the height.
  const double r = 1.5, z0 = -1, z1 = 2;
  Body c = cylinder(r, z0, z1, 1e-3);
  const Vec3 d(-1, -0.4, -0.7);
  auto segments = outline(c, Viewpoint::towards(d), 30, SmoothSurface::cylinder(r, z0, z1));
  ASSERT_FALSE(segments.empty());
  const Vec3 side = Vec3(d.x(), d.y(), 0).normalized().cross(Vec3::UnitZ());  // ± tangent points
  double length = 0;
  for (const auto& s : segments) {
    length += (s.b - s.a).norm();
    for (const Vec3& p : {s.a, s.b}) {
      // On a generator: horizontal position along the tangent direction ±r (within the
      // chordal tolerance), none across it.
      const Vec3 h(p.x(), p.y(), 0);
      EXPECT_NEAR(std::abs(h.dot(side)), r, 1.01e-3);
      EXPECT_NEAR(h.dot(Vec3(d.x(), d.y(), 0).normalized()), 0, 0.06);
    }
    // Vertical: both ends at the same horizontal place.
    EXPECT_NEAR((s.b - s.a).head<2>().norm(), 0, 1e-9);
  }
  EXPECT_NEAR(length, 2 * (z1 - z0), 1e-9);
}

TEST(Outline, BoxHasOnlySharpEdgesAndNoOutline) {
  Body b = box({0, 0, 0}, {1, 2, 3});
  for (EdgeClass e : classify_edges(b)) EXPECT_EQ(e, EdgeClass::Sharp);
  EXPECT_TRUE(outline(b, Viewpoint::towards({-1, -2, -3})).empty());
  EXPECT_TRUE(outline(b, Viewpoint::at({5, 6, 7})).empty());
}

TEST(Outline, CreaseAngleSeparatesSharpFromSmoothEdges) {
  // A 12-sided prism turns by 30° per side: smooth below a crease angle of 30°, sharp above;
  // caps meet the sides at 90°, always sharp; as a cylinder surface the sides are smooth.
  Body p = regular_prism(12, 1, 0, 1);
  auto count = [](const std::vector<EdgeClass>& c) {
    return std::count(c.begin(), c.end(), EdgeClass::Smooth);
  };
  EXPECT_EQ(count(classify_edges(p, 31)), 12);
  EXPECT_EQ(count(classify_edges(p, 29)), 0);
  EXPECT_EQ(count(classify_edges(p, 10, SmoothSurface::cylinder(1, 0, 1))), 12);
  // The outline of the 12-gon as a cylinder is two generators of height 1; seen from a point.
  auto segments = outline(p, Viewpoint::at({5, 1, 0.5}), 30, SmoothSurface::cylinder(1, 0, 1));
  double length = 0;
  for (const auto& s : segments) length += (s.b - s.a).norm();
  EXPECT_NEAR(length, 2, 1e-9);
}

}  // namespace
}  // namespace hedra
