#include "hedra/mesh/convexity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "hedra/core/primitives.h"

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

}  // namespace
}  // namespace hedra
