#include "core/exact_solid.h"

#include <utility>

namespace hedra::internal {

std::shared_ptr<const ExactSolid> transformed(const ExactSolid& solid, const Transform& t) {
  using FT = ExactKernel::FT;
  const Mat4& m = t.matrix();
  auto out = std::make_shared<ExactSolid>();
  out->points.reserve(solid.points.size());
  for (const ExactKernel::Point_3& p : solid.points) {
    // Row-vector convention: x'_j = x·m(0, j) + y·m(1, j) + z·m(2, j) + m(3, j).
    std::array<FT, 3> q;
    for (int j = 0; j < 3; ++j) q[j] = p.x() * m(0, j) + p.y() * m(1, j) + p.z() * m(2, j) + m(3, j);
    out->points.emplace_back(q[0], q[1], q[2]);
  }
  out->triangles = solid.triangles;
  out->rounded = solid.rounded;
  if (t.linear_determinant() < 0)
    for (ExactSolid::Tri& tri : out->triangles) std::swap(tri.v[1], tri.v[2]);
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
  if (const auto& solid = body.exact_solid()) {
    std::vector<E3> e(solid->points.size());
    for (size_t i = 0; i < e.size(); ++i) {
      const auto& p = CGAL::exact(solid->points[i]);
      e[i] = {p.x(), p.y(), p.z()};
    }
    for (const ExactSolid::Tri& t : solid->triangles) add(e[t.v[0]], e[t.v[1]], e[t.v[2]]);
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
