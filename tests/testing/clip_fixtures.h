// Fixtures shared by the clipping tests and bench/clip_bench.cpp: convex bodies (hulls, the
// icosahedron), non-convex clippers as convex pieces, and an exact rational Cyrus–Beck used as
// the oracle (CGAL::Exact_rational, independent of the predicates and filters under test).
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/clip/convex_clipper.h"
#include "hedra/clip/cyrus_beck.h"
#include "hedra/core/primitives.h"

namespace hedra::testing {

using Rational = CGAL::Exact_rational;

/// The convex hull of points in general position, as a Body of triangles.
inline Body convex_hull_body(const std::vector<Vec3>& points) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Mesh = CGAL::Surface_mesh<K::Point_3>;
  std::vector<K::Point_3> pts;
  for (const Vec3& p : points) pts.emplace_back(p.x(), p.y(), p.z());
  Mesh mesh;
  CGAL::convex_hull_3(pts.begin(), pts.end(), mesh);
  std::vector<Vec3> vertices;
  for (auto v : mesh.vertices()) {
    const K::Point_3& p = mesh.point(v);
    vertices.emplace_back(p.x(), p.y(), p.z());
  }
  std::vector<Face> faces;
  for (auto f : mesh.faces()) {
    std::vector<int> loop;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      loop.push_back(static_cast<int>(v.idx()));
    faces.emplace_back(loop);
  }
  return Body(std::move(vertices), std::move(faces));
}

/// Regular icosahedron (20 triangular faces) with circumradius about `radius`.
inline Body icosahedron(double radius = 1) {
  const double phi = std::numbers::phi, s = radius / std::sqrt(1 + phi * phi);
  std::vector<Vec3> v;
  for (int a : {-1, 1})
    for (int b : {-1, 1}) {
      v.emplace_back(0, a * s, b * phi * s);
      v.emplace_back(a * s, b * phi * s, 0);
      v.emplace_back(b * phi * s, 0, a * s);
    }
  return convex_hull_body(v);
}

/// A random convex body: the hull of n points on a sphere of radius r about c.
inline Body random_convex_body(std::mt19937_64& rng, int n, double r, const Vec3& c) {
  std::normal_distribution<double> g(0, 1);
  std::vector<Vec3> pts;
  while (static_cast<int>(pts.size()) < n) {
    Vec3 d(g(rng), g(rng), g(rng));
    if (d.norm() < 1e-3) continue;
    pts.push_back(c + r * d.normalized());
  }
  return convex_hull_body(pts);
}

/// The L prism of the tests as a body and as its two convex pieces (sharing x = 1, 0 ≤ y ≤ 1).
inline Body l_prism() { return prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2); }
inline std::vector<Body> l_prism_pieces() {
  return {box({0, 0, 0}, {1, 3, 2}), box({1, 0, 0}, {4, 1, 2})};
}

/// A 4 × 4 × 1 plate with a 2 × 2 hole through it, and its four convex pieces: two full-width
/// strips (front and back) and two blocks between them (left and right of the hole).
inline Body plate_with_hole() {
  return prism({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, 1, {{{1, 1}, {1, 3}, {3, 3}, {3, 1}}});
}
inline std::vector<Body> plate_pieces() {
  return {box({0, 0, 0}, {4, 1, 1}), box({0, 3, 0}, {4, 4, 1}), box({0, 1, 0}, {1, 3, 1}),
          box({3, 1, 0}, {4, 3, 1})};
}

inline std::vector<ConvexClipper> clippers_of(const std::vector<Body>& bodies) {
  std::vector<ConvexClipper> c;
  for (const Body& b : bodies) c.emplace_back(b);
  return c;
}

/// f(p) exactly.
inline Rational exact_value(const ExactPlane& f, const Vec3& p) {
  Rational v;
  if (f.by_points()) {
    const auto& [a, b, c] = f.points();
    const Rational bax = Rational(b.x()) - a.x(), bay = Rational(b.y()) - a.y(),
                   baz = Rational(b.z()) - a.z();
    // Through a direction (through_direction): c is the direction, not a point.
    const Rational ax = f.by_direction() ? 0 : a.x(), ay = f.by_direction() ? 0 : a.y(),
                   az = f.by_direction() ? 0 : a.z();
    const Rational cax = Rational(c.x()) - ax, cay = Rational(c.y()) - ay, caz = Rational(c.z()) - az;
    const Rational pax = Rational(p.x()) - a.x(), pay = Rational(p.y()) - a.y(),
                   paz = Rational(p.z()) - a.z();
    v = -(bax * (cay * paz - caz * pay) - bay * (cax * paz - caz * pax) +
          baz * (cax * pay - cay * pax));
  } else {
    const Vec4& k = f.coefficients().coefficients;
    v = Rational(k[0]) * p.x() + Rational(k[1]) * p.y() + Rational(k[2]) * p.z() + k[3];
  }
  return f.negated() ? -v : v;
}

/// Cyrus–Beck in exact rational arithmetic, with the same conventions as clip_segment: the
/// exact maximum of the lower bounds and minimum of the upper bounds, ties to the first plane,
/// plane −1 for an end fixed at exactly 0 or 1.
struct ExactClip {
  bool visible = false;
  bool point = false;
  Rational t_low = 0, t_up = 1;
  int low_plane = -1, up_plane = -1;
};

inline ExactClip exact_clip(const ConvexClipper& clipper, const Vec3& p1, const Vec3& p2) {
  ExactClip r;
  for (int i = 0; i < clipper.plane_count(); ++i) {
    const Rational w = exact_value(clipper.plane(i), p1), e = exact_value(clipper.plane(i), p2);
    if (w < 0 && e < 0) return ExactClip{};
    if (w >= 0 && e >= 0) continue;
    if (w < 0) {
      if (e == 0) {
        r.t_low = 1;
        r.low_plane = -1;
      } else if (!(r.low_plane < 0 && r.t_low == 1)) {
        const Rational t = w / (w - e);
        if (r.low_plane < 0 || t > r.t_low) r.t_low = t, r.low_plane = i;
      }
    } else {
      if (w == 0) {
        r.t_up = 0;
        r.up_plane = -1;
      } else if (!(r.up_plane < 0 && r.t_up == 0)) {
        const Rational t = w / (w - e);
        if (r.up_plane < 0 || t < r.t_up) r.t_up = t, r.up_plane = i;
      }
    }
  }
  r.visible = r.t_low <= r.t_up;
  r.point = r.visible && (r.t_low == r.t_up || p1 == p2);
  return r;
}

inline double to_double(const Rational& q) { return CGAL::to_double(q); }

/// |computed point − exact point| for the point at parameter t (computed with point_at) and
/// the exact parameter, the difference taken exactly and rounded once.
inline double end_point_error(const Vec3& p1, const Vec3& p2, double t, const Rational& exact_t) {
  const Vec3 q = point_at(p1, p2, t);
  double sum = 0;
  for (int i = 0; i < 3; ++i) {
    const Rational exact = Rational(p1[i]) + (Rational(p2[i]) - p1[i]) * exact_t;
    const double d = to_double(Rational(q[i]) - exact);
    sum += d * d;
  }
  return std::sqrt(sum);
}

}  // namespace hedra::testing
