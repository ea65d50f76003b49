// The brute-force stage 2 of Roberts' algorithm: the oracle that hidden_part is tested against.
#pragma once

#include <optional>

#include "hedra/visibility/roberts.h"

namespace hedra {

/// The course's stage 2 for one convex body (docs/algorithms.md §6.2), as written: with h_j(t, a) =
/// P(t)·V_j + a·g·V_j (g the viewer vector towards the eye: (−direction, 0) for a parallel view,
/// (eye, 1) for perspective), the hidden parameters are those t with some a ≥ 0 making every h_j >
/// 0. The n + 3 boundary lines (n faces, t = 0, t = 1, a = 0) are intersected pairwise, the
/// intersections that satisfy every inequality kept, and the hidden part is the open interval
/// between their least and greatest t when they span a region of positive area. Exact arithmetic
/// throughout (planes through the faces' support points); t rounded at the end. The reference
/// oracle of hidden_part. Cost O(n³).
std::optional<HiddenPart> hidden_part_brute_force(const Body& convex_body, const Viewpoint& view,
                                                  const Vec3& p1, const Vec3& p2);

}  // namespace hedra
