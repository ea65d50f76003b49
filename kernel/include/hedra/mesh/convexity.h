// Convexity test (docs/algorithms.md §5.1): is a body convex with respect to each of its faces?
#pragma once

#include <optional>
#include <vector>

#include "hedra/core/body.h"

namespace hedra {

struct ConvexityReport {
  bool convex = false;
  /// All vertices lie in one plane: the "body" is flat (degenerate). Such data cannot form a
  /// Body; the raw overloads report it.
  bool flat = false;
  /// Faces some vertex lies strictly outside of (on the outer side of the face plane): the
  /// body is not convex with respect to them. Ascending.
  std::vector<int> nonconvex_faces;
};

/// Whether the body is convex in the sense of the course's definition: no vertex lies strictly
/// on the outer side of the supporting plane (Body::support) of a face it is not on. Exact.
///
/// Decided from a certificate in O(V + E) exact predicates (Mehlhorn et al., "Checking
/// geometric programs or verification of geometric structures", CGTA 1999, §5): (1) every
/// edge is locally convex (the dihedral sign from orient3d of one face's support triple and a
/// vertex of the neighbour on the neighbour's side of the edge; coplanar neighbours must not
/// fold back); (2) a centre point o lies strictly on the inner side of every face plane;
/// (3) the surface winds exactly once around o: given (1) and (2), the central projection
/// from o onto the sphere of directions is a covering, branched at most at vertices, so a ray
/// from o crosses as many faces as the surface winds; one ray's crossings are counted with
/// exact orientations (when the ray meets an edge or a corner, the total signed solid angle
/// seen from o, 4π, is summed in floating point with a bound on its error). This rules out
/// surfaces that are locally convex but wound twice around o. Then the
/// solid is star-shaped about o and locally convex everywhere, hence convex (Tietze–Nakajima).
/// Faces rounded off their plane (a rotated body, a tessellated sphere) are checked as two
/// triangles (quadrilaterals: one orientation decides planarity and the convex diagonal) plus
/// a local search that relates the face's support plane to the convex surface: none when the
/// support triple is one of the two triangles, else the faces around the face's own vertices
/// outside that plane. A strictly reflex edge proves non-convexity at once. Cases the certificate
/// does not settle (rounded faces of five or more vertices, a centre on a face plane, folded
/// coplanar faces) fall back to the definition evaluated through the convex hull (see
/// convexity()), so the answer is always exact.
/// Cost O(V + E) when certified; O(V log V + Σ hull degrees) in the fallback, plus O(V) per
/// face with a rounded vertex of its own outside its plane.
/// The one convexity test of hedra's visibility passes (hidden lines, shadows). Decided once
/// per body: later calls on it or its copies read the verdict back (Body::convexity_memo), O(1).
bool is_convex(const Body& body);

/// What the O(V + E) certificate of is_convex() alone settles.
enum class ConvexityCertificate { Convex, NotConvex, Undecided };

/// The certificate of is_convex() without the fallback: Convex and NotConvex are exact
/// verdicts; Undecided leaves the body to the definition. Cost O(V + E).
ConvexityCertificate certify_convexity(const Body& body);

namespace internal {
/// certify_convexity() counting the surface's degree about its centre along `ray` instead of
/// the direction it picks (tests: a ray through an edge or a corner takes the floating-point
/// winding sum instead).
ConvexityCertificate certify_convexity_along(const Body& body, const std::optional<Vec3>& ray);
/// The hull-based list of non-convex faces of convexity(), with the vertices split into `parts`
/// slabs whose hulls are built in parallel (convexity() picks one part per 65 536 vertices, at
/// most one per thread; a flat slab makes it one part). The list does not depend on `parts`.
std::vector<int> nonconvex_faces_in_parts(const Body& body, int parts);
}  // namespace internal

/// Exact test with the list of non-convex faces: the verdict of is_convex(); when the body is
/// not convex, the faces some vertex not on them lies strictly outside of, found through the
/// exact convex hull of the vertices (CGAL convex_hull_3): the highest vertex along a face's
/// outer normal is a hull vertex, and a hull vertex none of whose hull neighbours is higher is
/// the highest (hill climbing with exact comparisons where the face has no vertex on the hull).
/// Cost O(V + E) for a convex body; O(V log V) plus the hull degree of a support vertex per
/// face (a climb where none is on the hull) for a non-convex one.
ConvexityReport convexity(const Body& body);

/// The same exact test on raw, unvalidated data (so flat input can be reported as flat).
/// Faces use their outer loop. \pre indices in range; loops of at least 3 vertices.
ConvexityReport convexity(const std::vector<Vec3>& vertices, const std::vector<Face>& faces);

/// The course's own formulation, kept as a reference oracle: for each face, translate a
/// vertex of the face to the origin, rotate about OZ and OY so that an edge lies on the x
/// axis, rotate about OX so that the face lies in z = 0, and read the signs of z of all
/// vertices not on the face. Floating point: |z| <= zero_tolerance · scale counts as 0.
/// Cost O(F·V).
ConvexityReport convexity_by_rotation(const std::vector<Vec3>& vertices,
                                      const std::vector<Face>& faces,
                                      double zero_tolerance = -1);
ConvexityReport convexity_by_rotation(const Body& body);

}  // namespace hedra
