// Internal: the exact solid a rounded body stands for (docs/design.md, "Exact inside, rounded
// only at the edge"). A Boolean's result is an exact triangle mesh with rational corners
// (CGAL's corefinement on Epeck); the Body its caller gets has those corners rounded to
// double, once. The body keeps the exact mesh (Body::exact_solid()), so that what is built on
// it next — another Boolean, an affine move, an exact volume — starts from the exact solid,
// not from its rounding.
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <array>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hedra/core/body.h"
#include "core/primitive_solids.h"

namespace hedra::internal {

using ExactKernel = CGAL::Exact_predicates_exact_constructions_kernel;

/// A closed, consistently oriented triangle mesh with exact corners. Immutable once attached.
/// Either made (points, triangles), or pending: the exact image of a double body's corners
/// under a chain of affine maps (a body with exactly planar faces moved by transformed()),
/// made on first use by materialized(), so that moving a large mesh costs nothing until a
/// Boolean needs its exact corners.
struct ExactSolid {
  struct Tri {
    std::array<int, 3> v;  // counter-clockwise seen from outside
    int face;              // the body's face this triangle rounds into
  };
  std::vector<ExactKernel::Point_3> points;
  std::vector<Tri> triangles;
  /// Per point: the body vertex it rounds to, −1 for a point the body dropped (one only
  /// splitting an edge of the body). Empty: point i is vertex i (a pending image, and a Boolean
  /// whose body kept every point). Kept through affine moves, which keep the body's vertex
  /// order. What lets a consumer of the solid's decomposition decide incidence with the rounded
  /// body's vertices by construction (Decomposition::planes).
  std::vector<int> body_vertex;
  struct Pending {
    // The double corners and triangles of the body first moved (exactly planar faces, no
    // solid of its own), shared by every later move; not the body, whose derived data
    // (edges, planes, matrix) would stay alive with its moved copies.
    std::shared_ptr<const std::vector<Vec3>> corners;
    std::shared_ptr<const std::vector<Tri>> triangles;
    std::vector<Mat4> maps;  // applied in order (row-vector convention)
    bool reflected = false;  // an odd number of the maps reverse orientation
  };
  std::optional<Pending> pending;
  mutable std::once_flag once;
  mutable std::shared_ptr<const ExactSolid> made;  // the pending image, once materialized
  /// Whether the Boolean (or the frustum()) that made this solid rounded a corner of its body
  /// (a corner here that is not a double). Else the Boolean's body has this solid's corners exactly (the points only
  /// the solid keeps lie on straight edges between its faces), and an affine move of it is a
  /// moved double body like any other. Kept through affine moves.
  bool rounded = true;
};

/// The solid with its corners: `solid` itself, or its pending image, made once (thread-safe).
/// Cost O(n) lazy exact operations the first time.
const ExactSolid& materialized(const ExactSolid& solid);

/// Attaches `solid` to a body made from it (its rounding) and not yet shared with anyone.
/// \pre body's geometry is not shared (a freshly built body).
void attach_exact_solid(Body& body, std::shared_ptr<const ExactSolid> solid);

/// The exact image of `solid` under the affine map `t` (row-vector convention, as
/// Transform): every corner mapped in exact arithmetic; loops reversed for reflections.
/// A pending solid stays pending, with `t` appended. \pre t.is_affine(). Cost O(n) lazy exact
/// operations for a made solid, O(maps) for a pending one.
std::shared_ptr<const ExactSolid> transformed(const ExactSolid& solid, const Transform& t);

/// The pending exact image of `body` (double corners, no solid) under `t`, or null where a
/// face is not exactly planar (its exact image would not be planar either: a tessellated
/// sphere's quadrilaterals). \pre t.is_affine(). Cost O(corners of the faces that are not
/// triangles) exact orientation tests.
std::shared_ptr<const ExactSolid> moved_exactly(const Body& body, const Transform& t);

/// The plane solid of a body whose faces are planar only within rounding (Body::faces_off_plane():
/// a rotated part written as doubles to OFF, OBJ or PLY, which has no exact solid of its own):
/// the exactly planar solid within rounding of it. The faces are grouped into planes — a face
/// joins the first plane met before (in face order) that has the same orientation and all its
/// vertices within the rounding guard (kRoundingPlanarity × scale), else makes its own, exact,
/// through its support triple — and each vertex lying on one of its planes only within the
/// guard is replaced by the exact point where its planes meet: the three with the
/// best-conditioned normals where it has three or more, each other one required to pass through
/// that point exactly; the foot of the perpendicular on the line of two planes, or on the plane
/// of one. Every other vertex stays the body's double, exactly on its planes already. Every face
/// is then exactly planar, and its triangles (Body::triangles()) are the solid's; point i stands
/// for vertex i (body_vertex empty); `rounded` is set.
/// nullptr where there is no such solid within rounding: planes that do not meet in one point
/// at a vertex (a rotated torus's quadrilaterals, four planes at every vertex), a vertex moved by
/// more than 16 guards, or a triangle turned over or flattened by the moves; and for a body with
/// exactly planar faces, or two-sided. Cost O(V + T) lazy exact constructions and orientation
/// tests (O(F) normal-cell lookups for the planes); it gives up at the first vertex that fails.
/// Decompose takes it (DecomposeOptions::from_exact_solid). Booleans do not: with it, 25 rotated
/// cylinders read back subtracted in turn from a rotated slab read back took 5.6 s instead of
/// 2.4 s, and the result's decomposition 1.7 s instead of 0.28 s, for the same drawing; they
/// take such a body's triangles, which are exact too.
std::shared_ptr<const ExactSolid> plane_solid(const Body& body);

/// The solid as bytes (Body::exact_solid_bytes()), and back for `body`, a body with the same
/// vertices and faces as the one written: "HXS1", then whether the Boolean rounded a corner and
/// whether the solid is pending; a pending image as its first body's double corners,
/// triangles, maps (16 doubles each) and whether they reflect; a made solid as its corners (three
/// exact rationals each, as text in base 16), triangles and ExactSolid::body_vertex. Counts are
/// 64-bit, indices 32-bit, all little-endian. Reading checks every count against what is left
/// and every index against the solid's points and `body`'s vertices and faces.
/// \throw InvalidInput (reading). Cost O(n).
std::string exact_solid_bytes(const ExactSolid& solid);
std::shared_ptr<const ExactSolid> exact_solid_from_bytes(std::string_view bytes, const Body& body);

/// Six times the exact volume: of the body's exact solid where it carries one, else of its
/// triangles with their double corners. Cost O(T) exact operations.
ExactKernel::FT::ET six_volume(const Body& body);

}  // namespace hedra::internal
