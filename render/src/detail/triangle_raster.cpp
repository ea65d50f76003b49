#include "detail/triangle_raster.h"

#include <algorithm>
#include <cmath>

#include "hedra/core/parallel.h"

namespace hedra::detail {

TriangleRaster prepare_triangles(const SceneGeometry& geometry, const RasterView& view,
                                 const std::vector<uint8_t>& draw, int g, int tile_size) {
  TriangleRaster r;
  r.grid = SampleGrid(view.width(), view.height(), g);
  r.bins = TileBins(view.width(), view.height(), tile_size);
  // Homogeneous raster coordinates of every vertex, once: shared vertices of neighbouring
  // triangles are then bit-identical, which the coverage rule needs.
  std::vector<Eigen::Vector3d> h(geometry.positions.size());
  parallel_blocks(h.size(), 0, 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i != end; ++i) h[i] = view.homogeneous(geometry.positions[i]);
  });
  r.key_plane.assign(geometry.faces.size(), Eigen::Vector3d::Zero());
  // Guard band: polygons are clipped to the image plus one image size on each side, which
  // keeps raster coordinates small without clipping most triangles that cross the border.
  const double guard = std::max(view.width(), view.height());
  std::vector<Eigen::Vector3d> ring(3), scratch;
  std::vector<Point2> clipped;
  for (size_t f = 0; f < geometry.faces.size(); ++f) {
    if (!draw[f]) continue;
    const SceneGeometry::FaceRef& face = geometry.faces[f];
    r.key_plane[f] = view.key_plane(geometry.bodies[face.body].body->body.plane(face.face));
    for (int t = geometry.triangle_begin[f]; t < geometry.triangle_begin[f + 1]; ++t) {
      const SceneGeometry::Tri& tri = geometry.triangles[t];
      for (int k = 0; k < 3; ++k) ring[k] = h[tri.v[k]];
      clip_ring(ring, view, guard, clipped, scratch);
      if (clipped.size() < 3) continue;
      ScanPolygon polygon;
      begin_polygon(polygon, r.edges);
      add_ring(polygon, clipped, r.edges);
      if (polygon.edge_count == 0) continue;
      r.bins.add(static_cast<uint32_t>(r.polygons.size()), polygon);
      r.polygons.push_back(polygon);
      r.triangle.push_back(t);
      r.face.push_back(static_cast<int>(f));
    }
  }
  return r;
}

TileRect tile_rect(const TriangleRaster& raster, int tile) {
  const int g = raster.grid.g, size = raster.bins.size * g;
  const int tx = tile % raster.bins.tiles_x, ty = tile / raster.bins.tiles_x;
  TileRect rect;
  rect.c0 = tx * size;
  rect.r0 = ty * size;
  rect.c1 = std::min(rect.c0 + size, raster.grid.columns);
  rect.r1 = std::min(rect.r0 + size, raster.grid.rows);
  return rect;
}

void depth_tile(const TriangleRaster& raster, const TileRect& tile, double* key, int* polygon,
                std::vector<double>& scratch) {
  const int n = tile.size(), stride = tile.columns();
  std::fill(key, key + n, INFINITY);
  std::fill(polygon, polygon + n, -1);
  const std::vector<uint32_t>& list = raster.bins.lists[static_cast<size_t>(
      (tile.r0 / (raster.bins.size * raster.grid.g)) * raster.bins.tiles_x +
      tile.c0 / (raster.bins.size * raster.grid.g))];
  const SampleGrid& grid = raster.grid;
  for (uint32_t index : list) {
    const ScanPolygon& p = raster.polygons[index];
    const Eigen::Vector3d& plane = raster.key_plane[static_cast<size_t>(raster.face[index])];
    const int id = static_cast<int>(index);
    scan_polygon(p, raster.edges, grid, tile.r0, tile.r1, tile.c0, tile.c1, scratch,
                 [&](int r, int c0, int c1) {
                   const double y = grid.y(r);
                   const double row = plane[1] * y + plane[2];
                   double* k = key + (r - tile.r0) * stride - tile.c0;
                   int* id_row = polygon + (r - tile.r0) * stride - tile.c0;
                   for (int c = c0; c < c1; ++c) {
                     // The face's depth key evaluated at the sample itself (never stepped
                     // incrementally), so it does not depend on where the span starts.
                     const double z = plane[0] * grid.x(c) + row;
                     if (z < k[c]) {
                       k[c] = z;
                       id_row[c] = id;
                     }
                   }
                 });
  }
}

}  // namespace hedra::detail
