// Shadow probes (docs/algorithms.md §7.5, ray tracing): from a visible point, a ray towards the
// light; any face in between means shadow. A bounding-volume hierarchy over the scene's triangles
// (binned surface-area heuristic) keeps each probe O(log triangles).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "hedra/render/scene_geometry.h"

namespace hedra {

class ShadowBvh {
 public:
  /// Builds the hierarchy over every triangle of the geometry. Cost O(n log n).
  explicit ShadowBvh(const SceneGeometry& geometry);

  /// Whether a triangle of any face other than `skip_face` meets the ray origin + t·dir for
  /// t_min < t < t_max (triangle edges included, so a ray through an edge shared inside a
  /// face cannot slip between its triangles). A probe from a point of a planar face cannot
  /// meet that face again, so skipping it removes self-intersection without an offset;
  /// t_min only absorbs the rounding of the origin against neighbouring faces.
  /// Cost O(log n) typical.
  bool occluded(const Vec3& origin, const Vec3& dir, double t_min, double t_max,
                int skip_face) const;

  int node_count() const { return static_cast<int>(nodes_.size()); }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int32_t first;  // leaf: first triangle in order_; inner: right child (left = this + 1)
    int32_t count;  // leaf: triangles; inner: 0
  };
  struct Triangle {
    Vec3 a, e1, e2;
    int face;
  };
  std::vector<Node> nodes_;
  std::vector<Triangle> triangles_;  // in leaf order
};

}  // namespace hedra
