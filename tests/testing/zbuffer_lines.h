// An image-space hidden-line method (bench/hlr_bench.cpp's peer, and the tests' example of how
// image space fails): the faces rasterized into a z-buffer of res × res pixels, each edge
// sampled every half pixel and kept where its depth is within a small bias of the farthest
// depth in the 3 × 3 pixels around it. Compared with an exact result, per edge, it reports the
// visible length it misses and invents. Approximate by nature: about a pixel wrong at every
// visibility transition, and edges that align in the picture confuse it.
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/visibility/roberts.h"
#include "hedra/render/svg.h"

namespace hedra::testing {

struct ZBufferLineError {
  double visible = 0;  // visible length the z-buffer reports (3D, sampled)
  double missed = 0;   // visible in `exact`, hidden for the z-buffer
  double extra = 0;    // hidden in `exact`, visible for the z-buffer
};

struct ZBuffer {
  int res = 0;
  PictureFit fit;
  std::vector<double> key;  // smaller is nearer; +inf for background
};

// Visible t-intervals of every edge of every body, from an exact result computed without
// merging coincident edges.
using EdgeKey = std::pair<int, int>;
inline std::map<EdgeKey, std::vector<std::pair<double, double>>> visible_intervals(std::span<const Body> bodies,
                                                                                   const HlrResult& r) {
  std::map<EdgeKey, std::vector<std::pair<double, double>>> out;
  for (const HlrSegment& seg : r.visible) {
    if (seg.kind != LineKind::Edge) continue;
    const Body& b = bodies[static_cast<size_t>(seg.body)];
    const Edge& e = b.edges()[static_cast<size_t>(seg.edge)];
    const Vec3 p = b.vertices()[e.v0], d = b.vertices()[e.v1] - p;
    double t0 = (seg.a - p).dot(d) / d.squaredNorm(), t1 = (seg.b - p).dot(d) / d.squaredNorm();
    if (t0 > t1) std::swap(t0, t1);
    out[{seg.body, seg.edge}].emplace_back(t0, t1);
  }
  return out;
}

inline void rasterize(ZBuffer& z, std::span<const Body> bodies, const PictureProjection& proj,
                      const Eigen::AlignedBox2d& box) {
  z.fit = fit_picture(box, z.res, z.res, 0.01);
  z.key.assign(static_cast<size_t>(z.res) * z.res, INFINITY);
  const bool persp = proj.perspective();
  for (const Body& b : bodies)
    for (const Triangle& t : b.triangles()) {
      Vec2 p[3];
      double k[3];
      for (int i = 0; i < 3; ++i) {
        const Vec3& v = b.vertices()[static_cast<size_t>(t.v[i])];
        p[i] = z.fit.to_pixels(proj.project(v));
        const double d = proj.depth(v);
        k[i] = persp ? -1 / d : d;  // affine in the picture for both projections
      }
      const double area = (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
      if (area == 0) continue;
      const int x0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].x(), p[1].x(), p[2].x()}))));
      const int x1 = std::min(z.res - 1, static_cast<int>(std::ceil(std::max({p[0].x(), p[1].x(), p[2].x()}))));
      const int y0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].y(), p[1].y(), p[2].y()}))));
      const int y1 = std::min(z.res - 1, static_cast<int>(std::ceil(std::max({p[0].y(), p[1].y(), p[2].y()}))));
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const Vec2 c(x + 0.5, y + 0.5);
          const auto edge = [&](const Vec2& u, const Vec2& v) {
            return ((v - u).x() * (c - u).y() - (v - u).y() * (c - u).x()) / area;
          };
          const double w0 = edge(p[1], p[2]), w1 = edge(p[2], p[0]), w2 = edge(p[0], p[1]);
          if (w0 < 0 || w1 < 0 || w2 < 0) continue;
          const double kk = w0 * k[0] + w1 * k[1] + w2 * k[2];
          double& cell = z.key[static_cast<size_t>(y) * z.res + x];
          cell = std::min(cell, kk);
        }
    }
}

/// The z-buffer method at res × res against `exact` (hidden_lines of the same bodies and
/// camera with merge_coincident = false and junctions = false). `visible_t` caches
/// visible_intervals(bodies, exact).
inline ZBufferLineError zbuffer_lines(std::span<const Body> bodies, const Camera& camera, const HlrResult& exact,
                                      const std::map<EdgeKey, std::vector<std::pair<double, double>>>& visible_t,
                                      int res) {
  const PictureProjection proj(camera);
  ZBuffer z;
  z.res = res;
  rasterize(z, bodies, proj, exact.picture_box);
  const bool persp = proj.perspective();
  ZBufferLineError out;
  double depth_range = 0;
  for (const Body& b : bodies)
    for (const Vec3& v : b.vertices()) depth_range = std::max(depth_range, std::abs(proj.depth(v)));
  for (size_t bi = 0; bi < bodies.size(); ++bi) {
    const Body& b = bodies[bi];
    for (int ei = 0; ei < b.edge_count(); ++ei) {
      const Edge& e = b.edges()[static_cast<size_t>(ei)];
      const Vec3 &p = b.vertices()[static_cast<size_t>(e.v0)], &q = b.vertices()[static_cast<size_t>(e.v1)];
      const double px = (z.fit.to_pixels(proj.project(q)) - z.fit.to_pixels(proj.project(p))).norm();
      if (px == 0) continue;  // end-on
      const int samples = static_cast<int>(std::ceil(2 * px)) + 1;
      const double w = (q - p).norm() / samples;
      auto it = visible_t.find({static_cast<int>(bi), ei});
      for (int k = 0; k < samples; ++k) {
        const double t = (k + 0.5) / samples;
        const Vec3 x = p + (q - p) * t;
        const Vec2 c = z.fit.to_pixels(proj.project(x));
        const double d = proj.depth(x), kx = persp ? -1 / d : d;
        const double bias = persp ? 1e-4 / d : 1e-4 * depth_range;
        const int cx = static_cast<int>(std::floor(c.x())), cy = static_cast<int>(std::floor(c.y()));
        double far = -INFINITY;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = std::clamp(cx + dx, 0, res - 1), yy = std::clamp(cy + dy, 0, res - 1);
            far = std::max(far, z.key[static_cast<size_t>(yy) * res + xx]);
          }
        const bool seen = kx <= far + bias;
        bool truth = false;
        if (it != visible_t.end())
          for (const auto& [t0, t1] : it->second) truth = truth || (t >= t0 && t <= t1);
        if (seen) out.visible += w;
        if (truth && !seen) out.missed += w;
        if (!truth && seen) out.extra += w;
      }
    }
  }
  return out;
}

}  // namespace hedra::testing
