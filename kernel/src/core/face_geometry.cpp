#include "hedra/core/face_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <CGAL/Exact_rational.h>

#include <cstdint>
#include <unordered_map>
#include <utility>

#include "hedra/core/predicates.h"

namespace hedra {

Vec3 newell_normal(const std::vector<Vec3>& vertices, const std::vector<int>& loop) {
  // Relative to the loop's first vertex (the sum is the same for any origin): with absolute
  // coordinates the sums p + q carry the face's distance from the origin and the products
  // cancel, so a real but thin face far from the origin (a triangle 1.5e-8 high at y = 1e8)
  // came out with a zero normal and was rejected as having zero area. The differences of
  // nearby vertices are exact or nearly so.
  Vec3 n = Vec3::Zero();
  const size_t k = loop.size();
  if (k == 0) return n;
  const Vec3& o = vertices[loop[0]];
  for (size_t i = 0; i < k; ++i) {
    const Vec3 p = vertices[loop[i]] - o;
    const Vec3 q = vertices[loop[(i + 1) % k]] - o;
    n.x() += (p.y() - q.y()) * (p.z() + q.z());
    n.y() += (p.z() - q.z()) * (p.x() + q.x());
    n.z() += (p.x() - q.x()) * (p.y() + q.y());
  }
  return n;
}

Vec3 oriented_normal(const std::vector<Vec3>& vertices, const std::vector<int>& loop) {
  const size_t k = loop.size();
  Vec3 n = newell_normal(vertices, loop);
  if (k < 3) return n;
  // Error bound of each centred Newell component: every term is a product of a rounded
  // difference and a rounded sum of differences (relative error ≤ 3u each) and the sum of k
  // terms adds ≤ (k − 1)u: |error| ≤ (k + 4)·u·Σ|term| (u = 2^-53), doubled for margin.
  const Vec3& o = vertices[loop[0]];
  Vec3 magnitude = Vec3::Zero();
  for (size_t i = 0; i < k; ++i) {
    const Vec3 p = vertices[loop[i]] - o;
    const Vec3 q = vertices[loop[(i + 1) % k]] - o;
    magnitude.x() += std::abs((p.y() - q.y()) * (p.z() + q.z()));
    magnitude.y() += std::abs((p.z() - q.z()) * (p.x() + q.x()));
    magnitude.z() += std::abs((p.x() - q.x()) * (p.y() + q.y()));
  }
  const double u = std::ldexp(1.0, -53);
  const double factor = 2 * (static_cast<double>(k) + 4) * u;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(n[axis]) > factor * magnitude[axis] && std::isfinite(n[axis])) continue;
    // Component `axis` of the area vector is the signed area of the loop projected on the
    // plane of the two other coordinates (a cyclic pair, so the sign matches).
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    int sign = 0;
    if (k == 3) {
      const auto proj = [&](int i) { return Vec2(vertices[loop[i]][a], vertices[loop[i]][b]); };
      const Sign s = orient2d(proj(0), proj(1), proj(2));
      sign = s == Sign::Positive ? 1 : s == Sign::Negative ? -1 : 0;
    } else {
      CGAL::Exact_rational sum = 0;
      for (size_t i = 0; i < k; ++i) {
        const Vec3& p = vertices[loop[i]];
        const Vec3& q = vertices[loop[(i + 1) % k]];
        sum += CGAL::Exact_rational(p[a]) * CGAL::Exact_rational(q[b]) -
               CGAL::Exact_rational(q[a]) * CGAL::Exact_rational(p[b]);
      }
      sign = CGAL::sign(sum);
    }
    const double size = std::max(std::abs(n[axis]), std::numeric_limits<double>::min());
    n[axis] = sign * size;
  }
  return n;
}

Vec3 newell_normal(const std::vector<Vec3>& vertices, const std::vector<std::vector<int>>& loops) {
  Vec3 n = Vec3::Zero();
  for (const auto& loop : loops) n += newell_normal(vertices, loop);
  return n;
}

std::array<int, 3> support_triple(const std::vector<Vec3>& vertices, const std::vector<int>& loop,
                                  const Vec3& normal) {
  if (loop.size() == 3) {
    // The triangle in its own order, from its lexicographically smallest vertex (exact).
    size_t first = 0;
    for (size_t i = 1; i < 3; ++i) {
      const Vec3& p = vertices[loop[i]];
      const Vec3& q = vertices[loop[first]];
      if (std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3)) first = i;
    }
    if (collinear(vertices[loop[0]], vertices[loop[1]], vertices[loop[2]])) return {loop[0], loop[1], -1};
    return {loop[first], loop[(first + 1) % 3], loop[(first + 2) % 3]};
  }
  auto lex_less = [&](int i, int j) {
    const Vec3& p = vertices[i];
    const Vec3& q = vertices[j];
    return std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3);
  };
  int a = loop[0];
  for (int v : loop)
    if (lex_less(v, a)) a = v;
  int b = -1;
  double best = -1;
  for (int v : loop) {
    double d = (vertices[v] - vertices[a]).squaredNorm();
    if (d > best) { best = d; b = v; }
  }
  int c = -1;
  best = 0;
  double signed_best = 0;
  const Vec3 ab = vertices[b] - vertices[a];
  for (int v : loop) {
    if (v == a || v == b) continue;
    double s = ab.cross(vertices[v] - vertices[a]).dot(normal);
    if (std::abs(s) > best) { best = std::abs(s); signed_best = s; c = v; }
  }
  // Keep (b − a) × (c − a) along the normal.
  if (signed_best < 0) std::swap(b, c);
  return {a, b, c};
}

double distance_from_plane(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  using Q = CGAL::Exact_rational;
  const auto diff = [](const Vec3& x, const Vec3& y) {
    return std::array<Q, 3>{Q(x.x()) - Q(y.x()), Q(x.y()) - Q(y.y()), Q(x.z()) - Q(y.z())};
  };
  const auto u = diff(b, a), w = diff(c, a), d = diff(p, a);
  const std::array<Q, 3> n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  const Q det = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
  const Q squared = det * det / (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  return std::sqrt(CGAL::to_double(squared));
}

std::string convex_face_defect(const std::vector<Vec3>& vertices, const std::vector<int>& loop,
                               double planarity, std::array<int, 3>* support, Vec3* normal,
                               bool* off_plane) {
  const size_t n = loop.size();
  if (off_plane) *off_plane = false;
  if (n < 3) return "has fewer than 3 vertices";
  const Vec3 outward = newell_normal(vertices, loop);
  if (normal) *normal = outward;
  const std::array<int, 3> s = support_triple(vertices, loop, outward);
  if (support) *support = s;
  const auto at = [&](int v) -> const Vec3& { return vertices[static_cast<size_t>(v)]; };
  if (s[2] < 0 || collinear(at(s[0]), at(s[1]), at(s[2]))) return "has zero area (its vertices are collinear)";
  // Exact: planar, and every corner turns the same way as the support triple (strictly convex).
  const Vec3 &a = at(s[0]), &b = at(s[1]), &c = at(s[2]);
  // A point well off the plane on the outward side (rounded: only its exact side matters).
  const Vec3 lift = a + outward.normalized() * (a.cwiseAbs().maxCoeff() + (b - a).norm() + 1);
  const Sign up = orient3d(a, b, c, lift);
  const Vec3 unit_normal = outward.normalized();
  for (size_t i = 0; i < n; ++i) {
    const Vec3& p = at(loop[i]);
    if (orient3d(a, b, c, p) != Sign::Zero) {
      if (!(planarity > 0 && (std::abs(unit_normal.dot(p - a)) <= planarity ||
                              distance_from_plane(a, b, c, p) <= planarity)))
        return "is not planar: vertex " + std::to_string(i) + " is off its plane";
      if (off_plane) *off_plane = true;
    }
    const Vec3& q = at(loop[(i + 1) % n]);
    const Vec3& r = at(loop[(i + 2) % n]);
    // The corner at q turns like (a, b, c): lift lies on the same side of (p, q, r).
    if (up == Sign::Zero || orient3d(p, q, r, lift) != up)
      return "is not strictly convex at vertex " + std::to_string((i + 1) % n);
  }
  // Turning the same way at every corner does not make a star polygon convex (a pentagram
  // winds twice). A convex one winds once: seen along the normal's largest axis, one of the
  // other coordinates rises and falls once round the loop, its steps changing sign twice
  // (signs of differences of doubles: exact).
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(outward[k]) > std::abs(outward[axis])) axis = k;
  const int across = (axis + 1) % 3;
  const auto step_sign = [&](size_t i) {
    const double step = at(loop[(i + 1) % n])[across] - at(loop[i])[across];
    return (step > 0) - (step < 0);
  };
  size_t first = 0;
  while (first < n && step_sign(first) == 0) ++first;
  int changes = 0;
  for (size_t k = 1, last = first; first < n && k <= n; ++k) {
    const size_t i = (first + k) % n;
    const int step = step_sign(i);
    if (step == 0) continue;
    changes += step != step_sign(last);
    last = i;
  }
  if (changes > 2) return "is not strictly convex: it winds round more than once (a star)";
  return {};
}

std::array<std::array<int, 3>, 2> convex_quad_split(const Vec3& q0, const Vec3& q1, const Vec3& q2,
                                                    const Vec3& q3) {
  if (orient3d(q0, q1, q2, q3) == Sign::Negative) return {{{0, 1, 2}, {2, 3, 0}}};
  return {{{1, 2, 3}, {3, 0, 1}}};
}

std::vector<std::array<int, 3>> convex_polygon_split(const std::vector<Vec3>& corners) {
  const int k = static_cast<int>(corners.size());
  if (k < 3) return {};
  // Strictly convex seen along the dominant axis of the Newell normal: exact 2D orientations on
  // the two kept coordinates, all the same sign and not zero.
  Vec3 n = Vec3::Zero();
  for (int i = 0; i < k; ++i)
    n += (corners[static_cast<size_t>(i)] - corners[0]).cross(corners[static_cast<size_t>((i + 1) % k)] - corners[0]);
  int axis = 0;
  n.cwiseAbs().maxCoeff(&axis);
  const auto flat = [&](int i) {
    const Vec3& p = corners[static_cast<size_t>(i)];
    return Vec2(p[(axis + 1) % 3], p[(axis + 2) % 3]);
  };
  const auto turn = [&](int a, int b, int c) { return orient2d(flat(a), flat(b), flat(c)); };
  const Sign way = turn(k - 1, 0, 1);
  if (way == Sign::Zero) return {};
  for (int i = 1; i < k; ++i)
    if (turn(i - 1, i, (i + 1) % k) != way) return {};
  if (k == 3) return {{0, 1, 2}};
  if (k == 4) {
    const auto s = convex_quad_split(corners[0], corners[1], corners[2], corners[3]);
    return {s[0], s[1]};
  }
  // The fan from corner 0, then Lawson's flips driven by a stack of diagonals to test. Triangle
  // t has corners tri[t] in the loop's turning order; `owner` maps each directed edge a → b of a
  // triangle to that triangle.
  const auto p = [&](int i) -> const Vec3& { return corners[static_cast<size_t>(i)]; };
  std::vector<std::array<int, 3>> tri;
  tri.reserve(static_cast<size_t>(k - 2));
  std::unordered_map<std::uint64_t, int> owner;
  owner.reserve(static_cast<size_t>(3 * k));
  const auto key = [](int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  };
  const auto add = [&](int t, const std::array<int, 3>& c) {
    tri[static_cast<size_t>(t)] = c;
    for (int e = 0; e < 3; ++e) owner[key(c[static_cast<size_t>(e)], c[static_cast<size_t>((e + 1) % 3)])] = t;
  };
  std::vector<std::pair<int, int>> stack;  // diagonals u → v (either direction) to test
  for (int i = 1; i + 1 < k; ++i) {
    tri.push_back({});
    add(i - 1, {0, i, i + 1});
    if (i > 1) stack.push_back({0, i});
  }
  const auto opposite = [&](int t, int a, int b) {
    for (int c : tri[static_cast<size_t>(t)])
      if (c != a && c != b) return c;
    return -1;
  };
  const auto side = [k](int a, int b) { return (b - a + k) % k == 1 || (a - b + k) % k == 1; };
  long flips = 0;
  const long limit = static_cast<long>(k) * k;
  while (!stack.empty()) {
    const auto [u, v] = stack.back();
    stack.pop_back();
    const auto a = owner.find(key(u, v)), b = owner.find(key(v, u));
    if (a == owner.end() || b == owner.end()) continue;  // flipped away since it was pushed
    const int t = a->second, s = b->second;
    const int w1 = opposite(t, u, v), w2 = opposite(s, v, u);
    // Triangle u v w1 (in turning order), its neighbour's far corner w2: convex or flat there
    // when w2 is not strictly outside the triangle's plane.
    if (orient3d(p(u), p(v), p(w1), p(w2)) != Sign::Positive) continue;
    if (++flips > limit) return {};
    // The quadrilateral v w1 u w2 takes the other diagonal, w1–w2.
    owner.erase(key(u, v));
    owner.erase(key(v, u));
    add(t, {w1, u, w2});
    add(s, {w2, v, w1});
    for (const auto& [x, y] : {std::pair{w1, u}, std::pair{u, w2}, std::pair{w2, v}, std::pair{v, w1}})
      if (!side(x, y)) stack.push_back({x, y});
  }
  return tri;
}

}  // namespace hedra
