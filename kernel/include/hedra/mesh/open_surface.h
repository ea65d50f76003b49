// Open surfaces (scans, terrains, single faces): meshes with boundary edges, which are not
// solids, taken by hidden lines, shadows and rendering as sets of two-sided convex faces.
//
// A convex planar polygon seen from a point off its plane hides exactly the open region behind
// it inside the planes through its edges and the point: the occlusion volume of a flat convex
// body whose one face turns to the point (hedra/visibility/occlusion.h). So each face of an
// open surface becomes a Body::two_sided_polygon(): it occludes and casts shadows like a
// convex piece, receives shadows on the side facing a light (the other side is self-shadowed)
// and is rasterized on the side facing the camera. Hidden lines classify the edges between
// faces of a surface by the crease angle and draw the outline of its smooth parts, as for a
// solid (docs/hidden-lines.md); its boundary edges are always sharp.
#pragma once

#include <vector>

#include "hedra/core/body.h"
#include "hedra/mesh/merge_coplanar.h"

namespace hedra {

/// Counts of an open surface's soup: edges, boundary edges (directed edges whose reverse is
/// absent) and the first of them, as (from, to) vertex ids of the file.
struct SurfaceBoundary {
  int edges = 0;
  int boundary_edges = 0;
  int first_from = -1, first_to = -1;
};
/// \pre every index in range. Cost O(E log E).
SurfaceBoundary surface_boundary(const PolygonSoup& soup);

/// Whether hidden lines, shadows and rendering take the soup as an open surface: every index
/// in range, each directed edge at most once (consistently oriented, no edge of three faces),
/// and at least one boundary edge. A closed mesh, or one with a flipped face, is not one.
/// Cost O(E log E).
bool is_open_surface(const PolygonSoup& soup);

/// What `hedra info` reports of an open surface: vertices used, edges, faces, its boundary,
/// and the area (the sum of the faces' Newell areas).
struct SurfaceSummary {
  int vertices = 0, edges = 0, faces = 0;
  SurfaceBoundary boundary;
  double area = 0;
};
/// \pre every index in range. Cost O(E log E).
SurfaceSummary summarize_surface(const PolygonSoup& soup);

/// The faces of an open surface as two-sided convex faces, in soup order. A polygon that is
/// exactly planar and strictly convex is kept whole; any other (non-convex, not planar, with
/// collinear corners) is triangulated in its Newell plane and its triangles are merged back
/// greedily into convex polygons while they stay exactly coplanar and strictly convex, so that
/// no drawn edge is an artefact of the triangulation between exactly coplanar triangles.
/// Exactly coplanar neighbouring faces of the soup are merged the same way (a flat region given
/// as triangles is drawn without its diagonals). Zero-area triangles are dropped.
///
/// `tolerance` D > 0 (the command's `--tolerance`) first merges nearly coplanar neighbours, as
/// for closed meshes (MergeOptions::coplanar_tolerance, snap_surface): regions of neighbours
/// within D of their first face's plane get their fitted plane, every vertex moves onto the
/// planes of its regions by at most D (certified; farther, it stays); a region bounded by one
/// simple loop becomes that loop, its interior vertices gone, and a vertex of the loop used by
/// it alone (on the surface's boundary) or by one other such region (on a crease, then left
/// out of both loops alike) is left out where it lies within D of the chord that replaces it;
/// the result is
/// then made convex faces as above, planar within the rounding of the snapped coordinates
/// (kRoundingPlanarity, as closed bodies' faces). Every vertex kept is within D of its input
/// position, every vertex left out within D of the output. Where that gives no valid faces,
/// the surface is taken exactly (D = 0).
/// \throw InvalidInput naming the polygon when one cannot be triangulated (self-crossing), or
///   when no face has non-zero area. Cost O(F log F + n) for F faces of n vertices in all;
///   with D > 0 also O(R²) for R regions and O(b²) per region of b boundary vertices.
std::vector<Body> two_sided_faces(const PolygonSoup& soup, double tolerance = 0);

/// The faces of two_sided_faces() as one Body::two_sided_surface(): the form scene files and
/// mesh files give hidden lines, shadows and rendering (one body for a million faces). Vertices
/// of equal coordinates are taken as one. \throw InvalidInput as two_sided_faces(), and when
/// the faces, so joined, use an edge twice in one direction or three times (then
/// two_sided_faces() still takes them). Cost as two_sided_faces(), plus O(n log n).
Body two_sided_surface(const PolygonSoup& soup, double tolerance = 0);

}  // namespace hedra
