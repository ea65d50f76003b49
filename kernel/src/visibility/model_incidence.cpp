#include "visibility/model_incidence.h"

#include <algorithm>

namespace hedra::internal {

std::vector<int> rounded_face_planes(const Body& piece,
                                     const std::vector<std::pair<int, int>>& exact_faces,
                                     const InputPlanes& model) {
  std::vector<int> out(static_cast<size_t>(piece.face_count()), -1);
  if (model.empty()) return out;
  for (int g = 0; g < piece.face_count(); ++g) {
    const Vec3 normal = piece.plane(g).normal();  // unit, inner
    int best = -1;
    double best_dot = -2, second = -2;
    for (const auto& [c, sign] : exact_faces) {
      // The piece lies on c's negative side when sign is +1: its inner normal is −sign·n_c.
      const double dot = -sign * normal.dot(model.approx[static_cast<size_t>(c)].normal());
      if (dot > best_dot) {
        second = best_dot;
        best_dot = dot;
        best = c;
      } else {
        second = std::max(second, dot);
      }
    }
    if (best_dot >= 1 - 1e-10 && second < 1 - 1e-8) out[static_cast<size_t>(g)] = best;
  }
  return out;
}

bool volume_plane_through(const OcclusionVolume& volume, size_t i, const Body& piece,
                          const std::vector<int>& face_planes, const InputPlanes& model, int w,
                          const Vec3& q) {
  if (w < 0 || !volume.clipper || i >= volume.clipper->planes().size() || face_planes.empty())
    return false;
  const size_t fronts = volume.front_faces.size();
  if (i < fronts) {
    const int c = face_planes[static_cast<size_t>(volume.front_faces[i])];
    return c >= 0 && model.on(c, w, q);
  }
  const ExactPlane& f = volume.clipper->planes()[i];
  if (!f.by_points()) return false;
  const Vec3 &a = f.points()[0], &b = f.points()[1];
  const auto& corner = piece.vertices();
  for (const Edge& e : piece.edges()) {
    const Vec3 &x = corner[static_cast<size_t>(e.v0)], &y = corner[static_cast<size_t>(e.v1)];
    if (!((x == a && y == b) || (x == b && y == a))) continue;
    const int c1 = face_planes[static_cast<size_t>(e.left_face)];
    const int c2 = face_planes[static_cast<size_t>(e.right_face)];
    return c1 >= 0 && c2 >= 0 && model.on(c1, w, q) && model.on(c2, w, q);
  }
  return false;
}

bool exact_volume_plane_through(const OcclusionVolume& volume, size_t i, const ExactConvex& piece,
                                const InputPlanes& model, int w, const Vec3& q) {
  if (w < 0 || !volume.clipper || i >= volume.clipper->planes().size() || piece.canonical.size() != piece.faces.size())
    return false;
  const auto on = [&](int face) {
    const int c = piece.canonical[static_cast<size_t>(face)];
    return c >= 0 && model.on(c, w, q);
  };
  const auto& fronts = volume.front_faces;  // ascending (occlusion_volume)
  if (i < fronts.size()) return on(fronts[i]);
  const auto front = [&](int f) { return std::binary_search(fronts.begin(), fronts.end(), f); };
  size_t k = fronts.size();
  for (const auto& [a, b] : piece.edges) {
    if (front(a) == front(b)) continue;
    if (k++ == i) return on(a) && on(b);
  }
  return false;
}

}  // namespace hedra::internal
