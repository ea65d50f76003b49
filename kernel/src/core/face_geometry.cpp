#include "hedra/core/face_geometry.h"

#include <cmath>
#include <utility>

namespace hedra {

Vec3 newell_normal(const std::vector<Vec3>& vertices, const std::vector<int>& loop) {
  Vec3 n = Vec3::Zero();
  const size_t k = loop.size();
  for (size_t i = 0; i < k; ++i) {
    const Vec3& p = vertices[loop[i]];
    const Vec3& q = vertices[loop[(i + 1) % k]];
    n.x() += (p.y() - q.y()) * (p.z() + q.z());
    n.y() += (p.z() - q.z()) * (p.x() + q.x());
    n.z() += (p.x() - q.x()) * (p.y() + q.y());
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

}  // namespace hedra
