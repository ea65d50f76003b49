// Geometry of one planar face given as loops of vertex indices: Newell normal and the
// three vertices that carry its exact supporting plane.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "hedra/core/plane.h"

namespace hedra {

/// Newell's area vector of the loops (outer and holes together): its direction is the
/// right-hand normal of the outer loop, its length twice the face area. Cost O(k).
Vec3 newell_normal(const std::vector<Vec3>& vertices, const std::vector<std::vector<int>>& loops);

/// Newell's area vector of one loop.
Vec3 newell_normal(const std::vector<Vec3>& vertices, const std::vector<int>& loop);

/// Newell's area vector of one loop with every component's sign exact: where the rounded
/// sum cannot be trusted (a sliver triangle, 1e-17 of its size wide: a rotated vertex an ulp
/// off an edge, written to a file and read back), the sign comes from the exact projected
/// area (orient2d for a triangle, exact rationals otherwise) and a component the rounding
/// made zero or flipped gets that sign and the smallest normal magnitude. Its direction is
/// then only as good as the rounding allows, but it never points to the wrong side of a
/// coordinate plane, so dot products with a parallel normal have the exact sign. Cost O(k),
/// O(k) exact rational operations in the rare uncertain case.
Vec3 oriented_normal(const std::vector<Vec3>& vertices, const std::vector<int>& loop);

/// Three vertices (a, b, c) of `loop` with (b − a) × (c − a) pointing along `normal` and
/// within a constant factor of the best-conditioned choice: a is the lexicographically
/// smallest vertex, b the farthest from a, c maximises |area| along `normal` (b and c swapped when
/// needed so the triple turns the normal's way). For exactly
/// coplanar vertices every non-degenerate triple defines the same plane; for rounded ones this
/// fixes one, deterministically. A triangle is its own triple, in its own (exact) turning
/// order, whatever `normal` says. Cost O(k). Returns c = −1 when every vertex is collinear
/// with a and b (in floating point).
std::array<int, 3> support_triple(const std::vector<Vec3>& vertices, const std::vector<int>& loop,
                                  const Vec3& normal);

/// A quadrilateral q0 q1 q2 q3 planar only within rounding as two triangles (positions 0…3 in
/// its loop, each in the loop's turning order), cut along the diagonal that keeps the surface
/// convex there: q0–q2 where q3 lies strictly on the inner side of the plane of q0, q1, q2
/// (orient3d(q0, q1, q2, q3) < 0), else q1–q3. The one rule of the convexity certificate's split
/// and of the exact occluders and receivers of hidden lines and shadows (exactly_planar_convex,
/// shadows' faces); Body::triangles() triangulates the face without it. Exact; cost O(1).
std::array<std::array<int, 3>, 2> convex_quad_split(const Vec3& q0, const Vec3& q1, const Vec3& q2,
                                                    const Vec3& q3);

/// Distance of p from the plane through a, b, c (not collinear), to double precision: the
/// determinant and the normal's squared length in exact rationals, one rounding at the end.
/// The planarity checks take it where the floating-point distance from a face's fitted plane
/// exceeds their tolerance: that plane tilts by about ε · length / width on a long thin face
/// (a fine cylinder's side, moved). Cost O(1) rational operations.
double distance_from_plane(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p);

/// A convex polygon planar only within rounding (a rotated cylinder's cap read back from a
/// file) as triangles (positions in its loop, each in the loop's turning order) whose surface
/// is convex toward the outside: every diagonal between two triangles has the far corner of the
/// one on the inner side of the other's plane or on it (orient3d(a, b, c, d) ≤ 0 for a triangle
/// a b c and the far corner d of its neighbour), so the triangles are the outer side of the
/// convex hull of the corners, the one polyhedral surface through them that a convex body can
/// have. Quadrilaterals: convex_quad_split. Larger polygons: a fan, then Lawson's flips of the
/// diagonals that fold outward; in a strictly convex polygon every flip is legal and, as for
/// Delaunay flips under the lifting map, they end at the locally, hence globally, convex
/// surface. Empty when the polygon, projected along its dominant normal axis, is not strictly
/// convex (every corner turning as the first does), or the flips have not ended after k² (they
/// never need that many on a strictly convex polygon). Exact; cost O(k) orient2d, then O(k)
/// orient3d and hashed edge lookups plus O(1) a flip, at most k² flips (a handful per diagonal
/// on rotated caps).
std::vector<std::array<int, 3>> convex_polygon_split(const std::vector<Vec3>& corners);

/// Why `loop` is not a two-sided convex face (Body::two_sided_polygon, Body::two_sided_surface):
/// empty when its corners are exactly coplanar (or, with `planarity` > 0, each within that
/// distance of the plane of its support triple) and it is strictly convex (every corner turns
/// as the support triple does); else "has zero area (its vertices are collinear)", "is not
/// planar: vertex i is off its plane" or "is not strictly convex at vertex i", i the position
/// in the loop. The support triple goes to `support`, the Newell normal to `normal`, and to
/// `off_plane` whether a corner lies off the support triple's plane (accepted within
/// `planarity`: Body::faces_off_plane()). Exact predicates; cost O(k).
std::string convex_face_defect(const std::vector<Vec3>& vertices, const std::vector<int>& loop,
                               double planarity, std::array<int, 3>* support = nullptr,
                               Vec3* normal = nullptr, bool* off_plane = nullptr);

}  // namespace hedra
