// Splitting a body by a plane, exactly.
#pragma once

#include <vector>

#include "hedra/core/body.h"

namespace hedra {

/// The closed parts of a body on each side of a plane; cut faces are capped.
struct SplitResult {
  std::vector<Body> below;  // where plane.value(p) < 0 (each connected component one body)
  std::vector<Body> above;  // where plane.value(p) > 0
};

/// Splits `body` by `plane` (its stored double coefficients taken as exact). Every side
/// decision is exact; new vertices are exact intersections of input edges with the plane,
/// rounded to double only in the returned bodies. A plane through vertices, edges or whole
/// faces creates no slivers: faces in the plane go to the side the solid lies on. Implemented
/// in decompose.cpp, which holds the exact machinery (one CGAL-heavy translation unit).
/// \throw InvalidInput if the plane's normal is zero. Cost O(n log n) for n triangles.
SplitResult split(const Body& body, const Plane& plane);

}  // namespace hedra
