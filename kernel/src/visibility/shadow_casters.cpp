// Shadows: the convex pieces' broad phase, which pieces can shade a face
// (shadows_internal.h).
#include <algorithm>
#include <cmath>

#include "hedra/core/parallel.h"
#include "hedra/core/tolerance.h"
#include "visibility/shadows_internal.h"

namespace hedra::internal {

bool piece_on_face_plane(const Body& piece, const ShadowFace& fd, double scale) {
  const double tol = kRoundingPlanarity * scale;
  const Plane plane = Plane::through(fd.anchor, fd.normal);
  for (int g = 0; g < piece.face_count(); ++g) {
    if (piece.inner_normal(g).dot(fd.normal) <= 0) continue;
    bool on = true;
    for (int id : piece.faces()[static_cast<size_t>(g)].loops[0])
      if (std::abs(plane.value(piece.vertices()[static_cast<size_t>(id)])) > tol) {
        on = false;
        break;
      }
    if (on) return true;
  }
  return false;
}

CasterIndex::CasterIndex(const std::vector<ShadowPiece>& pieces, const PieceVolumes& volumes,
                         const Viewpoint& view, double scale, int threads)
    : pieces_(pieces), view_(view), margin_(1e-9 * scale) {
  if (!view.at_infinity) {
    // The angular grid (shadows_internal.h): the frame from the pieces' mean direction, then
    // about one cell per small piece over the range of their cones.
    std::vector<int> active;
    Vec3 mean = Vec3::Zero();
    for (size_t p = 0; p < pieces.size(); ++p) {
      if (!volumes.active[p]) continue;
      active.push_back(static_cast<int>(p));
      const Vec3 c = pieces[p].centre - view.point;
      if (c.norm() > 0) mean += c.normalized();
    }
    if (mean.norm() > 0) {
      ax_ = mean.normalized();
      az_ = ax_.unitOrthogonal();
      ay_ = az_.cross(ax_);
    }
    // The cones in parallel (asin, acos, atan2 each: half a million triangles of a mesh took
    // 0.2 s on one thread), then split into wide and small in piece order.
    std::vector<Cone> cones(active.size());
    tests_.resize(active.size());
    parallel_blocks(active.size(), threads, 4096, [&](size_t begin, size_t end) {
      for (size_t i = begin; i != end; ++i) {
        const size_t p = static_cast<size_t>(active[i]);
        const Vec3 c = pieces[p].centre - view.point;
        const double d = c.norm(), r = pieces[p].radius + margin_;
        cones[i] = cone_of(c, d, r);
        const double sa = std::min(1.0, r / d);
        tests_[i] = {c, d, r, sa, std::sqrt(1 - sa * sa)};
      }
    });
    ids_ = std::move(active);  // slot → piece
    std::vector<int> small;
    const double pi = std::numbers::pi;
    double t_lo = pi, t_hi = 0, p_lo = pi, p_hi = -pi;
    for (size_t i = 0; i < ids_.size(); ++i) {
      const int p = static_cast<int>(i);  // the slot
      const Cone& k = cones[i];
      if (k.all_phi || k.t1 - k.t0 > 2 * kWideCone || k.p1 - k.p0 > 2 * kWideCone || k.p0 < -pi || k.p1 > pi) {
        always_.push_back(p);
        continue;
      }
      small.push_back(p);
      t_lo = std::min(t_lo, k.t0), t_hi = std::max(t_hi, k.t1);
      p_lo = std::min(p_lo, k.p0), p_hi = std::max(p_hi, k.p1);
    }
    if (small.empty()) return;
    const double tr = std::max(t_hi - t_lo, 1e-12), pr = std::max(p_hi - p_lo, 1e-12);
    // One cell per small piece. With four (before), the 1M-triangle sphere under a point light
    // listed 24.6 M cells and 659 M entries for 446 000 faces, 50.6 M of them distinct pieces;
    // with one, 7.8 M cells and 285 M entries for 58.9 M distinct (the candidates passed on,
    // 28.5 M, are the same: the cone test decides). Fewer, larger cells: fewer repeated entries.
    const double cells_wanted = std::min(static_cast<double>(small.size()), 4.0e6);
    n_theta_ = std::clamp(static_cast<int>(std::ceil(std::sqrt(cells_wanted * tr / pr))), 1, 4096);
    n_phi_ = std::clamp(static_cast<int>(std::ceil(cells_wanted / n_theta_)), 1, 4096);
    t_lo_ = t_lo, t_scale_ = n_theta_ / tr, p_lo_ = p_lo, p_scale_ = n_phi_ / pr;
    const size_t cells = static_cast<size_t>(n_theta_) * static_cast<size_t>(n_phi_);
    cells_.assign(cells + 1, 0);
    for (int p : small) for_cone(cones[static_cast<size_t>(p)], [&](size_t c) { ++cells_[c + 1]; });
    for (size_t c = 1; c < cells_.size(); ++c) cells_[c] += cells_[c - 1];
    items_.resize(static_cast<size_t>(cells_.back()));
    std::vector<int> fill(cells_.begin(), cells_.end() - 1);
    for (int p : small)
      for_cone(cones[static_cast<size_t>(p)], [&](size_t c) { items_[static_cast<size_t>(fill[c]++)] = p; });
    return;
  }
  dir_ = view.direction.normalized();
  e1_ = dir_.unitOrthogonal();
  e2_ = dir_.cross(e1_);
  std::vector<int> ids;
  for (size_t p = 0; p < pieces.size(); ++p) {
    if (!volumes.active[p]) continue;
    Bounds b = bounds(pieces[p].vertices());
    boxes_.push_back(b);
    ids.push_back(static_cast<int>(p));
  }
  if (ids.empty()) return;
  lo_ = boxes_[0].lo;
  Vec2 hi = boxes_[0].hi;
  for (const Bounds& b : boxes_) {
    lo_ = lo_.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  n_ = std::clamp(static_cast<int>(std::ceil(std::sqrt(static_cast<double>(ids.size())))), 1,
                  2048);
  const Vec2 size = (hi - lo_).cwiseMax(Vec2(1e-300, 1e-300));
  inv_ = Vec2(n_ / size.x(), n_ / size.y());
  cells_.assign(static_cast<size_t>(n_) * static_cast<size_t>(n_) + 1, 0);
  for (const Bounds& b : boxes_) for_cells(b, [&](size_t c) { ++cells_[c + 1]; });
  for (size_t c = 1; c < cells_.size(); ++c) cells_[c] += cells_[c - 1];
  items_.resize(static_cast<size_t>(cells_.back()));
  std::vector<int> fill(cells_.begin(), cells_.end() - 1);
  for (size_t k = 0; k < boxes_.size(); ++k)
    for_cells(boxes_[k],
              [&](size_t c) { items_[static_cast<size_t>(fill[c]++)] = static_cast<int>(k); });
  ids_ = std::move(ids);
}
CasterIndex::Bounds CasterIndex::bounds(std::span<const Vec3> pts) const {
  Bounds b{Vec2(1e300, 1e300), Vec2(-1e300, -1e300), 1e300, -1e300};
  for (const Vec3& p : pts) {
    const Vec2 q(p.dot(e1_), p.dot(e2_));
    b.lo = b.lo.cwiseMin(q);
    b.hi = b.hi.cwiseMax(q);
    const double d = p.dot(dir_);
    b.depth_lo = std::min(b.depth_lo, d);
    b.depth_hi = std::max(b.depth_hi, d);
  }
  b.lo.array() -= margin_;
  b.hi.array() += margin_;
  b.depth_lo -= margin_;
  b.depth_hi += margin_;
  return b;
}
}  // namespace hedra::internal
