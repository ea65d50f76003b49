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

}  // namespace hedra
