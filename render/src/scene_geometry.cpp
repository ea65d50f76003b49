#include "hedra/render/scene_geometry.h"

namespace hedra {

SceneGeometry SceneGeometry::of(const Scene& scene) {
  SceneGeometry g;
  g.body_of_scene_index.assign(scene.bodies().size(), -1);
  for (const SceneBody* sb : scene.visible_bodies()) {
    const int scene_index = static_cast<int>(sb - scene.bodies().data());
    const Body& body = sb->body;
    const int body_index = static_cast<int>(g.bodies.size());
    const int first_face = static_cast<int>(g.faces.size());
    const int first_vertex = static_cast<int>(g.positions.size());
    g.bodies.push_back({sb, scene_index, first_face, first_vertex});
    g.body_of_scene_index[scene_index] = body_index;
    g.positions.insert(g.positions.end(), body.vertices().begin(), body.vertices().end());
    for (int f = 0; f < body.face_count(); ++f) {
      Vec3 centroid = Vec3::Zero();
      const std::vector<int>& outer = body.faces()[f].loops[0];
      for (int v : outer) centroid += body.vertices()[v];
      centroid /= static_cast<double>(outer.size());
      const Vec3 outward = -body.inner_normal(f).normalized();
      g.faces.push_back({body_index, f, outward, centroid, sb->surface.curved_face(outward)});
    }
    // Triangles grouped by face (Body::triangles() lists them face by face, but sort to be
    // independent of that).
    std::vector<std::vector<const Triangle*>> by_face(body.face_count());
    for (const Triangle& t : body.triangles()) by_face[t.face].push_back(&t);
    for (int f = 0; f < body.face_count(); ++f) {
      g.triangle_begin.push_back(static_cast<int>(g.triangles.size()));
      const FaceRef& face = g.faces[first_face + f];
      for (const Triangle* t : by_face[f]) {
        Tri tri;
        tri.face = first_face + f;
        for (int k = 0; k < 3; ++k) {
          tri.v[k] = first_vertex + t->v[k];
          tri.normal[k] = face.smooth ? sb->surface.normal(body.vertices()[t->v[k]], face.centroid)
                                      : face.outward;
        }
        g.triangles.push_back(tri);
      }
    }
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
