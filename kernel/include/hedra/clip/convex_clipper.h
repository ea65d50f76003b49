// A convex clipping volume prepared for clipping segments and polygons: the closed
// intersection of the inner half-spaces of its planes (docs/algorithms.md §3–4).
#pragma once

#include <vector>

#include "hedra/core/body.h"
#include "hedra/core/predicates.h"
#include "hedra/core/transform.h"

namespace hedra {

/// The clipper of Cyrus–Beck, batch and polygon clipping: a list of oriented exact planes whose
/// closed inner half-spaces intersect in the clipping volume. The volume may be unbounded (an
/// occlusion volume) or empty; clipping is still well defined. Value type.
class ConvexClipper {
 public:
  /// One plane per face of a convex body, in face order, each through the face's support
  /// triple, so every side decision equals Body::face_side exactly and segments along the
  /// body's own edges or through its own vertices are clipped exactly.
  /// \throw InvalidInput "the clipper is not convex: vertices lie outside the planes of faces
  ///   4, 5" when the body is not convex (docs/algorithms.md §4, step 2). Cost O(F·V) for the exact
  ///   convexity test.
  explicit ConvexClipper(const Body& body);

  /// The columns (a, b, c, d) of a body matrix (interior: a·x + b·y + c·z + d ≥ 0), each
  /// taken as exact. Any matrix describes a convex volume, so nothing is checked beyond the
  /// columns themselves. \throw InvalidInput for a non-finite column or a zero normal,
  /// naming the column. Cost O(n).
  static ConvexClipper from_matrix(const BodyMatrix& matrix);

  /// Planes built by the caller (frusta, occlusion volumes). \throw InvalidInput if empty.
  static ConvexClipper from_planes(std::vector<ExactPlane> planes);

  int plane_count() const { return static_cast<int>(planes_.size()); }
  const ExactPlane& plane(int i) const { return planes_[static_cast<size_t>(i)]; }
  const std::vector<ExactPlane>& planes() const { return planes_; }
  /// The size tolerances refer to: Body::scale() of the body it was built from, 0 for planes.
  double scale() const { return scale_; }

  /// Exact: p lies in the closed clipping volume (no plane Negative). Cost O(planes).
  bool contains(const Vec3& p) const;

 private:
  ConvexClipper() = default;
  std::vector<ExactPlane> planes_;
  double scale_ = 0;
};

}  // namespace hedra
