// The visible bodies of a scene flattened into one list of faces and triangles in world
// coordinates: what the raster passes, the shadow maps and the shadow-ray BVH work on.
#pragma once

#include <array>
#include <vector>

#include "hedra/scene/scene.h"

namespace hedra {

struct SceneGeometry {
  struct BodyRange {
    const SceneBody* body;
    int scene_index;  // index into Scene::bodies()
    int first_face, first_vertex;
  };
  /// A face: its body (index into `bodies`, i.e. into Scene::visible_bodies()) and its
  /// number in that body, outward unit normal, centroid, and whether it lies on the curved
  /// part of a smooth primitive (SmoothSurface::curved_face).
  struct FaceRef {
    int body, face;
    Vec3 outward, centroid;
    bool smooth;
  };
  /// A triangle of a face's triangulation (counter-clockwise seen from outside): global
  /// vertex indices, global face index, and the shading normal at each corner (the analytic
  /// normal on smooth faces, the face normal elsewhere, so real edges stay sharp).
  struct Tri {
    std::array<int, 3> v;
    int face;
    std::array<Vec3, 3> normal;
  };

  std::vector<BodyRange> bodies;
  std::vector<Vec3> positions;
  std::vector<FaceRef> faces;
  std::vector<Tri> triangles;
  /// Triangles of each face: face f owns triangles [triangle_begin[f], triangle_begin[f+1]).
  std::vector<int> triangle_begin;

  /// Builds the lists from Scene::visible_bodies(). Cost O(total size).
  static SceneGeometry of(const Scene& scene);
  /// Global index of face `face` of `bodies[body]`.
  int face_index(int body, int face) const { return bodies[body].first_face + face; }
  /// Index into `bodies` of Scene::bodies()[scene_index], −1 when that body is hidden.
  std::vector<int> body_of_scene_index;
  /// Bounding box of every vertex.
  Eigen::AlignedBox3d bbox() const;
};

}  // namespace hedra
