// The contour of an interpolated function over a triangle: shared by the outlines of solids
// (outline.cpp) and of open surfaces (hidden_lines.cpp, Roberts::surface_outline).
#pragma once

#include <utility>

#include "hedra/core/plane.h"

namespace hedra::internal {

/// The segment of triangle (p[0], p[1], p[2]) where g, given at the corners and interpolated
/// linearly, changes sign (g ≥ 0 counting as positive): its ends on the two sides whose ends
/// differ in sign. Each crossing is interpolated from the side's end with the smaller `id`, so
/// that the triangle across the side, with the same ids, gets the same point. False (ends
/// untouched) when g has one sign. Cost O(1).
inline bool contour_segment(const Vec3* const p[3], const double g[3], const int id[3], Vec3 ends[2]) {
  const bool positive[3] = {g[0] >= 0, g[1] >= 0, g[2] >= 0};
  if (positive[0] == positive[1] && positive[1] == positive[2]) return false;
  int m = 0;
  for (int k = 0; k < 3; ++k) {
    int i = k, j = (k + 1) % 3;
    if (positive[i] == positive[j]) continue;
    if (id[j] < id[i]) std::swap(i, j);
    ends[m++] = *p[i] + (g[i] / (g[i] - g[j])) * (*p[j] - *p[i]);
  }
  return true;
}

}  // namespace hedra::internal
