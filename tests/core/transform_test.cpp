#include "hedra/core/transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hedra/core/error.h"

namespace hedra {
namespace {

constexpr double kPi = std::numbers::pi;

void expect_near(const Mat4& a, const Mat4& b, double tol = 1e-12) {
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), tol) << "\n" << a << "\nvs\n" << b;
}

TEST(Transform, TranslationIsRowFour) {
  Mat4 expected = Mat4::Identity();
  expected.row(3) << 1, 2, 3, 1;
  EXPECT_EQ(Transform::translation({1, 2, 3}).matrix(), expected);
  EXPECT_EQ(Transform::translation({1, 2, 3}).apply(Vec3(1, 1, 1)), Vec3(2, 3, 4));
}

TEST(Transform, ScalingAboutCentreFollowsCourseFormula) {
  // x' = x·kx + (1 − kx)·xm
  Transform s = Transform::scaling(Vec3(2, 3, -1), Vec3(1, 1, 1));
  Mat4 expected;
  expected << 2, 0, 0, 0, 0, 3, 0, 0, 0, 0, -1, 0, -1, -2, 2, 1;
  EXPECT_EQ(s.matrix(), expected);
  EXPECT_EQ(s.apply(Vec3(2, 2, 2)), Vec3(3, 4, 0));
  EXPECT_EQ(s.apply(Vec3(1, 1, 1)), Vec3(1, 1, 1));  // the centre is fixed
}

TEST(Transform, ReflectionsInCoordinatePlanes) {
  EXPECT_EQ(Transform::scaling(Vec3(-1, 1, 1)).apply(Vec3(1, 2, 3)), Vec3(-1, 2, 3));  // YOZ
  EXPECT_EQ(Transform::scaling(Vec3(1, -1, 1)).apply(Vec3(1, 2, 3)), Vec3(1, -2, 3));  // XOZ
  EXPECT_EQ(Transform::scaling(Vec3(1, 1, -1)).apply(Vec3(1, 2, 3)), Vec3(1, 2, -3));  // XOY
  EXPECT_EQ(Transform::scaling(-1.0).apply(Vec3(1, 2, 3)), Vec3(-1, -2, -3));          // origin
  EXPECT_LT(Transform::scaling(Vec3(-1, 1, 1)).linear_determinant(), 0);
}

TEST(Transform, RotationMatricesByHand) {
  const double t = 30, c = std::cos(kPi / 6), s = std::sin(kPi / 6);
  Mat4 z, x, y;
  z << c, s, 0, 0, -s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  x << 1, 0, 0, 0, 0, c, s, 0, 0, -s, c, 0, 0, 0, 0, 1;
  y << c, 0, -s, 0, 0, 1, 0, 0, s, 0, c, 0, 0, 0, 0, 1;
  expect_near(Transform::rotation_z(t).matrix(), z);
  expect_near(Transform::rotation_x(t).matrix(), x);
  expect_near(Transform::rotation_y(t).matrix(), y);
  // The course's formulas about a centre (docs/algorithms.md §2):
  // x' = xc + (x−xc)cosθ − (y−yc)sinθ, ...
  const Vec3 centre(1, 2, 3), p(4, -1, 7);
  Vec3 q = Transform::rotation_z(t, centre).apply(p);
  EXPECT_NEAR(q.x(), 1 + 3 * c - (-3) * s, 1e-12);
  EXPECT_NEAR(q.y(), 2 + 3 * s + (-3) * c, 1e-12);
  EXPECT_EQ(q.z(), 7);
  q = Transform::rotation_x(t, centre).apply(p);
  EXPECT_NEAR(q.y(), 2 + (-3) * c - 4 * s, 1e-12);
  EXPECT_NEAR(q.z(), 3 + 4 * c + (-3) * s, 1e-12);
  q = Transform::rotation_y(t, centre).apply(p);
  EXPECT_NEAR(q.x(), 1 + 3 * c + 4 * s, 1e-12);
  EXPECT_NEAR(q.z(), 3 + 4 * c - 3 * s, 1e-12);
}

TEST(Transform, QuarterTurnsAreExact) {
  EXPECT_EQ(Transform::rotation_z(90).apply(Vec3(1, 0, 0)), Vec3(0, 1, 0));
  EXPECT_EQ(Transform::rotation_x(-90).apply(Vec3(0, 1, 0)), Vec3(0, 0, -1));
  EXPECT_EQ(Transform::rotation_y(180).apply(Vec3(1, 2, 3)), Vec3(-1, 2, -3));
}

TEST(Transform, ArbitraryAxisMatchesCoordinateAxes) {
  expect_near(Transform::rotation({0, 0, 2}, 37).matrix(), Transform::rotation_z(37).matrix());
  expect_near(Transform::rotation({5, 0, 0}, -12, {1, 2, 3}).matrix(),
              Transform::rotation_x(-12, {1, 2, 3}).matrix());
  // 120° about (1,1,1) permutes the axes.
  Vec3 q = Transform::rotation({1, 1, 1}, 120).apply(Vec3(1, 0, 0));
  EXPECT_LT((q - Vec3(0, 1, 0)).norm(), 1e-15);
  EXPECT_THROW(Transform::rotation({0, 0, 0}, 10), InvalidInput);
}

TEST(Transform, CompositionAndInverse) {
  Transform a = Transform::rotation_z(25, {1, 0, 0}) * Transform::scaling(Vec3(2, 3, 4)) *
                Transform::translation({1, -2, 5});
  expect_near((a * a.inverse()).matrix(), Mat4::Identity());
  Vec3 p(0.3, -1.7, 2.2);
  EXPECT_LT((a.inverse().apply(a.apply(p)) - p).norm(), 1e-13);
  // Row convention: (A * B) applies A first.
  Transform t = Transform::translation({1, 0, 0}), s = Transform::scaling(2.0);
  EXPECT_EQ((t * s).apply(Vec3(0, 0, 0)), Vec3(2, 0, 0));
  EXPECT_EQ((s * t).apply(Vec3(0, 0, 0)), Vec3(1, 0, 0));
  EXPECT_THROW(Transform::perspective_projection(5).inverse(), InvalidInput);
}

TEST(Transform, CourseCommutativityFacts) {
  Transform t1 = Transform::translation({1, 2, 3}), t2 = Transform::translation({-4, 0, 2});
  expect_near((t1 * t2).matrix(), (t2 * t1).matrix());
  Transform u = Transform::scaling(2.5), r = Transform::rotation_z(33);
  expect_near((u * r).matrix(), (r * u).matrix());
  Transform r2 = Transform::rotation_z(12);
  expect_near((r * r2).matrix(), Transform::rotation_z(45).matrix());  // angles add
  Transform nonuniform = Transform::scaling(Vec3(1, 3, 1));
  EXPECT_GT(((nonuniform * r).matrix() - (r * nonuniform).matrix()).cwiseAbs().maxCoeff(), 0.1);
  Transform s2 = Transform::scaling(Vec3(2, 5, 7));
  expect_near((nonuniform * s2).matrix(), Transform::scaling(Vec3(2, 15, 7)).matrix());
  // Translation and scaling do not commute.
  EXPECT_GT(((t1 * u).matrix() - (u * t1).matrix()).cwiseAbs().maxCoeff(), 0.1);
}

TEST(Transform, PerspectiveFollowsCourseFormula) {
  const double C = 10;
  Mat4 expected = Mat4::Identity();
  expected(2, 3) = -1.0 / C;
  EXPECT_EQ(Transform::perspective(C).matrix(), expected);
  expected(2, 2) = 0;
  EXPECT_EQ(Transform::perspective_projection(C).matrix(), expected);
  // (x, y, z) -> (x, y, 0) / (1 − z/C)
  Vec3 p(2, -3, 4);
  Vec3 q = Transform::perspective_projection(C).apply(p);
  EXPECT_DOUBLE_EQ(q.x(), 2 / (1 - 0.4));
  EXPECT_DOUBLE_EQ(q.y(), -3 / (1 - 0.4));
  EXPECT_EQ(q.z(), 0);
  EXPECT_FALSE(Transform::perspective(C).is_affine());
  EXPECT_THROW(Transform::perspective(C).apply(Vec3(0, 0, C)), InvalidInput);  // vanishing plane
  EXPECT_THROW(Transform::perspective(0), InvalidInput);
}

TEST(Transform, PlanesAndBodyMatricesKeepInteriorPositive) {
  // Plane x > 1 (inner side), moved by a rotation and translation.
  Plane plane(1, 0, 0, -1);
  Transform t = Transform::rotation_z(40) * Transform::translation({3, 4, 5});
  Plane moved = t.apply(plane);
  Vec3 inside(2, 0.5, 0), outside(0, 0.5, 0);
  EXPECT_GT(moved.value(t.apply(inside)), 0);
  EXPECT_LT(moved.value(t.apply(outside)), 0);
  EXPECT_NEAR(moved.normal().norm(), 1, 1e-15);
  // [VT] = [T]⁻¹[V]: p'·V' = p·V.
  BodyMatrix v(4, 2);
  v << 1, -1, 0, 0, 0, 0, 1, 1;
  BodyMatrix vt = t.apply(v);
  for (int j = 0; j < 2; ++j)
    EXPECT_NEAR(t.apply(inside).homogeneous().dot(vt.col(j)),
                inside.homogeneous().dot(v.col(j)), 1e-12);
}

}  // namespace
}  // namespace hedra
