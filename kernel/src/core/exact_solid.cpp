#include "core/exact_solid.h"

#include <utility>

#include "hedra/core/predicates.h"

namespace hedra::internal {

namespace {

using FT = ExactKernel::FT;
using P3 = ExactKernel::Point_3;

// p · m in the row-vector convention, exactly: x'_j = x·m(0, j) + y·m(1, j) + z·m(2, j) + m(3, j).
P3 image(const P3& p, const Mat4& m) {
  std::array<FT, 3> q;
  for (int j = 0; j < 3; ++j) q[j] = p.x() * m(0, j) + p.y() * m(1, j) + p.z() * m(2, j) + m(3, j);
  return P3(q[0], q[1], q[2]);
}

// Reverses every triangle (the image of a reflection keeps its faces outward).
void reverse(std::vector<ExactSolid::Tri>& triangles) {
  for (ExactSolid::Tri& tri : triangles) std::swap(tri.v[1], tri.v[2]);
}

}  // namespace

const ExactSolid& materialized(const ExactSolid& solid) {
  if (!solid.pending) return solid;
  std::call_once(solid.once, [&solid] {
    const ExactSolid::Pending& from = *solid.pending;
    auto out = std::make_shared<ExactSolid>();
    out->rounded = solid.rounded;
    out->points.reserve(from.corners->size());
    for (const Vec3& p : *from.corners) {
      P3 q(p.x(), p.y(), p.z());
      for (const Mat4& m : from.maps) q = image(q, m);
      out->points.push_back(std::move(q));
    }
    out->triangles = *from.triangles;
    if (from.reflected) reverse(out->triangles);
    solid.made = std::move(out);
  });
  return *solid.made;
}

std::shared_ptr<const ExactSolid> transformed(const ExactSolid& solid, const Transform& t) {
  auto out = std::make_shared<ExactSolid>();
  out->rounded = solid.rounded;
  if (solid.pending) {
    out->pending = solid.pending;
    out->pending->maps.push_back(t.matrix());
    if (t.linear_determinant() < 0) out->pending->reflected = !out->pending->reflected;
    return out;
  }
  out->points.reserve(solid.points.size());
  for (const P3& p : solid.points) out->points.push_back(image(p, t.matrix()));
  out->triangles = solid.triangles;
  out->body_vertex = solid.body_vertex;
  if (t.linear_determinant() < 0) reverse(out->triangles);
  return out;
}

std::shared_ptr<const ExactSolid> moved_exactly(const Body& body, const Transform& t) {
  const auto& v = body.vertices();
  for (int f = 0; f < body.face_count(); ++f) {
    const auto& loops = body.faces()[static_cast<size_t>(f)].loops;
    if (loops.size() == 1 && loops[0].size() == 3) continue;  // a triangle is planar
    const auto& s = body.support(f);
    for (const auto& loop : loops)
      for (int w : loop)
        if (orient3d(v[s[0]], v[s[1]], v[s[2]], v[w]) != Sign::Zero) return nullptr;
  }
  auto triangles = std::make_shared<std::vector<ExactSolid::Tri>>();
  triangles->reserve(body.triangles().size());
  for (const Triangle& tri : body.triangles()) triangles->push_back({tri.v, tri.face});
  auto out = std::make_shared<ExactSolid>();
  out->rounded = false;  // a moved double body, as any other (ExactSolid::rounded)
  out->pending = ExactSolid::Pending{std::make_shared<const std::vector<Vec3>>(body.vertices()), std::move(triangles),
                                     {t.matrix()}, t.linear_determinant() < 0};
  return out;
}

ExactKernel::FT::ET six_volume(const Body& body) {
  using ET = ExactKernel::FT::ET;
  ET sum = 0;
  // Summed in the exact number type: a lazy sum of many terms recurses once per term.
  using E3 = std::array<ET, 3>;
  const auto add = [&sum](const E3& a, const E3& b, const E3& c) {
    sum += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
           a[2] * (b[0] * c[1] - b[1] * c[0]);
  };
  if (body.exact_solid()) {
    const ExactSolid& solid = materialized(*body.exact_solid());
    std::vector<E3> e(solid.points.size());
    for (size_t i = 0; i < e.size(); ++i) {
      const auto& p = CGAL::exact(solid.points[i]);
      e[i] = {p.x(), p.y(), p.z()};
    }
    for (const ExactSolid::Tri& t : solid.triangles) add(e[t.v[0]], e[t.v[1]], e[t.v[2]]);
    return sum;
  }
  const auto& v = body.vertices();
  for (const Triangle& t : body.triangles()) {
    const Vec3 &p = v[t.v[0]], &q = v[t.v[1]], &r = v[t.v[2]];
    add(E3{p.x(), p.y(), p.z()}, E3{q.x(), q.y(), q.z()}, E3{r.x(), r.y(), r.z()});
  }
  return sum;
}

}  // namespace hedra::internal
