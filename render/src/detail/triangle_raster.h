// The z-buffer pass over a scene's triangles for one view, shared by the camera and the
// shadow maps (internal to hedra::render).
#pragma once

#include <cstdint>
#include <vector>

#include "detail/scan.h"
#include "hedra/render/raster_view.h"
#include "hedra/render/scene_geometry.h"

namespace hedra::detail {

/// The triangles of the selected faces, clipped to the view volume, projected and binned.
struct TriangleRaster {
  SampleGrid grid;
  TileBins bins{1, 1, 1};
  std::vector<ScanPolygon> polygons;  // one per drawn (clipped) triangle, in triangle order
  std::vector<ScanEdge> edges;
  std::vector<int> triangle;  // SceneGeometry triangle of each polygon
  std::vector<int> face;      // and its face
  /// Depth-key plane of each face (RasterView::key_plane of the face's plane); for faces
  /// not drawn, unspecified.
  std::vector<Eigen::Vector3d> key_plane;
};

/// Prepares the triangles of the faces with draw[f] != 0 for the view, on a grid of
/// g × g samples per pixel, binned to tiles of `tile_size` pixels. Cost O(triangles).
TriangleRaster prepare_triangles(const SceneGeometry& geometry, const RasterView& view,
                                 const std::vector<uint8_t>& draw, int g, int tile_size);

/// One tile's samples: the tile covers sample columns [c0, c1) and rows [r0, r1); arrays are
/// row-major over the tile with stride c1 − c0.
struct TileRect {
  int c0, c1, r0, r1;
  int columns() const { return c1 - c0; }
  int size() const { return (c1 - c0) * (r1 - r0); }
};
TileRect tile_rect(const TriangleRaster& raster, int tile);

/// The z-buffer of one tile: for each sample, the smallest depth key of the triangles
/// covering it (+∞ if none) and that triangle's polygon index (−1 if none); ties keep the
/// polygon that comes first. `key` and `polygon` have tile.size() entries.
void depth_tile(const TriangleRaster& raster, const TileRect& tile, double* key, int* polygon,
                std::vector<double>& scratch);

}  // namespace hedra::detail
