// Every tolerance hedra uses lives here. Predicates are exact and need none; tolerances
// only serve methods that are approximate by nature (rounded coordinates after a transform,
// mesh import). Each is relative and scaled by the size of the data it applies to.
#pragma once

#include <limits>

namespace hedra {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

/// Planarity accepted for faces whose vertices were rounded by a computation (a rotation,
/// a tessellated sphere): distance from the face plane <= kRoundingPlanarity * scale, where
/// scale is the largest absolute vertex coordinate of the body (rounding error grows with
/// it) or its bounding-box diagonal, whichever is larger. 64 ulps: far above what one
/// transform leaves (a few ulps), far below anything a modeler would call a real bend.
constexpr double kRoundingPlanarity = 64 * kEpsilon;

/// Largest accepted |coordinate|. Volumes are cubes of coordinates and must stay finite
/// in double (1e300 would overflow), so bodies beyond this are rejected as invalid input.
constexpr double kMaxAbsCoordinate = 1e75;

/// Default relative tolerance for the course's translate-and-rotate convexity test, which
/// runs in floating point (it is the reference formulation, not the exact one):
/// |z| <= kRotationConvexityZero * scale counts as zero.
constexpr double kRotationConvexityZero = 1e-12;

/// Default precision ε of midpoint subdivision clipping (algorithms.md §3), relative: the CLI
/// uses ε = kMidpointEpsilon · scale (the clipper's Body::scale()). Bisection stops when the
/// bracket around an end is at most ε long: about 30 bisections per end on data of unit size,
/// far above the rounding of the midpoints themselves (~1e-16 · scale).
constexpr double kMidpointEpsilon = 1e-9;

}  // namespace hedra
