// Differential random testing (tests/differential, `make stress`): seeded random solids and
// scenes (rotated boxes and prisms, convex and not), the case count from the environment, and
// the independent oracles the random cases are checked against (cover by sampling, the ground
// shadow as CGAL's exact union of projected piece hulls).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/core/predicates.h"
#include "hedra/core/primitives.h"
#include "hedra/decompose/decompose.h"
#include "hedra/visibility/polygon_union.h"

namespace hedra::testing {

/// Number of random cases: HEDRA_STRESS_CASES when set (`make stress` sets thousands), else
/// `fallback` (the count `make test` runs), or its first half in the sanitizer build (CI's 30
/// minutes: the differential tests were 66 s of its sanitizer tests; memory errors show on the
/// first seeds as well as on the later ones, and the Release build runs them all).
inline int stress_cases(int fallback) {
  if (const char* s = std::getenv("HEDRA_STRESS_CASES")) {
    const int n = std::atoi(s);
    if (n > 0) return n;
  }
#ifdef HEDRA_SANITIZED
  return (fallback + 1) / 2;
#else
  return fallback;
#endif
}

/// Runs `body(seed)` for `cases` seeds derived from `base`, each under a trace naming the seed
/// and how to rerun that case alone (HEDRA_STRESS_SEED=<seed>, which runs only that seed).
/// The case count scales with stress_cases(cases).
inline void for_each_case(std::uint64_t base, int cases, const std::function<void(std::uint64_t)>& body) {
  const char* test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const char* suite = ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name();
  if (const char* one = std::getenv("HEDRA_STRESS_SEED")) {
    const std::uint64_t seed = std::strtoull(one, nullptr, 10);
    SCOPED_TRACE("seed " + std::to_string(seed));
    body(seed);
    return;
  }
  const int n = stress_cases(cases);
  for (int i = 0; i < n; ++i) {
    const std::uint64_t seed = base * 1000003 + static_cast<std::uint64_t>(i);
    SCOPED_TRACE("seed " + std::to_string(seed) + " (rerun alone: HEDRA_STRESS_SEED=" + std::to_string(seed) +
                 " --gtest_filter=" + suite + "." + test + ")");
    body(seed);
    if (::testing::Test::HasFailure()) {
      std::printf("differential case failed: %s.%s seed %llu\n", suite, test,
                  static_cast<unsigned long long>(seed));
      return;  // the first failing seed is the one to look at
    }
  }
}

/// A random simple polygon of one of the prism families: a convex polygon, an L, a star, a
/// comb (notches), in a box about `size` wide.
inline Polygon2 random_outline(std::mt19937_64& rng, int family, double size) {
  std::uniform_real_distribution<double> u(0, 1);
  Polygon2 p;
  switch (family % 4) {
    case 0: {  // convex: points on an ellipse at random angles
      const int n = 3 + static_cast<int>(u(rng) * 6);
      const double a = size * (0.3 + 0.2 * u(rng)), b = size * (0.3 + 0.2 * u(rng)), phase = 7 * u(rng);
      for (int k = 0; k < n; ++k) {
        const double t = phase + 2 * std::numbers::pi * (k + 0.4 * u(rng)) / n;
        p.emplace_back(a * std::cos(t), b * std::sin(t));
      }
      break;
    }
    case 1: {  // L
      const double w = size * (0.6 + 0.4 * u(rng)), h = size * (0.6 + 0.4 * u(rng));
      const double tx = w * (0.2 + 0.5 * u(rng)), ty = h * (0.2 + 0.5 * u(rng));
      p = {{0, 0}, {w, 0}, {w, ty}, {tx, ty}, {tx, h}, {0, h}};
      break;
    }
    case 2: {  // star
      const int n = 3 + static_cast<int>(u(rng) * 6);
      const double outer = size * 0.5, inner = outer * (0.3 + 0.5 * u(rng)), phase = 7 * u(rng);
      for (int k = 0; k < 2 * n; ++k) {
        const double r = k % 2 ? inner : outer, t = phase + std::numbers::pi * k / n;
        p.emplace_back(r * std::cos(t), r * std::sin(t));
      }
      break;
    }
    default: {  // comb with 1–4 notches
      const int k = 1 + static_cast<int>(u(rng) * 4);
      const double step = size / (2 * k + 1), depth = size * (0.2 + 0.3 * u(rng));
      p = {{0, 0}, {size, 0}, {size, size * 0.6}};
      for (int i = k - 1; i >= 0; --i) {
        p.emplace_back((2 * i + 2) * step, size * 0.6);
        p.emplace_back((2 * i + 2) * step, size * 0.6 - depth * 0.9);
        p.emplace_back((2 * i + 1) * step, size * 0.6 - depth * 0.9);
        p.emplace_back((2 * i + 1) * step, size * 0.6);
      }
      p.emplace_back(0, size * 0.6);
    }
  }
  return p;
}

/// Three draws of `u`, in this order (a constructor's arguments are evaluated in an
/// unspecified order: GCC and clang made different scenes from one seed).
template <class Distribution>
inline Vec3 draw3(std::mt19937_64& rng, Distribution& u) {
  const double x = u(rng);
  const double y = u(rng);
  const double z = u(rng);
  return {x, y, z};
}

/// A random solid about `size` wide centred near `at`: a box (family 0) or a prism over
/// random_outline(family − 1), under a random generic rotation about its centroid (so that
/// its faces are planar only within rounding).
inline Body random_solid(std::mt19937_64& rng, int family, double size, const Vec3& at) {
  std::uniform_real_distribution<double> u(0, 1);
  Body b = [&] {
    if (family % 5 == 0) return box({0, 0, 0}, size * (Vec3(0.3, 0.3, 0.3) + 0.7 * draw3(rng, u)));
    const Polygon2 outline = random_outline(rng, family % 5 - 1, size);  // drawn before the height
    return prism(outline, 0, size * (0.3 + 0.7 * u(rng)));
  }();
  const Vec3 axis = draw3(rng, u) - Vec3(0.5, 0.5, 0.5);
  b = b.transformed(Transform::rotation(axis.norm() > 1e-3 ? axis : Vec3(1, 2, 3), 360 * u(rng), b.centroid()));
  return b.translated(at - b.centroid());
}

/// Whether `pieces` cover `body` without overlap at `samples` random points of its bounding
/// box: inside the body, inside exactly one piece (or on the boundary of at least two);
/// outside it, inside none. Empty string when they do, else the first offending point.
inline std::string cover_error(const Body& body, const std::vector<Body>& pieces, std::mt19937_64& rng,
                               int samples = 200) {
  const Eigen::AlignedBox3d box = body.bbox();
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < samples; ++trial) {
    const Vec3 p = box.min() + (box.max() - box.min()).cwiseProduct(draw3(rng, u));
    const Location where = body.classify(p);
    int in = 0, on = 0;
    for (const Body& piece : pieces) {
      const Location l = piece.classify(p);
      in += l == Location::Inside;
      on += l == Location::OnBoundary;
    }
    const bool ok = where == Location::Inside    ? (in == 1 || (in == 0 && on >= 2))
                    : where == Location::Outside ? in == 0
                                                 : true;
    if (!ok) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "point (%.17g, %.17g, %.17g): body %s, inside %d pieces, on %d", p.x(), p.y(),
                    p.z(), where == Location::Inside ? "inside" : "outside", in, on);
      return buf;
    }
  }
  return {};
}

/// 2D convex hull (counter-clockwise, no collinear points) by exact orientation. O(n log n).
inline Ring2 convex_hull_2d(std::vector<Vec2> pts) {
  std::sort(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return {};
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

/// Area of the shadow that bodies above z = 0 cast on the square |x|, |y| <= half of the
/// plane z = 0 under a directional light going along d (d.z() < 0): the union of the hulls of
/// their convex pieces (hedra's decomposition, each piece's hull projected along d), clipped
/// to the square, by CGAL's exact polygon Booleans. Independent of the shadow engine.
inline double ground_shadow_reference(const std::vector<Body>& casters, const Vec3& d, double half) {
  std::vector<Ring2> hulls;
  for (const Body& b : casters)
    for (const Body& piece : decompose(b).pieces) {
      std::vector<Vec2> pts;
      for (const Vec3& p : piece.vertices()) {
        const double t = -p.z() / d.z();
        pts.emplace_back(p.x() + t * d.x(), p.y() + t * d.y());
      }
      if (Ring2 h = convex_hull_2d(pts); !h.empty()) hulls.push_back(std::move(h));
    }
  const double big = 1e4;
  const std::vector<Ring2> frame = {{{-big, -big}, {big, -big}, {big, -half}, {-big, -half}},
                                    {{-big, half}, {big, half}, {big, big}, {-big, big}},
                                    {{-big, -half}, {-half, -half}, {-half, half}, {-big, half}},
                                    {{half, -half}, {big, -half}, {big, half}, {half, half}}};
  return cgal_difference(hulls, frame).area;
}

}  // namespace hedra::testing
