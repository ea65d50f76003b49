// Primitive solids. Flat-faced primitives are exact: built from the given coordinates
// without rounding, so their faces are exactly planar. Curved ones (cylinder, cone, sphere)
// are polyhedra whose tessellation follows a chordal tolerance: the largest distance between
// the true surface and the polyhedron, so no body has more faces than the tolerance needs
// (docs/primitives.md has the faces-vs-tolerance table).
#pragma once

#include <vector>

#include "hedra/core/body.h"
#include "hedra/core/error.h"

namespace hedra {

using Polygon2 = std::vector<Vec2>;

/// Most faces a curved primitive or a regular prism may have unless the caller allows more
/// (scene files: the "max_faces" key). It keeps a tiny input (a cylinder at tolerance 1e-12)
/// from building millions of faces.
constexpr int kDefaultMaxFaces = 100000;
/// Smallest chordal tolerance, relative to the radius, that a tessellation can honour: vertex
/// coordinates are rounded to about 1e-16 of the radius, so below this the requested error is
/// lost in rounding (and the side count would overflow). Tolerances below it are rejected.
constexpr double kMinRelativeTolerance = 1e-13;

/// A primitive needs more faces than the allowed maximum; the message names the shape, the
/// tolerance, the face count it would need and the limit.
class FaceBudgetExceeded : public InvalidInput {
 public:
  using InvalidInput::InvalidInput;
};

/// Axis-aligned box (docs/algorithms.md §1). Faces in the course's order: x = min, x = max, y =
/// min, y = max, z = min, z = max, so box({−1,−1,−1}, {1,1,1}).matrix() is the course's matrix.
/// \throw InvalidInput unless min < max in every coordinate.
Body box(const Vec3& min, const Vec3& max);

/// Prism: the simple polygon `outline` (convex or not, either orientation) with optional
/// polygonal holes, extruded from z = z0 to z = z1. Consecutive collinear outline vertices are
/// dropped (they would only split side faces). Faces: bottom, top, then one side face per
/// outline edge and per hole edge. \throw InvalidInput on self-crossing outlines, holes
/// outside the outline, holes touching the outline or each other, or z0 >= z1.
Body prism(const Polygon2& outline, double z0, double z1,
           const std::vector<Polygon2>& holes = {});

/// Pyramid over the polygon `base` at height z0 (convex or not) with apex `apex`
/// (apex.z() != z0). Faces: base, then one triangle per base edge.
Body pyramid(const Polygon2& base, double z0, const Vec3& apex);

/// Frustum (truncated pyramid): the pyramid over `base` at z0 with apex `apex`, cut by the
/// plane z = z1 strictly between z0 and apex.z(). Faces: base, top, then one side per edge.
/// The top's corners are computed: where one is not a double, the body is their rounding
/// (sides planar within rounding) and keeps the exact frustum (Body::exact_solid()), which
/// Booleans, moves and the exact decompositions use.
Body frustum(const Polygon2& base, double z0, const Vec3& apex, double z1);

/// Regular n-gon prism about the z axis with circumradius r, first vertex at angle 0.
/// \throw FaceBudgetExceeded when its n + 2 faces are more than `max_faces`.
Body regular_prism(int n, double r, double z0, double z1, int max_faces = kDefaultMaxFaces);

/// Number of segments of a regular polygon inscribed in a circle of radius r whose chordal
/// error r·(1 − cos(π/n)) is at most `tolerance` (at least 3). \throw InvalidInput when
/// tolerance < kMinRelativeTolerance·radius (not representable in doubles).
int segments_for_tolerance(double radius, double tolerance);

/// Cylinder about the z axis from z0 to z1, radius r, inscribed n-gon prism with the fewest
/// sides whose chordal error is at most `tolerance`. \throw FaceBudgetExceeded beyond
/// `max_faces` faces.
Body cylinder(double radius, double z0, double z1, double tolerance,
              int max_faces = kDefaultMaxFaces);

/// Cone: base circle of radius r at z0, apex (0, 0, z1); inscribed pyramid, chordal error at
/// most `tolerance`. \throw FaceBudgetExceeded beyond `max_faces` faces.
Body cone(double radius, double z0, double z1, double tolerance, int max_faces = kDefaultMaxFaces);

/// How far sphere() may move a vertex off the sphere, relative to the radius, so that every
/// face is exactly planar (2^-23).
constexpr double kSphereSnap = 1.0 / (1 << 23);

/// Sphere of radius r about `centre`: latitude–longitude polyhedron (quad bands, triangle
/// fans at the poles) with the fewest bands for which the largest distance from the sphere to
/// the polyhedron is at most `tolerance`. Every face is exactly planar: the vertices are
/// within kSphereSnap·r of the sphere, their coordinates about the centre rounded so that
/// each band's quadrilaterals are planar in exact arithmetic (docs/primitives.md). About a
/// centre within about 4r of the origin, with coordinates on the grid of the moved ones, they
/// are rounded to a grid that the move keeps exact, so the body is exactly planar as it is;
/// about another centre it is the sphere about the origin moved exactly (its rounded corners
/// are planar within rounding, its Body::exact_solid() exactly). Below a tolerance of 2·kSphereSnap·r the
/// vertices lie on the sphere to the last bit and the faces are planar within rounding.
/// \throw FaceBudgetExceeded beyond `max_faces` faces (2·rings² faces), InvalidInput below
/// kMinRelativeTolerance·radius. Cost O(rings²) to choose the rings.
Body sphere(const Vec3& centre, double radius, double tolerance, int max_faces = kDefaultMaxFaces);

/// The chordal error of the ideal latitude–longitude tessellation with `rings` latitude bands
/// (and 2·rings meridians, every vertex on the sphere): the largest distance from the sphere
/// to any face plane. sphere() adds kSphereSnap·r for its snapped vertices.
double sphere_chordal_error(double radius, int rings);

}  // namespace hedra
