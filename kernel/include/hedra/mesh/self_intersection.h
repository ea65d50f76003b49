// Validation up front: does a surface intersect or touch itself away from the edges and
// vertices it is built from? A Body's constructor checks everything local (closed,
// consistently oriented, manifold edges and vertices, planar simple faces); this is the one
// global check, so that no later algorithm is asked about a polyhedron that does not exist.
//
// Cost: one CGAL box_intersection_d pass over the triangles' bounding boxes,
// O(n log³ n + k) for n triangles and k overlapping box pairs (k = O(n) for meshes whose
// triangles are small against the body: every tessellated primitive, every scan), plus one
// exact test per overlapping pair (filtered predicates, exact arithmetic only near
// degeneracy). Memory: about 80 bytes per triangle. Measured on a 986 048-triangle sphere
// (docs/io.md, "Validation"): 1.0–1.2 s of one core. Sequential, so the pair reported is the
// same on every run.
//
// Where it runs (docs/io.md, "Validation"): on every body read from a file (mesh files, a
// scene's "mesh" and "polyhedron" bodies, after their transform), so every command rejects a
// self-intersecting input with exit 3 before any algorithm sees it. Primitives are valid by
// construction (tests/core/primitives_test.cpp); Boolean results come from exact
// corefinement of valid operands and are not checked again (their cost is dominated by the
// Boolean itself, but a failure there would be hedra's bug, not the user's input).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "hedra/core/body.h"

namespace hedra {

/// Two faces (or triangles) whose point sets meet anywhere other than in the edges and
/// vertices the mesh says they share. face_a < face_b.
struct SelfIntersection {
  int face_a = -1, face_b = -1;
  /// A point of the intersection (rounded; for messages).
  Vec3 point = Vec3::Zero();
};

/// The first pair of faces of `body` that intersect or touch: two faces may only meet in the
/// edge or vertices they share, and two faces sharing an edge must not fold onto each other
/// (coplanar on the same side). Vertices at equal coordinates under different numbers count
/// as touching. Exact. std::nullopt for a valid body. Cost: see the file comment.
std::optional<SelfIntersection> find_self_intersection(const Body& body);

/// The same for an indexed triangle soup, each triangle its own face: two triangles may share
/// a vertex (and then meet only there) or an edge (and then not fold onto each other).
/// Degenerate (collinear) triangles are reported as intersecting themselves (face_a ==
/// face_b). Used for surfaces that are not bodies (open meshes) and by the tests.
std::optional<SelfIntersection> find_self_intersection(
    const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles);

/// "faces 3 and 17 intersect near (0.5, 0.25, 1)": the message part for an intersection.
std::string describe(const SelfIntersection& hit);

/// Throws InvalidInput("the surface intersects itself: faces … intersect near (…)") when
/// find_self_intersection(body) finds a pair.
void check_no_self_intersection(const Body& body);

}  // namespace hedra
