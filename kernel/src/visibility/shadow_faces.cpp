// Shadows: faces in their own 2D frames and their convex parts (shadows_internal.h).
#include <algorithm>
#include <cmath>

#include "visibility/shadows_internal.h"

namespace hedra::internal {
namespace {

// Exact convexity of a counter-clockwise 2D ring (collinear vertices allowed).
bool convex_ccw(const Ring2& r) {
  const size_t n = r.size();
  for (size_t i = 0; i < n; ++i)
    if (orient2d(r[(i + n - 1) % n], r[i], r[(i + 1) % n]) == Sign::Negative) return false;
  return true;
}

// Convex parts of a face: the outer loop itself when it is convex and has no holes, else the
// face's triangles merged greedily while the union stays convex (Hertel–Mehlhorn).
void convex_parts(const Body& body, int f, ShadowFace& fd) {
  const Face& face = body.faces()[static_cast<size_t>(f)];
  const auto& v = body.vertices();
  auto ring2d = [&](const std::vector<int>& ids) {
    Ring2 r;
    r.reserve(ids.size());
    for (int id : ids) r.push_back(drop(v[static_cast<size_t>(id)], fd.axis));
    if (fd.flip) std::reverse(r.begin(), r.end());
    return r;
  };
  std::vector<std::vector<int>> polys;
  if (face.loops.size() == 1 && convex_ccw(ring2d(face.loops[0]))) {
    fd.convex = true;
    return;
  }
  fd.convex = false;
  {
    for (const Triangle& t : body.triangles())
      if (t.face == f) polys.push_back({t.v[0], t.v[1], t.v[2]});
    bool merged = true;
    while (merged) {
      merged = false;
      for (size_t a = 0; a < polys.size() && !merged; ++a) {
        for (size_t b = a + 1; b < polys.size() && !merged; ++b) {
          const auto& A = polys[a];
          const auto& B = polys[b];
          // A shared edge: A has (u → w), B has (w → u).
          for (size_t i = 0; i < A.size() && !merged; ++i) {
            const int u = A[i], w = A[(i + 1) % A.size()];
            for (size_t j = 0; j < B.size(); ++j) {
              if (B[j] != w || B[(j + 1) % B.size()] != u) continue;
              std::vector<int> m;
              for (size_t s = 0; s < A.size(); ++s)
                m.push_back(A[(i + 1 + s) % A.size()]);  // w … u
              for (size_t s = 2; s < B.size(); ++s)
                m.push_back(B[(j + s) % B.size()]);  // after u … before w
              if (!convex_ccw(ring2d(m))) break;
              polys[a] = std::move(m);
              polys.erase(polys.begin() + static_cast<std::ptrdiff_t>(b));
              merged = true;
              break;
            }
          }
        }
      }
    }
  }
  for (const auto& ids : polys) {
    Polygon3 p;
    for (int id : ids) p.push_back(v[static_cast<size_t>(id)]);
    fd.parts.push_back(std::move(p));
  }
}

}  // namespace

ShadowFace make_face(const Body& body, int f) {
  ShadowFace fd;
  fd.plane = exact_face_plane(body, f);
  fd.normal = body.plane(f).normal().normalized();
  fd.normal.cwiseAbs().maxCoeff(&fd.axis);
  // The outer loop runs counter-clockwise around the outward normal −n; seen from +e_k that
  // is counter-clockwise when −n_k > 0.
  fd.flip = fd.normal[fd.axis] > 0;
  fd.area = body.face_area(f);
  fd.area_factor = 1 / std::abs(fd.normal[fd.axis]);
  const Face& face = body.faces()[static_cast<size_t>(f)];
  fd.anchor = body.vertices()[static_cast<size_t>(face.loops[0][0])];
  fd.box = Eigen::AlignedBox3d();
  fd.corners.reserve(face.loops[0].size());
  for (int id : face.loops[0]) {
    fd.corners.push_back(body.vertices()[static_cast<size_t>(id)]);
    fd.box.extend(fd.corners.back());
  }
  fd.centre = fd.box.center();
  fd.radius = 0.5 * fd.box.diagonal().norm();
  convex_parts(body, f, fd);
  return fd;
}

// A clipped piece in 2D, made strictly convex: repeated points, straight vertices and the
// (rounding-sized) reflex dents that rounded crossings can leave are dropped.
bool to_convex_ring(const ShadowFace& fd, const Polygon3& poly, Ring2& ring) {
  ring = fd.project(poly);
  Ring2 r;
  r.reserve(ring.size());
  for (const Vec2& p : ring)
    if (r.empty() || r.back() != p) r.push_back(p);
  while (r.size() > 1 && r.front() == r.back()) r.pop_back();
  bool changed = true;
  while (changed && r.size() >= 3) {
    changed = false;
    for (size_t i = 0; i < r.size() && r.size() >= 3; ++i) {
      const size_t n = r.size();
      if (orient2d(r[(i + n - 1) % n], r[i], r[(i + 1) % n]) != Sign::Positive) {
        r.erase(r.begin() + static_cast<std::ptrdiff_t>(i));
        changed = true;
        if (i > 0) --i;
      }
    }
  }
  if (r.size() < 3) return false;
  ring = std::move(r);
  return true;
}

ShadowPolygon lift_polygon(const ShadowFace& fd, const PolygonWithHoles2& p) {
  ShadowPolygon s;
  s.outer = fd.lift(p.outer);
  for (const Ring2& h : p.holes) s.holes.push_back(fd.lift(h));
  s.area = p.area * fd.area_factor;
  return s;
}

ShadowPolygon whole_face(const Body& body, int f) {
  const Face& face = body.faces()[static_cast<size_t>(f)];
  ShadowPolygon s;
  auto ring = [&](const std::vector<int>& ids) {
    Polygon3 r;
    for (int id : ids) r.push_back(body.vertices()[static_cast<size_t>(id)]);
    return r;
  };
  s.outer = ring(face.loops[0]);
  for (size_t l = 1; l < face.loops.size(); ++l) s.holes.push_back(ring(face.loops[l]));
  s.area = body.face_area(f);
  return s;
}

}  // namespace hedra::internal
