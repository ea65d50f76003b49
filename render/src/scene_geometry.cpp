#include "hedra/render/scene_geometry.h"

#include "hedra/core/parallel.h"

namespace hedra {

SceneGeometry SceneGeometry::of(const Scene& scene) {
  SceneGeometry g;
  g.body_of_scene_index.assign(scene.bodies().size(), -1);
  size_t faces = 0, triangles = 0, vertices = 0;
  for (const SceneBody* sb : scene.visible_bodies()) {
    faces += static_cast<size_t>(sb->body.face_count());
    triangles += sb->body.triangles().size();
    vertices += sb->body.vertices().size();
  }
  g.positions.reserve(vertices);
  g.faces.resize(faces);
  g.triangles.resize(triangles);
  g.triangle_begin.reserve(faces + 1);
  size_t next_triangle = 0;
  for (const SceneBody* sb : scene.visible_bodies()) {
    const int scene_index = static_cast<int>(sb - scene.bodies().data());
    const Body& body = sb->body;
    const int body_index = static_cast<int>(g.bodies.size());
    const int first_face = g.bodies.empty() ? 0 : g.bodies.back().first_face + g.bodies.back().body->body.face_count();
    const int first_vertex = static_cast<int>(g.positions.size());
    g.bodies.push_back({sb, scene_index, first_face, first_vertex});
    g.body_of_scene_index[scene_index] = body_index;
    g.positions.insert(g.positions.end(), body.vertices().begin(), body.vertices().end());
    // Triangles grouped by face, in their order within each face (a counting sort: Body::
    // triangles() lists them face by face, but the grouping does not rely on it).
    const size_t nf = static_cast<size_t>(body.face_count());
    const auto& all = body.triangles();
    std::vector<int> start(nf + 1, 0), order(all.size());
    for (const Triangle& t : all) ++start[static_cast<size_t>(t.face) + 1];
    for (size_t f = 0; f < nf; ++f) start[f + 1] += start[f];
    {
      std::vector<int> fill(start.begin(), start.end() - 1);
      for (size_t k = 0; k < all.size(); ++k) order[static_cast<size_t>(fill[static_cast<size_t>(all[k].face)]++)] = static_cast<int>(k);
    }
    for (size_t f = 0; f < nf; ++f) g.triangle_begin.push_back(static_cast<int>(next_triangle) + start[f]);
    // Faces and their triangles, each in its own place, in parallel.
    parallel_blocks(nf, 0, 1024, [&](size_t begin, size_t end) {
      for (size_t f = begin; f != end; ++f) {
        Vec3 centroid = Vec3::Zero();
        const std::vector<int>& outer = body.faces()[f].loops[0];
        for (int v : outer) centroid += body.vertices()[static_cast<size_t>(v)];
        centroid /= static_cast<double>(outer.size());
        const Vec3 outward = -body.inner_normal(static_cast<int>(f)).normalized();
        FaceRef& face = g.faces[static_cast<size_t>(first_face) + f];
        face = {body_index, static_cast<int>(f), outward, centroid, sb->surface.curved_face(outward)};
        for (int k = start[f]; k < start[f + 1]; ++k) {
          const Triangle& t = all[static_cast<size_t>(order[static_cast<size_t>(k)])];
          Tri& tri = g.triangles[next_triangle + static_cast<size_t>(k)];
          tri.face = first_face + static_cast<int>(f);
          for (int c = 0; c < 3; ++c) {
            tri.v[static_cast<size_t>(c)] = first_vertex + t.v[static_cast<size_t>(c)];
            tri.normal[static_cast<size_t>(c)] = face.smooth ? sb->surface.normal(body.vertices()[static_cast<size_t>(t.v[static_cast<size_t>(c)])], face.centroid)
                                                             : face.outward;
          }
        }
      }
    });
    next_triangle += all.size();
  }
  g.triangle_begin.push_back(static_cast<int>(g.triangles.size()));
  return g;
}

Eigen::AlignedBox3d SceneGeometry::bbox() const {
  Eigen::AlignedBox3d box;
  box.setEmpty();
  for (const Vec3& p : positions) box.extend(p);
  return box;
}

}  // namespace hedra
