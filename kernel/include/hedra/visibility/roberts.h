// Roberts hidden-line removal (docs/algorithms.md §6): the visible parts of the edges of a scene of
// solids, with the junction lines where bodies interpenetrate, seen in parallel or in
// perspective. Exact: every decision (facing, hidden or not, which plane ends a hidden part,
// where a junction line starts) is an exact predicate on the input coordinates; only the end
// points of the output segments are rounded (docs/hidden-lines.md).
//
// Stages, in the course's order:
//  1. back faces: a face is Front, EdgeOn or Back by the exact sign of E·V
//     (hedra/visibility/occlusion.h's facing()); an edge between two back faces of its body is
//     hidden whole;
//  2. every other edge is clipped against the open occlusion volume of each convex piece whose
//     picture-plane box its projection meets (a uniform grid over the picture plane finds
//     them), or, as the reference, by the course's brute-force solution of the (t, a) system;
//  3. junction lines (edges of A ∩ B lying on a face of A and a face of B, for different
//     bodies A, B) are added and clipped like edges.
// Line classes (hedra/visibility/outline.h): an edge whose faces turn by at most the crease
// angle, or that lies between two faces of one analytic curved surface, is smooth and drawn
// only when asked; the outline of the smooth parts (the contour n·v = 0 interpolated from
// corner normals, O(triangles) per body) is clipped like an edge. Polyhedra whose edges are
// all sharp (boxes) are drawn exactly as without classes.
// Non-convex bodies take part through their exact convex decomposition (hedra/decompose):
// their own edges and faces are drawn, never the cuts; the pieces hide everything behind
// them, including other parts of their own body.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hedra/core/body.h"
#include "hedra/core/progress.h"
#include "hedra/core/smooth_surface.h"
#include "hedra/scene/camera.h"
#include "hedra/visibility/occlusion.h"
#include "hedra/scene/scene.h"

namespace hedra {

/// The picture plane of a camera. Parallel: orthographic coordinates in world units along
/// `right` and `up` (u to the right, v up). Perspective: the pinhole image at focal distance 1
/// (u = q·right / q·axis, v = q·up / q·axis with q = p − eye), so a segment in front of the
/// eye projects to a segment. Constructions in double: used for drawing and for culling with
/// a margin, never for a decision. Value type.
class PictureProjection {
 public:
  /// \pre camera.validate() passes.
  explicit PictureProjection(const Camera& camera);
  bool perspective() const { return perspective_; }
  Vec2 project(const Vec3& p) const;
  /// Increases away from the viewer: parallel, p·axis; perspective, (p − eye)·axis, which is
  /// positive exactly for points in front of the eye plane (up to rounding).
  double depth(const Vec3& p) const;
  const Vec3& axis() const { return axis_; }
  const Vec3& right() const { return right_; }
  const Vec3& up() const { return up_; }

 private:
  bool perspective_ = false;
  Vec3 eye_ = Vec3::Zero(), axis_ = Vec3(0, 0, -1), right_ = Vec3(1, 0, 0), up_ = Vec3(0, 1, 0);
};

/// Edge: a sharp edge (or every drawable edge with crease angle 0). Outline: a piece of the
/// contour of a smooth region. Smooth: a smooth edge (HlrOptions::smooth).
enum class LineKind { Edge, Junction, Outline, Smooth };

/// A visible or hidden part of an edge, or a visible part of a junction line.
struct HlrSegment {
  Vec3 a, b;     // world coordinates
  Vec2 a2, b2;   // picture plane (PictureProjection)
  LineKind kind = LineKind::Edge;
  int body = -1;        // the body of the edge; for a junction, the first of its two bodies
  int other_body = -1;  // junction: the second body
  int edge = -1;        // edge index in bodies[body].edges(); −1 once merged with a coincident
                        // edge, and for an outline
};

struct HlrOptions {
  /// Also report the hidden parts of the edges (back edges included), for dashed drawing.
  bool hidden = false;
  /// Stage 3 on or off.
  bool junctions = true;
  enum class Stage2 {
    OcclusionVolumes,  // exact Cyrus–Beck against each piece's open occlusion volume (fast)
    BruteForce,        // the course's (t, a) system, all pairs of boundary lines (reference)
  };
  Stage2 stage2 = Stage2::OcclusionVolumes;
  /// Test each edge only against the pieces whose picture-plane box it meets (uniform grid);
  /// false tests every edge against every piece (O(n²), for comparison). BruteForce ignores it.
  bool spatial_index = true;
  /// Edges of different bodies on one line (stacked boxes) are drawn once: their parts are
  /// merged along the line (decided exactly). Off: one list entry per edge part.
  bool merge_coincident = true;
  /// Edges whose faces turn by at most this angle (degrees, 0..180) are smooth: not drawn
  /// unless `smooth`; the outline of smooth regions is drawn instead. 0: every edge is sharp
  /// and no outline is drawn (every facet edge, as without line classes).
  double crease_angle = 30;
  /// Also draw the visible parts of smooth edges (LineKind::Smooth).
  bool smooth = false;
  /// How closed non-convex bodies occlude (hedra/visibility/occlusion.h): their exact convex
  /// pieces, or their faces (Auto: faces above kFaceOccluderFaces faces). BruteForce always
  /// uses the pieces.
  Occluders occluders = Occluders::Auto;
  /// Progress and cancellation (hedra/core/progress.h): the fraction done, on the calling
  /// thread; returning false stops the work with hedra::Cancelled and no result.
  ProgressCallback progress;
};

struct HlrStats {
  int bodies = 0;
  int pieces = 0;             // convex pieces (a convex body is one)
  int edges = 0;              // drawable sharp edges: not between coplanar faces, not seen end-on
  int back_edges = 0;         // removed whole by stage 1
  long long occlusion_tests = 0;  // edge × piece clips in stage 2
  int exact_segments = 0;     // segments in an edge-on internal cut plane (rational path)
  int junction_segments = 0;  // junction segments before visibility
  int grid_cells = 0;
  int smooth_edges = 0;       // edges classified smooth, all of them (drawn only with HlrOptions::smooth)
  int outline_segments = 0;   // outline segments before visibility
};

struct HlrResult {
  /// Sharp edges first, then junction lines, then outlines, then smooth edges (when asked).
  std::vector<HlrSegment> visible;
  std::vector<HlrSegment> hidden;   // sharp edges only, when HlrOptions::hidden
  Eigen::AlignedBox2d picture_box;  // projection of every vertex of the scene
  HlrStats stats;
  /// Total 3D length of the visible (or hidden) segments of a kind.
  double length(LineKind kind, bool visible = true) const;
  /// Total picture-plane length of the visible segments of a kind.
  double picture_length(LineKind kind) const;
  /// Whether the scene has smooth parts (smooth edges or outlines): the reports then list
  /// the outline.
  bool has_smooth() const { return stats.smooth_edges > 0 || stats.outline_segments > 0; }
  /// Whether smooth edges were asked for (HlrOptions::smooth): the reports then list them.
  bool smooth_listed = false;
};

/// Hidden-line removal for the bodies seen by `camera`.
/// Edges seen end-on (parallel to a parallel view, or on a line through the perspective eye)
/// project to a point and are not listed.
/// Perspective: the scene is clipped by the renderer's near plane (Camera::near_plane of the
/// bodies' box): bodies reaching it are split there exactly and only their parts in front are
/// drawn and hide; the cut's own edges are not drawn, and segments of split bodies have
/// edge = −1.
/// \throw InvalidInput naming the body when the perspective eye is inside or on a body.
/// Cost: O(E·k) for E edges each meeting k pieces in the picture, plus the decompositions
/// (and O(n log n) per body of n triangles that crosses the near plane); bodies with smooth
/// parts add O(T) for the outline of their T triangles (O(√T) segments on a smooth body, each
/// clipped like an edge).
HlrResult hidden_lines(std::span<const Body> bodies, const Camera& camera,
                       const HlrOptions& options = {});
/// The same with the analytic surface of each body (empty, or one per body; Kind::None for a
/// polyhedron): its curved faces meet in smooth edges and give outlines with analytic normals.
/// \throw InvalidInput when the crease angle is outside 0..180 or the sizes differ.
HlrResult hidden_lines(std::span<const Body> bodies, std::span<const SmoothSurface> surfaces,
                       const Camera& camera, const HlrOptions& options = {});
/// The visible bodies of a scene with its camera; messages name the bodies. The near plane is
/// the one of the scene's box, exactly as render() clips.
HlrResult hidden_lines(const Scene& scene, const HlrOptions& options = {});

/// The open part (t0, t1) of segment p1p2, 0 ≤ t0 < t1 ≤ 1, hidden by one convex piece: the
/// part strictly inside its occlusion volume (Cyrus–Beck with exact decisions: which planes
/// bound, their order, and emptiness; a segment on a bounding plane is not hidden). t rounded.
/// Cost O(planes).
struct HiddenPart {
  double t0 = 0, t1 = 0;
};
std::optional<HiddenPart> hidden_part(const OcclusionVolume& volume, const Vec3& p1,
                                      const Vec3& p2);


}  // namespace hedra
