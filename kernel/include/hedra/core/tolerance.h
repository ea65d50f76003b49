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

/// Largest accepted |coordinate|. Volumes are cubes of coordinates and must stay finite in
/// double: a bounding box (2e101)³ = 8e303 and sums of a few such terms do, 1e103 would not.
/// Products of higher degree (the centroid's moments, the predicates' filters) scale by powers
/// of two or fall back to exact arithmetic, so bodies from 1e-100 to 1e100 across work.
constexpr double kMaxAbsCoordinate = 1e101;

/// Default relative tolerance for the course's translate-and-rotate convexity test
/// (docs/algorithms.md §5.1), which runs in floating point (it is the reference formulation, not
/// the exact one): |z| <= kRotationConvexityZero * scale counts as zero.
constexpr double kRotationConvexityZero = 1e-12;

/// Default precision ε of midpoint subdivision clipping (docs/algorithms.md §3.4), relative: the
/// CLI uses ε = kMidpointEpsilon · scale (the clipper's Body::scale()). Bisection stops when the
/// bracket around an end is at most ε long: about 30 bisections per end on data of unit size, far
/// above the rounding of the midpoints themselves (~1e-16 · scale).
constexpr double kMidpointEpsilon = 1e-9;

/// Margin of the culling boxes of hidden-line removal (hedra/visibility/roberts.h), relative to the
/// size of the picture (or of the depth range): projections are rounded constructions, and a pair
/// is skipped only when its boxes are apart by more than this, far above their rounding (~1e-15
/// relative). It never changes a result, only which pairs are tested.
constexpr double kCullingMargin = 1e-9;

/// Joining the boundary pieces of a union of shadow polygons into rings
/// (hedra/visibility/polygon_union.h):
/// where three or more edges cross at one exact point, the rounded crossings of different
/// pairs of edges may differ by a few ulps, so an end with no start at its exact point is
/// joined to the nearest free start within kChainJoinTolerance × |coordinates|. Only the
/// rings' topology depends on it, never an area or a decision; beyond it the exact CGAL union
/// gives the rings.
constexpr double kChainJoinTolerance = 1e-12;

/// Rounding debris of shadow polygons (hedra/visibility/shadows.h): a face's shadow is the
/// union (or difference) of convex pieces clipped by rounded planes, so two crossings that are
/// one point in exact arithmetic can come out a few ulps apart, and where an occlusion volume
/// only touches a face a ring of no width can come out with an area of 1e-16. On output,
/// consecutive ring vertices closer than kShadowDebris × the scene's scale are one vertex, a
/// spike (the ring out and back along two edges that close) loses its tip, and a ring whose
/// mean width (2 · area / perimeter) is below that is dropped (a polygon whose outer
/// ring goes, with its holes); a polygon's own area moves by at most this × its perimeter.
/// A clipped piece that thin (an occlusion volume only touching the face) is dropped before
/// the union, so it adds to no area either; otherwise the areas (shadow_area,
/// visible_shadow_area, counts) are the unions' and do not depend on it.
constexpr double kShadowDebris = 1e-12;

/// Shadow rays of the raster renderer (hedra/render/ray_shadows.h): hits closer to the probe point
/// than kShadowRayOffset × the scene's bounding-box diagonal are ignored. The probe point is a
/// rounded construction on its face (a few ulps off the plane), and a ray leaving a facade's foot
/// could otherwise meet the ground it stands on at t ≈ 1e-16; the probe's own face is skipped
/// outright. Occluders nearer than this (1e-9 of the scene) are not seen.
constexpr double kShadowRayOffset = 1e-9;

/// Near clipping plane of a perspective raster view (hedra/render/raster_view.h), relative to the
/// distance from the eye to the farthest corner of the scene's box: geometry nearer to the
/// eye than that is cut away. Depth keys are −1/w, so it only bounds them; it is far below
/// anything a picture can show.
constexpr double kRasterNearPlane = 1e-5;

}  // namespace hedra
