// Line classes of tessellated bodies and the outlines of their smooth parts (issue 15, item 2).
//
// A mesh edge is sharp when the faces on its two sides turn by more than a crease angle
// (default 30°), smooth otherwise; edges between two faces of one analytic curved surface
// (SmoothSurface: a sphere, a cylinder or cone side) are smooth whatever their angle, so a
// coarse cylinder still reads as a cylinder. The outline of a smooth surface is the contour
// where n·v changes sign, n the surface normal interpolated inside each triangle from corner
// normals and v the viewing ray (Hertzmann and Zorin, "Illustrating smooth surfaces",
// SIGGRAPH 2000): analytic normals where the body carries a SmoothSurface, area-weighted
// normals of the faces around the corner within the crease angle otherwise. These are
// drawing constructions in double, not decisions: the polyhedron stays the model.
#pragma once

#include <vector>

#include "hedra/core/body.h"
#include "hedra/core/smooth_surface.h"
#include "hedra/visibility/occlusion.h"

namespace hedra {

enum class EdgeClass { Sharp, Smooth };

/// The class of each edge of body.edges(), in that order. `surface` may be none. A two-sided
/// body's boundary edges (a face joined to its other side) are always Sharp. Cost O(E).
std::vector<EdgeClass> classify_edges(const Body& body, double crease_angle_deg = 30,
                                      const SmoothSurface& surface = SmoothSurface());

/// One segment of an outline, on face `face` of the body (world coordinates).
struct OutlineSegment {
  Vec3 a, b;
  int face = -1;
};

/// Per-corner unit normals: for face f, loop l, position i, normals[corner_index]. Corners are
/// numbered in face, loop, position order. Cost O(V + E).
std::vector<Vec3> corner_normals(const Body& body, double crease_angle_deg = 30,
                                 const SmoothSurface& surface = SmoothSurface());

/// The outline of the body's smooth parts seen from `view`: in each triangle of
/// body.triangles(), the segment where the interpolated g = n·r (r the ray from the viewpoint)
/// changes sign, g ≥ 0 counting as positive. Segments of neighbouring triangles share end
/// points where the corner normals agree, so a smooth region's outline is a chain of closed
/// or open polylines. Faces that are flat with all corners on a sharp crease (a box) give
/// none. Cost O(triangles).
std::vector<OutlineSegment> outline(const Body& body, const Viewpoint& view,
                                    double crease_angle_deg = 30,
                                    const SmoothSurface& surface = SmoothSurface());

}  // namespace hedra
