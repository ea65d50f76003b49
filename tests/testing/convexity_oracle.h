// The course's definition of a convex body, kept as the test oracle of is_convex() and
// convexity(): evaluate each face's support plane at every vertex not on the face, exactly.
// Cost O(F·V).
#pragma once

#include <vector>

#include "hedra/core/body.h"

namespace hedra::testing {

/// Faces some vertex not on them lies strictly outside of, ascending. Cost O(F·V).
inline std::vector<int> nonconvex_faces_oracle(const Body& body) {
  std::vector<int> out;
  const auto& vertices = body.vertices();
  for (int f = 0; f < body.face_count(); ++f) {
    std::vector<char> on(vertices.size(), 0);
    for (const auto& loop : body.faces()[static_cast<size_t>(f)].loops)
      for (int v : loop) on[static_cast<size_t>(v)] = 1;
    for (size_t v = 0; v < vertices.size(); ++v)
      if (!on[v] && body.face_side(f, vertices[v]) == Sign::Negative) {
        out.push_back(f);
        break;
      }
  }
  return out;
}

}  // namespace hedra::testing
