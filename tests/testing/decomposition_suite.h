// The decomposition suite of issue "Exact convex decomposition": shapes built in code, used by
// tests/decompose/decompose_test.cpp and bench/.
#pragma once

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "hedra/mesh/boolean.h"
#include "hedra/mesh/merge_coplanar.h"
#include "hedra/core/primitives.h"

namespace hedra::suite {

struct Shape {
  std::string name;
  Body body;
};

/// A box 2k+1 wide with k rectangular notches cut into its top (+y), extruded along z.
inline Body comb(int k) {
  Polygon2 p{{0, 0}, {2.0 * k + 1, 0}, {2.0 * k + 1, 3}};
  for (int i = k - 1; i >= 0; --i) {
    p.emplace_back(2.0 * i + 2, 3);
    p.emplace_back(2.0 * i + 2, 2);
    p.emplace_back(2.0 * i + 1, 2);
    p.emplace_back(2.0 * i + 1, 3);
  }
  p.emplace_back(0, 3);
  return prism(p, 0, 2);
}

inline Body staircase(int steps) {
  Polygon2 p{{0, 0}, {double(steps), 0}};
  for (int i = steps; i >= 1; --i) {
    p.emplace_back(i, i);
    p.emplace_back(i - 1, i);
  }
  return prism(p, 0, 3);
}

inline Polygon2 star(int points, double outer, double inner) {
  Polygon2 p;
  for (int i = 0; i < 2 * points; ++i) {
    const double r = i % 2 ? inner : outer, t = std::numbers::pi * i / points;
    p.emplace_back(r * std::cos(t), r * std::sin(t));
  }
  return p;
}

inline Body plate_with_holes(int n) {
  const double size = 2.0 * n + 1;
  std::vector<Polygon2> holes;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      holes.push_back({{1.0 + 2 * i, 1.0 + 2 * j}, {2.0 + 2 * i, 1.0 + 2 * j},
                       {2.0 + 2 * i, 2.0 + 2 * j}, {1.0 + 2 * i, 2.0 + 2 * j}});
  return prism({{0, 0}, {size, 0}, {size, size}, {0, size}}, 0, 1, holes);
}

inline Body cross3(double a, double length) {
  const double h = a / 2, l = length / 2;
  return unite(unite(box({-l, -h, -h}, {l, h, h}), box({-h, -l, -h}, {h, l, h})),
               box({-h, -h, -l}, {h, h, l}));
}

/// A generic rotation (not about a coordinate axis), about the body's centroid.
inline Body rotated(const Body& b) {
  return b.transformed(Transform::rotation({1, 2, 3}, 37, b.centroid()));
}

inline std::vector<Shape> shapes(bool with_large = true) {
  std::vector<Shape> s = {
      {"L prism", prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2)},
      {"comb 4", comb(4)},
      {"comb 16", comb(16)},
      {"box with hole", prism({{0, 0}, {4, 0}, {4, 3}, {0, 3}}, 0, 2, {{{1, 1}, {3, 1}, {3, 2}, {1, 2}}})},
      {"staircase 10", staircase(10)},
      {"star 8", prism(star(8, 2.5, 1), 0, 1)},
      {"thin star 8", prism(star(8, 2.5, 1), 0, 5.0 / 500)},
      {"cross", cross3(2, 6)},
      {"plate 5x5", plate_with_holes(5)},
      {"stacked boxes", unite(box({0, 0, 0}, {2, 2, 1}), box({0.5, 0.5, 1}, {1.5, 1.5, 2}))},
  };
  if (with_large) {
    s.push_back({"comb 64", comb(64)});
    s.push_back({"plate 10x10", plate_with_holes(10)});
  }
  return s;
}

/// The body as a float32 STL stores it: every vertex rounded to float32, every face fanned into
/// triangles, read back with exactly coplanar neighbours merged (bodies_from_soup). A rotated
/// body's quadrilaterals come back as two triangles planar only together within float rounding.
inline Body float32_soup(const Body& body) {
  PolygonSoup soup;
  for (const Vec3& p : body.vertices())
    soup.vertices.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  for (const Triangle& t : body.triangles()) soup.polygons.push_back({t.v[0], t.v[1], t.v[2]});
  return bodies_from_soup(soup).at(0);
}

/// A random star-shaped polygon of 5 … 12 corners, radii 0.6 … 2 (prisms of the random tests).
template <class Rng>
std::vector<Vec2> random_polygon(Rng& random) {
  std::uniform_real_distribution<double> u(0, 1);
  const int n = 5 + static_cast<int>(u(random) * 8);
  std::vector<Vec2> polygon;
  for (int i = 0; i < n; ++i) {
    const double angle = 2 * M_PI * (i + 0.8 * u(random)) / n, r = 0.6 + 1.4 * u(random);
    polygon.emplace_back(r * std::cos(angle), r * std::sin(angle));
  }
  return polygon;
}

/// Triangle soup of a body with every vertex moved by up to `delta` × its size: still a valid
/// body (triangles are planar), but coplanar faces are no longer coplanar (the perturbation
/// study of docs/benchmarks.md). The three offsets of a vertex are drawn z, y, x: the order the
/// study's inputs were first drawn in, kept so that the regression tests named after its
/// failures (tests/decompose/perturbed_test.cpp) get the same inputs from every compiler.
template <class Rng>
Body perturbed_soup(const Body& body, double delta, Rng& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> v = body.vertices();
  for (Vec3& p : v) {
    const double z = u(rng), y = u(rng), x = u(rng);
    p += delta * body.scale() * Vec3(x, y, z);
  }
  std::vector<Face> faces;
  for (const Triangle& t : body.triangles()) faces.push_back(Face{t.v[0], t.v[1], t.v[2]});
  BodyOptions o;
  o.planarity_tolerance = 1;  // triangles: planar by construction
  return Body(std::move(v), std::move(faces), o);
}

}  // namespace hedra::suite
