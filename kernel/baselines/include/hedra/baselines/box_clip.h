// The course's box clippers in 3D (docs/algorithms.md §3.3): Cohen–Sutherland and Liang–Barsky.
// Both are floating-point methods (the exact one is Cyrus–Beck on box_clipper(box)); they are
// kept as the course states them and checked against Cyrus–Beck in tests.
#pragma once

#include <optional>
#include <utility>

#include "hedra/baselines/outcodes.h"

namespace hedra {

/// Cohen–Sutherland in 3D: while the segment is neither trivially visible (both codes 0) nor
/// trivially invisible (logical product non-zero), move an end that is outside onto the plane
/// of its lowest set bit. Each new end is the intersection of the original line with that
/// plane, its coordinate along the plane's axis set exactly, so errors do not accumulate; a
/// bit that rounding sets again on an end already moved onto that plane is ignored (the end is
/// within rounding of it), so at most six moves per end. Returns the visible segment or
/// nullopt. \pre box.validate() passes. Cost O(1).
std::optional<std::pair<Vec3, Vec3>> cohen_sutherland(const ClipBox& box, const Vec3& p1,
                                                      const Vec3& p2);

/// Liang–Barsky in 3D: p(α) = (1 − α)·p1 + α·p2 (the same points as p1 + α·(p2 − p1));
/// for each face, q_k − α·p_k ≥ 0 inside; faces with p_k < 0 raise α_low, p_k > 0 lower
/// α_up, p_k = 0 with q_k < 0 reject. Intersection parameters are compared with the current
/// bounds without division (q_k against α·p_k); a division happens only when a bound moves.
/// Returns (α_low, α_up) or nullopt. \pre box.validate() passes. Cost O(1).
std::optional<std::pair<double, double>> liang_barsky(const ClipBox& box, const Vec3& p1,
                                                      const Vec3& p2);

}  // namespace hedra
