// Internals of kernel/roberts: the parts computed in exact arithmetic (CGAL::Mpzf on
// homogeneous points), kept in one translation unit (kernel/roberts_exact.cpp).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/clip/convex_clipper.h"
#include "hedra/visibility/occlusion.h"

namespace hedra::detail {

/// A convex piece as an occluder: its open occlusion volume (fast path) and its face planes
/// (the brute-force path), both exact planes.
struct PieceOccluder {
  int body = -1;
  const ConvexClipper* volume = nullptr;      // null: hides nothing (no front face)
  const std::vector<ExactPlane>* faces = nullptr;
};

/// An internal facet of a non-convex body seen edge-on: two pieces P, Q of one body touch along
/// a cut plane C that contains the viewpoint (or the view direction). A ray lying in C can pass
/// through the body's interior only across that facet, which neither piece's open occlusion
/// volume sees. For points of C, the region hidden by the facet is the region hidden by the
/// convex set `bounds` (the planes of P and Q other than their faces on C), since within C it
/// is the facet itself. Decided with the (t, a) system, exactly.
struct FacetOccluder {
  int body = -1;
  ExactPlane plane;                 // C
  std::vector<ExactPlane> bounds;   // faces of P and Q except those on C
};

/// Occluders a segment must be tested against (from the caller's spatial index).
struct Candidates {
  std::vector<const PieceOccluder*> pieces;
  std::vector<const FacetOccluder*> facets;
};

/// The exact (Mpzf) planes of occluders, built once per occluder and reused by every junction
/// segment tested against it (building them dominated junction lines). Not thread-safe.
class ExactPlaneCache {
 public:
  ExactPlaneCache();
  ~ExactPlaneCache();
  struct Impl;
  std::unique_ptr<Impl> impl;
};

/// Visible parts [t0, t1] (t rounded, ascending, positive length) of segment p1p2 against the
/// candidates, every decision and every intermediate value exact: hidden parts are the open
/// parts strictly inside each piece's occlusion volume (or, with `brute_force`, the course's
/// (t, a) solution on the piece's faces) and, for a segment lying in a facet's plane C, the
/// facet's hidden part; touching hidden parts join.
std::vector<std::pair<double, double>> visible_parts_exact(const Vec3& p1, const Vec3& p2,
                                                           const Candidates& candidates,
                                                           const Viewpoint& view,
                                                           bool brute_force);

/// The (t, a) oracle for one convex set given by inner-oriented exact planes: the open hidden
/// interval, rounded, or nullopt.
std::optional<std::pair<double, double>> hidden_by_planes_brute_force(
    std::span<const ExactPlane> planes, const Viewpoint& view, const Vec3& p1, const Vec3& p2);

/// The visible parts of the junction lines of two bodies A and B: the closure of the points lying
/// in the relative interior of a face of A and of a face of B whose planes cross. End points
/// (crossings of edges with face planes: the course's penetration points, docs/algorithms.md §6.5)
/// are exact homogeneous points; visibility is decided by `query`'s candidates as in
/// visible_parts_exact, tried in the order given (nearest first pays: a candidate that hides a
/// whole segment ends its test). `found` counts junction segments before visibility.
/// `back_a` / `back_b` (empty when the body is not convex): faces strictly facing away from the
/// viewer of a convex body; a junction in the relative interior of such a face is hidden by its
/// own body, so it is skipped without a test.
/// `near_a` / `near_b` (null: all faces): the faces of A (of B) that may meet B's (A's) box, a
/// superset found by the caller's index; the rest are never read.
/// Cost: O(Fa + Fb) box tests (of the faces listed), then O(Fa'·Fb') for the faces of each whose
/// boxes meet the other body's box, and per junction segment O(candidates · planes) exact
/// evaluations at most (usually far fewer with the early end).
struct JunctionPart {
  Vec3 a, b;
};
/// Candidates for a junction segment a–b lying on face fa of the first body and fb of the second.
using CandidateQuery =
    std::function<void(const Vec3& a, const Vec3& b, int fa, int fb, Candidates& out)>;
/// The exact plane (exact_face_plane) of a face, built by the caller on first use: only the
/// faces near the other body are ever asked for (a face whose face_box meets the other body's
/// bounding box; closed boxes).
using FacePlane = std::function<const ExactPlane&(int face)>;
/// The bounding box of a face's outer loop (exact: the vertices' coordinates). Cost O(face).
Eigen::AlignedBox3d face_box(const Body& body, int face);
inline constexpr size_t kMaxMeetingBoxes = 10;
/// For each face of `body`, whether its face_box meets (closed boxes, as
/// Eigen::AlignedBox3d::intersects) at least one of `boxes` (1 to kMaxMeetingBoxes): the same
/// answers as face_box, from one outcode per vertex and the flat edge list, without reading
/// the faces' loops. Cost O(V·k + E) for k boxes.
std::vector<char> faces_meeting(const Body& body, std::span<const Eigen::AlignedBox3d> boxes);
std::vector<JunctionPart> junction_lines(const Body& a, const Body& b,
                                         const FacePlane& planes_a, const FacePlane& planes_b,
                                         const Viewpoint& view, const CandidateQuery& query,
                                         bool brute_force, int& found,
                                         const std::vector<bool>& back_a = {},
                                         const std::vector<bool>& back_b = {},
                                         ExactPlaneCache* cache = nullptr,
                                         const std::vector<int>* near_a = nullptr,
                                         const std::vector<int>* near_b = nullptr);

}  // namespace hedra::detail
