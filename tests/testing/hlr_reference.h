// An independent reference for hidden-line removal (tests and bench/hlr_bench.cpp): sample each
// edge densely, cast the ray from each sample towards the eye, and test it against the open
// interiors of the bodies (convex parts given as plane sets, slab test in double); where two
// neighbouring samples differ, bisect to the transition. Approximate by nature (it may miss a
// visible or hidden part shorter than the sample spacing, and its plane tests round), so it
// is only used on scenes in general position, where no ray grazes a face.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/decompose/decompose.h"
#include "hedra/scene/camera.h"
#include "hedra/visibility/occlusion.h"
#include "hedra/visibility/roberts.h"

namespace hedra::testing {

/// A convex part of an occluding body: unit inner-normal planes (double).
struct RefConvex {
  std::vector<Plane> planes;
  Eigen::AlignedBox2d picture_box;
};

class RayCastReference {
 public:
  /// `parts`: convex bodies whose union of open interiors hides (a non-convex body given by
  /// convex parts whose shared faces no ray of the test lies in).
  RayCastReference(std::span<const Body> parts, const Camera& camera)
      : view_(Viewpoint::of(camera)), projection_(camera) {
    Eigen::AlignedBox3d scene;
    scene.setEmpty();
    for (const Body& b : parts) {
      RefConvex c;
      for (int f = 0; f < b.face_count(); ++f) c.planes.push_back(b.plane(f).normalized());
      c.picture_box.setEmpty();
      for (const Vec3& p : b.vertices()) c.picture_box.extend(projection_.project(p));
      parts_.push_back(std::move(c));
      scene.extend(b.bbox());
    }
    scale_ = scene.isEmpty() ? 1 : scene.sizes().norm();
    build_grid();
  }

  /// Parts given by their planes (unit inner normals) and the points that span them (their
  /// picture boxes, inflated by 1e-9 of the scene: the points may be the rounding of the
  /// planes' corners): for instance the exact pieces of a decomposition (exact_parts).
  RayCastReference(std::span<const std::pair<std::vector<Plane>, std::vector<Vec3>>> parts,
                   const Camera& camera)
      : view_(Viewpoint::of(camera)), projection_(camera) {
    Eigen::AlignedBox3d scene;
    scene.setEmpty();
    for (const auto& [planes, points] : parts)
      for (const Vec3& p : points) scene.extend(p);
    scale_ = scene.isEmpty() ? 1 : scene.sizes().norm();
    for (const auto& [planes, points] : parts) {
      RefConvex c;
      c.planes = planes;
      c.picture_box.setEmpty();
      for (const Vec3& p : points) c.picture_box.extend(projection_.project(p));
      const double grow = 1e-9 * std::max({c.picture_box.min().cwiseAbs().maxCoeff(), c.picture_box.max().cwiseAbs().maxCoeff(), 1.0});
      c.picture_box.min().array() -= grow;
      c.picture_box.max().array() += grow;
      parts_.push_back(std::move(c));
    }
    build_grid();
  }

 private:
  void build_grid() {
    // A coarse grid over the picture for speed on large scenes.
    picture_.setEmpty();
    for (const RefConvex& c : parts_) picture_.extend(c.picture_box);
    cells_ = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(parts_.size()))));
    buckets_.assign(static_cast<size_t>(cells_ * cells_), {});
    for (size_t i = 0; i < parts_.size(); ++i) {
      int x0, y0, x1, y1;
      cell_range(parts_[i].picture_box, x0, y0, x1, y1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) buckets_[static_cast<size_t>(y * cells_ + x)].push_back(static_cast<int>(i));
    }
  }

 public:
  /// Does the open segment (ray for a direction) from x towards the viewer pass through the
  /// open interior of a part, over more than 1e-12 of the scene's size?
  bool hidden(const Vec3& x) const {
    const Vec2 q = projection_.project(x);
    int cx, cy, unused;
    cell_range(Eigen::AlignedBox2d(q, q), cx, cy, unused, unused);
    for (int i : buckets_[static_cast<size_t>(cy * cells_ + cx)]) {
      const RefConvex& c = parts_[static_cast<size_t>(i)];
      if (!c.picture_box.contains(q)) continue;
      if (passes_through(c, x)) return true;
    }
    return false;
  }

  /// Visible length of segment p1p2: `samples` samples and its two ends, transitions bisected
  /// to ~1e-15.
  /// `hints`: further parameters to sample (for instance the middles of the parts another
  /// method found), so that parts shorter than the spacing are classified too; each is
  /// classified independently like any sample.
  double visible_length(const Vec3& p1, const Vec3& p2, int samples = 400,
                        std::vector<double> hints = {}) const {
    const double length = (p2 - p1).norm();
    auto at = [&](double t) { return Vec3(p1 + (p2 - p1) * t); };
    // Samples inside, plus one next to each end: a part shorter than the spacing at an end of the
    // edge is found too.
    std::vector<double> ts{1e-12};
    for (int k = 0; k < samples; ++k) ts.push_back((k + 0.5) / samples);
    ts.push_back(1 - 1e-12);
    for (double t : hints)
      if (t > 1e-12 && t < 1 - 1e-12) ts.push_back(t);
    std::sort(ts.begin(), ts.end());
    ts.erase(std::unique(ts.begin(), ts.end()), ts.end());
    double visible = 0, from = 0;
    bool state = !hidden(at(ts[0]));
    for (size_t k = 1; k < ts.size(); ++k) {
      const bool s = !hidden(at(ts[k]));
      if (s == state) continue;
      double lo = ts[k - 1], hi = ts[k];
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (!hidden(at(mid)) == state ? lo : hi) = mid;
      }
      if (state) visible += 0.5 * (lo + hi) - from;
      from = 0.5 * (lo + hi);
      state = s;
    }
    if (state) visible += 1 - from;
    return visible * length;
  }

 private:
  bool passes_through(const RefConvex& c, const Vec3& x) const {
    // Y(s) = x + s·r, s in (0, s_max): r towards the viewer.
    Vec3 r;
    double s_max;
    if (view_.at_infinity) {
      r = -view_.direction.normalized();
      s_max = 1e3 * scale_;
    } else {
      r = view_.point - x;
      s_max = 1;
    }
    // A sample point within 1e-12 of the scene's size of a part's plane is taken as on it: the
    // sample is the edge's point rounded, and for a face seen nearly edge-on an ulp inside it
    // would put the ray inside the part over ulp / (sine of the grazing angle), far above the
    // length threshold below.
    const double on_plane = 1e-12 * scale_;
    double lo = 0, hi = s_max;
    for (const Plane& p : c.planes) {
      double f = p.value(x);
      if (std::abs(f) <= on_plane) f = 0;
      const double g = p.normal().dot(r);
      if (g == 0) {
        if (f <= 0) return false;
        continue;
      }
      const double s = -f / g;
      if (g > 0)
        lo = std::max(lo, s);
      else
        hi = std::min(hi, s);
      if (hi <= lo) return false;
    }
    return (hi - lo) * r.norm() > 1e-12 * scale_;
  }

  void cell_range(const Eigen::AlignedBox2d& box, int& x0, int& y0, int& x1, int& y1) const {
    const Vec2 size = picture_.sizes().cwiseMax(1e-300);
    auto idx = [&](double v, double o, double s) {
      const int i = static_cast<int>(std::floor((v - o) / s * cells_));
      return std::clamp(i, 0, cells_ - 1);
    };
    x0 = idx(box.min().x(), picture_.min().x(), size.x());
    x1 = idx(box.max().x(), picture_.min().x(), size.x());
    y0 = idx(box.min().y(), picture_.min().y(), size.y());
    y1 = idx(box.max().y(), picture_.min().y(), size.y());
  }

  Viewpoint view_;
  PictureProjection projection_;
  std::vector<RefConvex> parts_;
  double scale_ = 1;
  Eigen::AlignedBox2d picture_;
  int cells_ = 1;
  std::vector<std::vector<int>> buckets_;
};

/// The convex parts of a body as plane sets for RayCastReference: a convex body's own face
/// planes; a non-convex body's exact pieces (Decomposition::piece_planes), each plane the
/// input's own face plane (InputPlanes::approx), so that rounding the pieces to double (an ulp
/// off the body's edges, or the convex-hull fallback's sliver faces) plays no part.
inline std::vector<std::pair<std::vector<Plane>, std::vector<Vec3>>> exact_parts(const Body& body) {
  std::vector<std::pair<std::vector<Plane>, std::vector<Vec3>>> out;
  const Decomposition d = decompose(body);
  for (size_t k = 0; k < d.pieces.size(); ++k) {
    std::vector<Plane> planes;
    if (d.piece_planes.empty()) {
      for (int f = 0; f < d.pieces[k].face_count(); ++f) planes.push_back(d.pieces[k].plane(f).normalized());
    } else {
      // approx is outward for the plane's defining face; the piece's outward normal is sign times it.
      for (const auto& [c, sign] : d.piece_planes[k]) {
        const Plane& a = d.planes.approx[static_cast<size_t>(c)];
        planes.push_back(sign > 0 ? a.flipped() : a);
      }
    }
    out.emplace_back(std::move(planes), d.pieces[k].vertices());
  }
  return out;
}

/// The middles of the visible parts of edge (body, edge) in `result` and of the gaps between
/// them, as parameters on the edge: hints for visible_length.
inline std::vector<double> part_hints(const HlrResult& result, const Body& body, int b, int e) {
  const Edge& edge = body.edges()[static_cast<size_t>(e)];
  const Vec3 p = body.vertices()[static_cast<size_t>(edge.v0)];
  const Vec3 d = body.vertices()[static_cast<size_t>(edge.v1)] - p;
  std::vector<std::pair<double, double>> parts;
  for (const HlrSegment& s : result.visible) {
    if (s.kind != LineKind::Edge || s.body != b || s.edge != e) continue;
    double t0 = (s.a - p).dot(d) / d.squaredNorm(), t1 = (s.b - p).dot(d) / d.squaredNorm();
    parts.emplace_back(std::min(t0, t1), std::max(t0, t1));
  }
  std::sort(parts.begin(), parts.end());
  std::vector<double> hints;
  double from = 0;
  for (const auto& [t0, t1] : parts) {
    hints.push_back(0.5 * (from + t0));
    hints.push_back(0.5 * (t0 + t1));
    from = t1;
  }
  hints.push_back(0.5 * (from + 1));
  return hints;
}

}  // namespace hedra::testing
