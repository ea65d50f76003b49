// Internal: the exact solids primitives attach to the bodies they build (docs/primitives.md),
// declared apart from core/exact_solid.h so that primitives.cpp stays free of CGAL's exact
// kernel; defined in exact_solid.cpp.
#pragma once

#include <vector>

#include "hedra/core/body.h"

namespace hedra::internal {

/// Attaches to a freshly built frustum (frustum(): vertices 0..k−1 its base at z0, k..2k−1
/// its top at z1) the exact frustum: the top's corners are the base's moved towards `apex` by
/// the fraction (z1 − z0)/(apex.z − z0) in exact arithmetic, which the body's top corners round
/// (its sides are then planar only within rounding, the solid's exactly). Nothing where every
/// exact corner is a double (the body is its solid). Cost O(k) exact operations.
void attach_frustum_solid(Body& body, const Vec3& apex, double z0, double z1);

/// Attaches to a freshly built body whose vertices are `corners` + `offset` rounded, and whose
/// faces on `corners` are exactly planar (the caller's construction: sphere()), the pending
/// exact image of `corners` translated by `offset`: what transformed() would attach, without
/// a second body or the planarity tests. Cost O(n) copies.
void attach_translated_image(Body& body, std::vector<Vec3> corners, const Vec3& offset);

}  // namespace hedra::internal
