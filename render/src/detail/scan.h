// Scan conversion of polygons on a grid of samples, shared by the camera pass, the shadow
// maps and the exact-shadow mask (internal to hedra::render).
//
// Samples. With g samples per pixel side (g² per pixel), sample (c, r) lies at raster point
// ((c + ½)/g, (r + ½)/g): g = 1 puts one sample at each pixel centre.
//
// Coverage rule. A sample belongs to a polygon when it lies in the polygon's even–odd
// interior with the half-open conventions y0 ≤ y < y1 for the rows an edge crosses and
// x_left ≤ x < x_right for a span. Every edge is evaluated from its end points in one
// canonical order (lower end first), so two polygons that share an edge compute the same
// crossing bit for bit: a sample on a shared edge belongs to exactly one of them, and
// polygons that tile a region cover each sample of it exactly once (no cracks, no double
// hits). Clipping computes every new vertex from the canonical order of its edge too.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hedra/render/raster_view.h"

namespace hedra::detail {

using Point2 = Eigen::Vector2d;

/// The sample grid of a W × H image with g × g samples per pixel.
struct SampleGrid {
  int g = 1;
  int columns = 0, rows = 0;  // W·g, H·g
  double step = 1;            // 1/g (a power of two: sample coordinates are exact)
  SampleGrid() = default;
  SampleGrid(int width, int height, int per_side)
      : g(per_side), columns(width * per_side), rows(height * per_side), step(1.0 / per_side) {}
  double x(int c) const { return (c + 0.5) * step; }
  double y(int r) const { return (r + 0.5) * step; }
};

/// An edge with y0 < y1: it crosses sample rows with y0 ≤ y < y1 at x0 + (y − y0)·slope.
struct ScanEdge {
  double y0, y1, x0, slope;
};

/// A polygon ready for scan conversion: its edges (a range of a shared edge array) and its
/// raster bounding box.
struct ScanPolygon {
  uint32_t first_edge = 0, edge_count = 0;
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;
};

/// Clips a closed ring given in homogeneous raster coordinates (X, Y, W) to the view volume:
/// W ≥ near (perspective views) and −guard ≤ X/W ≤ width + guard, likewise for Y
/// (Sutherland–Hodgman, docs/algorithms.md §3.5). Returns the clipped ring in raster coordinates
/// (empty when nothing is left). Cost O(n).
void clip_ring(const std::vector<Eigen::Vector3d>& ring, const RasterView& view, double guard,
               std::vector<Point2>& out, std::vector<Eigen::Vector3d>& scratch);

/// Appends the edges of the closed ring (horizontal edges skipped) to `edges` and extends
/// the polygon's box. Call begin_polygon first.
void begin_polygon(ScanPolygon& polygon, const std::vector<ScanEdge>& edges);
void add_ring(ScanPolygon& polygon, const std::vector<Point2>& ring, std::vector<ScanEdge>& edges);

/// First sample index i with (i + ½)·step ≥ v.
inline int first_sample_at_or_after(double v, int g, double step) {
  const double f = std::ceil(v * g - 0.5);
  if (!(f > -1e9)) return -1000000000;
  if (!(f < 1e9)) return 1000000000;
  int i = static_cast<int>(f);
  while ((i + 0.5) * step < v) ++i;
  while ((i - 0.5) * step >= v) --i;
  return i;
}

/// Calls span(r, c0, c1) for the columns c0 ≤ c < c1 of sample row r inside the polygon
/// bounded by the `count` edges at `e` (rows ymin … ymax in raster units), for rows
/// r0 ≤ r < r1 and columns clamped to [cmin, cmax). Even–odd rule. `xs` is scratch space.
/// Cost O(rows · count) plus the spans.
template <class Span>
void scan_edges(const ScanEdge* e, uint32_t count, double ymin, double ymax,
                const SampleGrid& grid, int r0, int r1, int cmin, int cmax,
                std::vector<double>& xs, Span&& span) {
  r0 = std::max(r0, first_sample_at_or_after(ymin, grid.g, grid.step));
  r1 = std::min(r1, first_sample_at_or_after(ymax, grid.g, grid.step) + 1);
  for (int r = r0; r < r1; ++r) {
    const double y = grid.y(r);
    xs.clear();
    for (uint32_t k = 0; k < count; ++k)
      if (y >= e[k].y0 && y < e[k].y1) xs.push_back(e[k].x0 + (y - e[k].y0) * e[k].slope);
    const size_t n = xs.size();
    if (n < 2) continue;
    if (n == 2) {
      if (xs[1] < xs[0]) std::swap(xs[0], xs[1]);
    } else {
      std::sort(xs.begin(), xs.end());
    }
    for (size_t i = 0; i + 1 < n; i += 2) {
      const int c0 = std::max(cmin, first_sample_at_or_after(xs[i], grid.g, grid.step));
      const int c1 = std::min(cmax, first_sample_at_or_after(xs[i + 1], grid.g, grid.step));
      if (c0 < c1) span(r, c0, c1);
    }
  }
}

/// scan_edges over one polygon's own edges.
template <class Span>
void scan_polygon(const ScanPolygon& polygon, const std::vector<ScanEdge>& edges,
                  const SampleGrid& grid, int r0, int r1, int cmin, int cmax,
                  std::vector<double>& xs, Span&& span) {
  scan_edges(edges.data() + polygon.first_edge, polygon.edge_count, polygon.ymin, polygon.ymax,
             grid, r0, r1, cmin, cmax, xs, span);
}

/// Square tiles of `size` pixels over a W × H image and, per tile, the polygons whose box
/// meets it, in increasing polygon order (so ties in the z-buffer break the same way in
/// every tile and with any number of threads).
struct TileBins {
  int size = 32, tiles_x = 0, tiles_y = 0;
  std::vector<std::vector<uint32_t>> lists;
  TileBins(int width, int height, int tile_size);
  void add(uint32_t index, const ScanPolygon& polygon);
  int count() const { return tiles_x * tiles_y; }
};

}  // namespace hedra::detail
