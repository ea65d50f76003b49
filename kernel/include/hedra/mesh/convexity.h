// Convexity test (docs/algorithms.md §5.1): is a body convex with respect to each of its faces?
#pragma once

#include <vector>

#include "hedra/core/body.h"

namespace hedra {

struct ConvexityReport {
  bool convex = false;
  /// All vertices lie in one plane: the "body" is flat (degenerate). Such data cannot form a
  /// Body; the raw overloads report it.
  bool flat = false;
  /// Faces some vertex lies strictly outside of (on the outer side of the face plane): the
  /// body is not convex with respect to them. Ascending.
  std::vector<int> nonconvex_faces;
};

/// Exact test, the "equivalent formulation" of the course: evaluate each face's plane at
/// every vertex not on the face through the exact predicate layer (Body::face_side).
/// Cost O(F·V).
ConvexityReport convexity(const Body& body);

/// The same exact test on raw, unvalidated data (so flat input can be reported as flat).
/// Faces use their outer loop. \pre indices in range; loops of at least 3 vertices.
ConvexityReport convexity(const std::vector<Vec3>& vertices, const std::vector<Face>& faces);

/// The course's own formulation, kept as a reference oracle: for each face, translate a
/// vertex of the face to the origin, rotate about OZ and OY so that an edge lies on the x
/// axis, rotate about OX so that the face lies in z = 0, and read the signs of z of all
/// vertices not on the face. Floating point: |z| <= zero_tolerance · scale counts as 0.
/// Cost O(F·V).
ConvexityReport convexity_by_rotation(const std::vector<Vec3>& vertices,
                                      const std::vector<Face>& faces,
                                      double zero_tolerance = -1);
ConvexityReport convexity_by_rotation(const Body& body);

}  // namespace hedra
