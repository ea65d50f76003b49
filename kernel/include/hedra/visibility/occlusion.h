// Occlusion volumes: the region a convex piece hides from a viewpoint (the eye or a light).
// One clipping core serves both hidden lines (hedra/visibility/roberts.h) and cast shadows
// (hedra/visibility/shadows.h): docs/design.md, "Data flow"; docs/algorithms.md §6.4.
#pragma once

#include <array>

#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/scene/camera.h"
#include "hedra/clip/convex_clipper.h"
#include "hedra/decompose/decompose.h"  // ExactConvex
#include "hedra/scene/light.h"

namespace hedra {

/// A point of view: a finite point (perspective eye, point or spot light) or a direction at
/// infinity (parallel view, directional light, sun). Value type.
struct Viewpoint {
  bool at_infinity = true;
  Vec3 point = Vec3::Zero();           // when !at_infinity
  Vec3 direction = Vec3(0, 0, -1);     // when at_infinity: the way rays travel (into the scene)

  static Viewpoint at(const Vec3& point);
  static Viewpoint towards(const Vec3& direction);
  /// Parallel camera: its direction; perspective: its eye.
  static Viewpoint of(const Camera& camera);
  /// Directional light and sun: the direction the light travels; point and spot: the position.
  static Viewpoint of(const Light& light);

  /// The direction of the ray from the viewpoint through p (not normalized; exact for a
  /// direction, p − point rounded for a point: use only for non-decisions).
  Vec3 ray_to(const Vec3& p) const { return at_infinity ? direction : Vec3(p - point); }
};

/// How face f of a body turns to a viewpoint, decided exactly: Front when the viewpoint lies
/// strictly on the outer side of the face's plane (a direction: it enters the body through
/// the face, n·d > 0 with n the inner normal), Back when strictly on the inner side, EdgeOn
/// when in the plane (parallel to it). Equals the sign of the course's E·V with E the
/// viewer vector (Front ⇔ E·V > 0). Cost O(1).
/// Decided on the face's support triple (orient3d, orient_direction). Cost O(1).
enum class Facing { Front, EdgeOn, Back };
Facing facing(const Body& body, int face, const Viewpoint& view);

/// facing() on a face plane already built (exact_face_plane: inner side Positive), for callers
/// that cache the planes of many faces. Cost O(1).
Facing facing(const ExactPlane& face_plane, const Viewpoint& view);

/// The open region a convex body B hides from a viewpoint: the points X such that the
/// segment (or ray, for a direction) from the viewpoint to X meets B's interior before X.
/// It is the intersection of the inner half-spaces of B's front faces and of the planes
/// through B's silhouette edges and the viewpoint (parallel to the direction at infinity),
/// each plane exact (ExactPlane through input points, never rounded). A point on its boundary
/// is not hidden. Value type.
struct OcclusionVolume {
  /// The planes; std::nullopt when B has no front face (the viewpoint is inside B or on its
  /// boundary, or B is flat as seen): then B hides nothing.
  std::optional<ConvexClipper> clipper;
  std::vector<int> front_faces;                // faces of B turned to the viewpoint
  std::vector<std::pair<int, int>> silhouette;  // vertex ids (a, b) of silhouette edges
};

/// The occlusion volume of a convex body from a viewpoint. Planes in a fixed order: the front
/// faces' planes (exact_face_plane) in face order, then one plane per silhouette edge in edge
/// order, oriented with the body on its inner side. Cost O(F + E) (each silhouette plane is
/// oriented by the exact sign of a vertex of its edge's faces; O(V) only when all of them lie
/// on it).
/// \pre body is convex (a piece of a decomposition, or a convex input).
/// \throw InvalidInput if the body is flat.
OcclusionVolume occlusion_volume(const Body& convex_body, const Viewpoint& view);

/// The same volume from facings already decided (facing(body, f, view) for every face f) and,
/// when not empty, the faces' planes already built (exact_face_plane(body, f) for every f):
/// for callers that keep them per body or per piece (hidden lines, shadows). Identical planes.
OcclusionVolume occlusion_volume(const Body& convex_body, std::span<const Facing> facing,
                                 const Viewpoint& view,
                                 std::span<const ExactPlane> face_planes = {});

/// The occlusion volume of an exact convex piece (Decomposition::exact_pieces), from its planes
/// alone: the planes of its faces turned to the viewpoint (facing(plane, view) == Front), in
/// face order, then for each edge (j, k) between a front face and one that is not, in edge
/// order, the plane through the edge and the viewpoint as the pencil
/// ExactPlane::pencil(front, other, E) (the piece on its positive side; the other face itself
/// when it is edge-on, the pencil then being a positive multiple of it). No corner of the
/// piece is used, so nothing is rounded: the volume is the exact piece's. `front_faces` index
/// `piece.faces`; `silhouette` is empty (the edges have no double corners). Cost O(F + E),
/// each silhouette plane a few dozen multiprecision operations.
OcclusionVolume occlusion_volume(const ExactConvex& piece, const Viewpoint& view);

/// occlusion_volume without the front faces' planes: `front_faces` and `silhouette` as there,
/// the clipper holding only the silhouette edges' planes (std::nullopt when there are none).
/// Within those planes a point is hidden exactly when it lies behind the front face its view
/// ray meets (for a convex body every other front plane then holds too), so a caller that finds
/// the front faces under a segment needs no other front plane (hidden lines of a body of many
/// faces). Cost O(F + E).
OcclusionVolume silhouette_volume(const Body& convex_body, std::span<const Facing> facing,
                                  const Viewpoint& view);

/// The occlusion volume of a triangle turned to the viewpoint (Occluders::Faces), without
/// building a Body: `plane` is the plane of the triangle's support triple (exact_face_plane of
/// face 0 of Body::two_sided_polygon(t)), and the planes are those occlusion_volume gives for
/// that two-sided triangle when its face 0 is Front (`plane`: triangle_plane(t)): that plane,
/// then the planes through edges
/// (t0, t1), (t1, t2), (t2, t0) and the viewpoint, each oriented by the third corner. Cost O(1).
/// \pre facing(plane, view) == Facing::Front.
OcclusionVolume triangle_occlusion_volume(const std::array<Vec3, 3>& t, const ExactPlane& plane,
                                          const Viewpoint& view);

/// How a closed, non-convex body occludes in hidden lines and shadows.
///  - Pieces: its exact convex decomposition (hedra/decompose/decompose.h), each piece's
///    occlusion volume. Cost of the decomposition grows with the reflex edges (a 4000-point
///    star prism: about a second; a float32 mesh whose every edge is reflex by an ulp: far more).
///  - Faces: its faces cut into triangles, each an exactly planar two-sided occluder; only the
///    faces turned to the viewpoint occlude (a closed surface seen from outside: a ray that
///    reaches a point behind a face turned away entered the body through one turned to it).
///    Cost O(F) to build, and per segment the triangles whose picture box it meets. The same
///    answer as the pieces (both exact, for the same polyhedron), except that a segment lying
///    exactly in the plane through the viewpoint and an edge between two faces turned to it,
///    behind that edge, lies on the boundary of both triangles' open volumes and counts as
///    visible (the pieces' internal facets catch that case; docs/stability.md).
///  - Auto: Faces for a body of more than kFaceOccluderFaces faces, and for a body whose
///    pieces would not be exact: one with faces planar only within rounding and no exact
///    solid (a file's rotated part: Body::faces_off_plane(), decomposed with the rounding
///    guard), or whose decomposition gives a piece that is not exactly convex
///    (pieces_exactly_convex()). Its triangles are exactly planar, so it is then decided
///    exactly as the polyhedron its triangles bound. Pieces otherwise.
enum class Occluders { Auto, Pieces, Faces };
inline constexpr int kFaceOccluderFaces = 4096;

/// Whether a non-convex closed body occludes by its faces under `choice` (see Occluders),
/// before any decomposition.
inline bool occludes_by_faces(const Body& body, Occluders choice) {
  return choice == Occluders::Faces ||
         (choice == Occluders::Auto &&
          (body.face_count() > kFaceOccluderFaces ||
           (!body.has_exact_solid() && !body.faces_off_plane().empty())));
}

/// Whether every piece of a decomposition made with DecomposeOptions::exact_pieces is exactly
/// convex (has its exact planes); Occluders::Auto takes the faces where one is not. Cost O(P).
inline bool pieces_exactly_convex(const Decomposition& d) {
  if (d.exact_pieces.size() != d.pieces.size()) return false;
  for (const ExactConvex& e : d.exact_pieces)
    if (e.faces.empty()) return false;
  return true;
}

/// A convex body with faces off their planes (Body::faces_off_plane(): a file's rotated box,
/// planar only within rounding; a rotated cylinder's caps) as the convex polyhedron its
/// occlusion volume needs: each such face cut into triangles along the diagonals that keep the
/// body convex (convex_polygon_split: for a quadrilateral q0–q2 where q3 lies strictly on the
/// inner side of the plane of q0, q1, q2, else q1–q3, the convexity certificate's split), every
/// other face as it is. Every face of the result is exactly planar, so an occlusion volume of
/// its planes is the volume of the polyhedron the certificate proved convex, where the faces'
/// support planes would bound a body an ulp off it. std::nullopt when the body has no face off
/// its plane, is two-sided, has such a face that convex_polygon_split does not cut (not
/// strictly convex in projection), or the result is not certified convex (then its support
/// planes stand). Cost O(F) (a Body and its convexity certificate) plus the splits.
std::optional<Body> exactly_planar_convex(const Body& convex_body);
/// The same with the splits made already: splits[f] is convex_polygon_split of face f's outer
/// loop for each face off its plane (empty: not cut), as the shadows' faces have them. Cost O(F).
std::optional<Body> exactly_planar_convex(const Body& convex_body,
                                          std::span<const std::vector<std::array<int, 3>>> splits);

/// The triangles of a body's faces (Occluders::Faces): for each face f with wanted[f] (all
/// faces when `wanted` is empty), the triangles Body::triangles() lists for it, in that order,
/// as their corners (input vertices, so every triangle is exactly planar) with the face they
/// came from; a triangle with exactly collinear corners (none by contract) is dropped, as it
/// hides nothing. No Body each: a million-face mesh makes a million of them. Cost O(T).
struct FaceTriangle {
  int face = -1;
  std::array<Vec3, 3> corners;
};
std::vector<FaceTriangle> face_triangles_of(const Body& body, const std::vector<char>& wanted = {});

/// The triangles of a closed body turned to the viewpoint, for Occluders::Faces: those of the
/// faces `faces` (one Facing per face, facing()) says are Front, and of a face off its plane
/// (Body::faces_off_plane()) the triangles whose own plane is turned to it, decided on each
/// triangle (such a face's triangles are an ulp off each other: one nearly edge-on can turn
/// the other way). Cost O(T).
std::vector<FaceTriangle> front_triangles_of(const Body& body, std::span<const Facing> faces,
                                             const Viewpoint& view);

/// The plane of a triangle's support triple, inner side Positive: its corners in their own
/// order from the lexicographically smallest (support_triple), so it is exact_face_plane of a
/// triangular face listed in that order, and of face 0 of Body::two_sided_polygon(t). Cost O(1).
ExactPlane triangle_plane(const std::array<Vec3, 3>& t);

/// Exact: p lies strictly inside the occlusion volume (hidden). Cost O(planes).
bool hides(const OcclusionVolume& volume, const Vec3& p);

/// The face's plane as an exact plane through its support triple, inner side Positive:
/// ExactPlane::through's f(p) = −orient3d(a, b, c, p) is Body::face_side's own rule, so
/// side_of_plane agrees with Body::face_side. Cost O(1).
ExactPlane exact_face_plane(const Body& body, int face);

}  // namespace hedra
