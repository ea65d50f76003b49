// From a polygon soup (an imported mesh, a Boolean result) to bodies with polygonal faces:
// adjacent coplanar polygons are merged into one face, holes included.
#pragma once

#include <string>
#include <vector>

#include "hedra/core/body.h"

namespace hedra {

/// Indexed polygons, each a single loop of vertex indices, counter-clockwise from outside.
struct PolygonSoup {
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> polygons;
};

struct MergeOptions {
  /// 0 (default): merge only exactly coplanar neighbours (exact predicates). Positive (D): also
  /// neighbours whose vertices lie within D of the region's first plane; with the default
  /// planarity_tolerance the merged faces are then made planar (the `--tolerance D` of the
  /// command): each such region gets its fitted plane and each of its vertices moves to the
  /// nearest point on the planes of its faces, by at most D (certified; a vertex that would
  /// move farther stays). Every output vertex is within D of its input position, so the
  /// surface moves by at most D. Where the snapped faces are not a valid body, the soup is
  /// merged exactly instead: a valid input always gives valid bodies.
  double coplanar_tolerance = 0;
  /// Passed to the bodies built (see BodyOptions). Non-negative: no snapping, faces accepted
  /// this far from planar (the bodies are then only valid with this tolerance).
  double planarity_tolerance = -1;
};

/// Merges adjacent coplanar polygons into faces, drops vertices left inside merged faces, and
/// returns one Body per connected component (in order of their first polygon). A triangulated
/// box becomes one body with 6 faces; the triangulated cap of a plate with holes becomes one
/// face with holes. Regions whose boundary touches itself at a vertex keep their polygons
/// unmerged. A soup that fails only for its needles (triangles of three distinct, exactly
/// collinear corners: T-junction fillers) is merged without them, each needle's middle corner
/// put into the edge of the polygon across its long side (the same surface); where that does
/// not cure it, the input's own error stands. \throw InvalidInput naming the input polygon or
/// vertex (check_polygon_mesh runs on the soup first, so numbers refer to the input).
/// Cost O(n log n); a soup with needles is merged twice.
std::vector<Body> bodies_from_soup(const PolygonSoup& soup, const MergeOptions& options = {});

/// As above, but the caller decides coplanarity: neighbouring polygons with equal
/// `plane_ids` are merged, others are not. Used where planes were compared exactly before the
/// coordinates were rounded to double (Boolean results).
std::vector<Body> bodies_from_soup(const PolygonSoup& soup, const std::vector<int>& plane_ids,
                                   const MergeOptions& options = {});

/// The nearly coplanar regions of a surface, open or closed, and its vertices snapped onto
/// their planes as bodies_from_soup snaps with a positive coplanar tolerance (MergeOptions):
/// neighbours (across an edge used both ways) within `tolerance` of a region's first plane
/// join it; each region's vertices move to the nearest point on the fitted planes of their
/// regions when that moves them by at most `tolerance` (certified), else stay.
struct SnappedSurface {
  std::vector<Vec3> vertices;  ///< one per input vertex, each within the tolerance of it
  std::vector<int> region;     ///< per polygon, its region (0, 1, … in order of first polygon)
};
/// \throw InvalidInput for an index out of range, a zero-area polygon or a directed edge used
///   twice. Cost O(n log n) for n corners, plus O(R²) normal comparisons for R regions.
SnappedSurface snap_surface(const PolygonSoup& soup, double tolerance);

}  // namespace hedra
