// The expansion stage of orient3d (kernel/src/core/expansion.h) against the determinant in
// exact rationals (GMP), on the inputs it exists for — exactly coplanar points, the snapped
// quadrilaterals of a sphere — and on points an ulp off them, in general position, across
// exponents, and where it must decline (inexact differences, values out of its range).
#include <CGAL/Gmpq.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/expansion.h"
#include "hedra/core/predicates.h"
#include "hedra/core/primitives.h"

namespace hedra::internal {
namespace {

using Q = CGAL::Gmpq;

// sign det[b − a; c − a; d − a] (d a point) or det[b − a; c − a; d] (a direction), in GMP.
Sign reference(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, bool d_is_point = true) {
  Q u[3], v[3], w[3];
  for (int i = 0; i < 3; ++i) {
    u[i] = Q(b[i]) - Q(a[i]);
    v[i] = Q(c[i]) - Q(a[i]);
    w[i] = d_is_point ? Q(d[i]) - Q(a[i]) : Q(d[i]);
  }
  const Q det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                u[2] * (v[0] * w[1] - v[1] * w[0]);
  return det > 0 ? Sign::Positive : det < 0 ? Sign::Negative : Sign::Zero;
}

// Checks the stage where it decides, and orient3d (which falls back to Mpzf) everywhere;
// returns whether the stage decided.
bool check(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Sign want = reference(a, b, c, d);
  EXPECT_EQ(orient3d(a, b, c, d), want);
  const std::optional<Sign> got = expansion::orient3d(a.data(), b.data(), c.data(), d.data(), true);
  if (got) EXPECT_EQ(*got, want) << a.transpose() << " | " << b.transpose() << " | " << c.transpose() << " | " << d.transpose();
  return got.has_value();
}

// Points of the plane z = (k − p·x − q·y) / 2^s with small integers: exactly coplanar, scaled
// by 2^e; then one coordinate of the last point moved by an ulp either way.
TEST(Expansion, ExactlyCoplanarPointsAndTheirUlpNeighbours) {
  std::mt19937_64 rng(20261207);
  std::uniform_int_distribution<int> small(-1000, 1000), exponent(-60, 60), axis(0, 2);
  int decided = 0, zeros = 0, near = 0;
  for (int n = 0; n < 4000; ++n) {
    const int p = small(rng), q = small(rng), k = small(rng), e = exponent(rng);
    const auto on = [&] {
      const double x = small(rng), y = small(rng);
      return Vec3(std::ldexp(x, e), std::ldexp(y, e), std::ldexp((k - p * x - q * y) / 1024.0, e));
    };
    const Vec3 a = on(), b = on(), c = on(), d = on();
    zeros += reference(a, b, c, d) == Sign::Zero;
    decided += check(a, b, c, d);
    Vec3 up = d, down = d;
    const int i = axis(rng);
    up[i] = std::nextafter(d[i], INFINITY);
    down[i] = std::nextafter(d[i], -INFINITY);
    near += check(a, b, c, up);
    near += check(a, b, c, down);
  }
  EXPECT_GT(zeros, 3900);      // the coplanar cases are exactly zero
  EXPECT_EQ(decided, 4000);    // and the stage, not Mpzf, decides every one (exact differences)
  EXPECT_GT(near, 8000 / 4);   // an ulp off: many differences still exact (3969 of 8000)
}

// Every quadrilateral of a sphere about the origin is exactly planar (its snapped vertices:
// primitives.md); the stage decides each as zero, and a vertex an ulp off as non-zero.
TEST(Expansion, SnappedSphereQuadrilateralsAreExactlyPlanar) {
  const Body s = sphere(Vec3::Zero(), 1.7, 1e-3);
  const auto& v = s.vertices();
  int quads = 0, decided = 0;
  for (const Face& f : s.faces()) {
    const auto& l = f.loops[0];
    if (l.size() != 4) continue;
    ++quads;
    const Vec3 &a = v[static_cast<size_t>(l[0])], &b = v[static_cast<size_t>(l[1])], &c = v[static_cast<size_t>(l[2])],
               &d = v[static_cast<size_t>(l[3])];
    EXPECT_EQ(reference(a, b, c, d), Sign::Zero);
    decided += check(a, b, c, d);
    Vec3 off = d;
    off.z() = std::nextafter(d.z(), INFINITY);
    check(a, b, c, off);
  }
  EXPECT_GT(quads, 100);
  EXPECT_GT(decided, quads / 2);
  EXPECT_TRUE(s.faces_off_plane().empty());
}

TEST(Expansion, GeneralPositionAndDirections) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n = 0; n < 2000; ++n) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng)), d(u(rng), u(rng), u(rng));
    check(a, b, c, d);
    // A direction: the last row is d itself, not d − a.
    const std::optional<Sign> got = expansion::orient3d(a.data(), b.data(), c.data(), d.data(), false);
    const Sign want = reference(a, b, c, d, false);
    if (got) EXPECT_EQ(*got, want);
    EXPECT_EQ(orient_direction(a, b, c, d), want);
    // Dyadic points on a grid: exact differences, so the stage decides.
    const auto grid = [](const Vec3& p) { return Vec3((p * 64).array().round() / 64); };
    EXPECT_TRUE(check(grid(a), grid(b), grid(c), grid(d)) || grid(a) == grid(b));
  }
}

// It declines where it cannot be exact: a difference that rounds, a value out of its range.
TEST(Expansion, DeclinesInexactDifferencesAndValuesOutOfRange) {
  const Vec3 a(0.1, 0.2, 0.3), b(1e17, 0.2, 0.3), c(0.1, 1, 0.3), d(0.1, 0.2, 1);
  EXPECT_FALSE(expansion::orient3d(a.data(), b.data(), c.data(), d.data(), true));  // 1e17 − 0.1 rounds
  const Vec3 t(1e-100, 0, 0), o(0, 0, 0), y(0, 1e-100, 0), z(0, 0, 1e-100);
  EXPECT_FALSE(expansion::orient3d(o.data(), t.data(), y.data(), z.data(), true));
  EXPECT_EQ(orient3d(o, t, y, z), reference(o, t, y, z));
  const Vec3 big(0, 0, 1e300);
  EXPECT_FALSE(expansion::orient3d(o.data(), t.data(), y.data(), big.data(), true));
}

}  // namespace
}  // namespace hedra::internal
