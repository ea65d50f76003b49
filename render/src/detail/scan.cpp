#include "detail/scan.h"

#include <algorithm>

namespace hedra::detail {
namespace {

using H = Eigen::Vector3d;  // homogeneous raster point (X, Y, W)

bool less(const H& a, const H& b) {
  if (a.x() != b.x()) return a.x() < b.x();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.z() < b.z();
}

// Plane k of the view volume evaluated at h (≥ 0 inside).
double plane_value(int k, const H& h, const RasterView& view, double guard) {
  switch (k) {
    case 0: return h.z() - view.near();
    case 1: return h.x() + guard * h.z();
    case 2: return (view.width() + guard) * h.z() - h.x();
    case 3: return h.y() + guard * h.z();
    default: return (view.height() + guard) * h.z() - h.y();
  }
}

}  // namespace

void clip_ring(const std::vector<H>& ring, const RasterView& view, double guard,
               std::vector<Point2>& out, std::vector<H>& scratch) {
  out.clear();
  const int first_plane = view.is_perspective() ? 0 : 1;
  // Trivial acceptance: every vertex inside every plane.
  bool inside = true;
  for (const H& h : ring)
    for (int k = first_plane; k < 5 && inside; ++k) inside = plane_value(k, h, view, guard) >= 0;
  if (inside) {
    for (const H& h : ring) out.emplace_back(h.x() / h.z(), h.y() / h.z());
    return;
  }
  // Sutherland–Hodgman, one plane after the other; new vertices from the canonical order of
  // their edge so a shared edge is cut at the same point in both polygons.
  std::vector<H> current(ring);
  for (int k = first_plane; k < 5 && !current.empty(); ++k) {
    scratch.clear();
    const size_t n = current.size();
    for (size_t i = 0; i < n; ++i) {
      const H& a = current[i];
      const H& b = current[(i + 1) % n];
      const double fa = plane_value(k, a, view, guard), fb = plane_value(k, b, view, guard);
      if (fa >= 0) scratch.push_back(a);
      if ((fa >= 0) != (fb >= 0)) {
        const bool swap = less(b, a);
        const H& p = swap ? b : a;
        const H& q = swap ? a : b;
        const double fp = swap ? fb : fa, fq = swap ? fa : fb;
        const double t = fp / (fp - fq);
        scratch.push_back(p + t * (q - p));
      }
    }
    current.swap(scratch);
  }
  if (current.size() < 3) return;
  for (const H& h : current) out.emplace_back(h.x() / h.z(), h.y() / h.z());
}

void begin_polygon(ScanPolygon& polygon, const std::vector<ScanEdge>& edges) {
  polygon.first_edge = static_cast<uint32_t>(edges.size());
  polygon.edge_count = 0;
  polygon.xmin = polygon.ymin = INFINITY;
  polygon.xmax = polygon.ymax = -INFINITY;
}

void add_ring(ScanPolygon& polygon, const std::vector<Point2>& ring, std::vector<ScanEdge>& edges) {
  const size_t n = ring.size();
  for (size_t i = 0; i < n; ++i) {
    Point2 a = ring[i], b = ring[(i + 1) % n];
    polygon.xmin = std::min(polygon.xmin, a.x());
    polygon.xmax = std::max(polygon.xmax, a.x());
    polygon.ymin = std::min(polygon.ymin, a.y());
    polygon.ymax = std::max(polygon.ymax, a.y());
    if (a.y() == b.y()) continue;
    if (b.y() < a.y() || (b.y() == a.y() && b.x() < a.x())) std::swap(a, b);
    edges.push_back({a.y(), b.y(), a.x(), (b.x() - a.x()) / (b.y() - a.y())});
    ++polygon.edge_count;
  }
}

TileBins::TileBins(int width, int height, int tile_size)
    : size(tile_size),
      tiles_x((width + tile_size - 1) / tile_size),
      tiles_y((height + tile_size - 1) / tile_size),
      lists(static_cast<size_t>(tiles_x) * tiles_y) {}

void TileBins::add(uint32_t index, const ScanPolygon& polygon) {
  if (!(polygon.xmax >= polygon.xmin) || !(polygon.ymax >= polygon.ymin)) return;
  const int x0 = std::max(0, static_cast<int>(std::floor(polygon.xmin / size)));
  const int x1 = std::min(tiles_x - 1, static_cast<int>(std::floor(polygon.xmax / size)));
  const int y0 = std::max(0, static_cast<int>(std::floor(polygon.ymin / size)));
  const int y1 = std::min(tiles_y - 1, static_cast<int>(std::floor(polygon.ymax / size)));
  for (int ty = y0; ty <= y1; ++ty)
    for (int tx = x0; tx <= x1; ++tx) lists[static_cast<size_t>(ty) * tiles_x + tx].push_back(index);
}

}  // namespace hedra::detail
