#include "hedra/visibility/shadows.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "hedra/mesh/convexity.h"
#include "hedra/clip/cyrus_beck.h"
#include "hedra/decompose/decompose.h"
#include "hedra/core/error.h"
#include "hedra/visibility/polygon_union.h"
#include "hedra/scene/sun.h"
#include "hedra/core/tolerance.h"

namespace hedra {
namespace {

// ---- Faces in their own 2D frame ----
//
// A face is projected onto the coordinate plane of its normal's dominant axis k, keeping
// (p[k+1], p[k+2]) (cyclic): dropping a coordinate is exact, so exact 3D input points stay
// exact 2D points, and the 2D predicates on them decide exactly. 2D rings are
// counter-clockwise; `flip` says the face's own orientation (counter-clockwise seen from
// outside) is clockwise in 2D.

Vec2 drop(const Vec3& p, int k) { return {p[(k + 1) % 3], p[(k + 2) % 3]}; }

struct FaceData {
  int axis = 2;
  bool flip = false;
  double area = 0;
  double area_factor = 1;       // 3D area = 2D area × factor
  Vec3 normal = Vec3::UnitZ();  // unit inner normal
  Vec3 anchor = Vec3::Zero();   // a vertex of the face (exact), for lifting 2D points
  // Convex parts, face orientation, input vertices: the outer loop itself when it is convex
  // and the face has no holes (`convex`), else `parts`.
  bool convex = true;
  std::vector<Polygon3> parts;
  Eigen::AlignedBox3d box;
  Vec3 centre = Vec3::Zero();
  double radius = 0;
  ExactPlane plane;           // through the face's support triple: Positive inner (face_side)
  std::vector<Vec3> corners;  // the outer loop

  Vec3 lift(const Vec2& q) const {
    const int k = axis, i = (k + 1) % 3, j = (k + 2) % 3;
    Vec3 p;
    p[i] = q.x();
    p[j] = q.y();
    p[k] =
        anchor[k] - (normal[i] * (q.x() - anchor[i]) + normal[j] * (q.y() - anchor[j])) / normal[k];
    return p;
  }
  Polygon3 lift(const Ring2& ring) const {
    Polygon3 out;
    out.reserve(ring.size());
    for (const Vec2& q : ring) out.push_back(lift(q));
    if (flip) std::reverse(out.begin(), out.end());
    return out;
  }
  template <class F>
  void for_parts(F&& f) const {
    if (convex) {
      f(corners);
      return;
    }
    for (const Polygon3& p : parts) f(p);
  }
  std::vector<Ring2> parts2d() const {
    std::vector<Ring2> out;
    for_parts([&](const Polygon3& p) { out.push_back(project(p)); });
    return out;
  }
  Ring2 project(const Polygon3& poly) const {
    Ring2 r;
    r.reserve(poly.size());
    for (const Vec3& p : poly) r.push_back(drop(p, axis));
    if (flip) std::reverse(r.begin(), r.end());
    return r;
  }
};

// Exact convexity of a counter-clockwise 2D ring (collinear vertices allowed).
bool convex_ccw(const Ring2& r) {
  const size_t n = r.size();
  for (size_t i = 0; i < n; ++i)
    if (orient2d(r[(i + n - 1) % n], r[i], r[(i + 1) % n]) == Sign::Negative) return false;
  return true;
}

// Convex parts of a face: the outer loop itself when it is convex and has no holes, else the
// face's triangles merged greedily while the union stays convex (Hertel–Mehlhorn).
void convex_parts(const Body& body, int f, FaceData& fd) {
  const Face& face = body.faces()[static_cast<size_t>(f)];
  const auto& v = body.vertices();
  auto ring2d = [&](const std::vector<int>& ids) {
    Ring2 r;
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

// The exact plane of face f, oriented as Body::face_side: ExactPlane::through's f(p) is
// −orient3d(a, b, c, p), which is face_side's convention for the support triple.
ExactPlane face_plane(const Body& body, int f) {
  const auto& s = body.support(f);
  const auto& v = body.vertices();
  return ExactPlane::through(v[static_cast<size_t>(s[0])], v[static_cast<size_t>(s[1])],
                             v[static_cast<size_t>(s[2])]);
}

// direction_sign with a static filter first, from ExactPlane's documented bound: f's double
// form satisfies |value(p) − F(p)| ≤ error_bound(max|p_i|), F = f / 2^e affine, so the
// computed value(d) − value(0) is within error_bound(max|d_i|) + error_bound(0) of
// F(d) − F(0) = n·d / 2^e, plus the rounding of the subtraction. Decides unless n·d is within
// rounding of 0; then the exact predicate.
Sign direction_sign_fast(const ExactPlane& f, const Vec3& d) {
  constexpr double u = 0.5 * std::numeric_limits<double>::epsilon();
  const double diff = f.value(d) - f.value(0, 0, 0);
  const double bound = (f.error_bound(d.cwiseAbs().maxCoeff()) + f.error_bound(0)) * (1 + 4 * u) +
                       2 * u * std::abs(diff);
  if (diff > bound) return Sign::Positive;
  if (diff < -bound) return Sign::Negative;
  return direction_sign(f, d);
}

// Exactly facing() of hedra/visibility/occlusion.h, on a cached face plane.
Facing facing_of(const ExactPlane& plane, const Viewpoint& view) {
  if (view.at_infinity) {
    const Sign s = direction_sign_fast(plane, view.direction);
    return s == Sign::Positive ? Facing::Front : (s == Sign::Zero ? Facing::EdgeOn : Facing::Back);
  }
  const Sign s = side_of_plane(plane, view.point);
  return s == Sign::Negative ? Facing::Front : (s == Sign::Zero ? Facing::EdgeOn : Facing::Back);
}

FaceData make_face(const Body& body, int f) {
  FaceData fd;
  fd.plane = face_plane(body, f);
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
  for (int id : face.loops[0]) {
    fd.corners.push_back(body.vertices()[static_cast<size_t>(id)]);
    fd.box.extend(fd.corners.back());
  }
  fd.centre = fd.box.center();
  fd.radius = 0.5 * fd.box.diagonal().norm();
  convex_parts(body, f, fd);
  return fd;
}

// ---- Clipping a convex polygon against a convex occlusion volume ----
//
// Sutherland–Hodgman with exact sides. The volume is open (its boundary is lit): a polygon with
// no vertex strictly inside a plane, including one lying in the plane, gives nothing. A
// crossing point is computed from its segment's ends in lexicographic order, so two pieces
// sharing an edge (convex parts of one face) cut it at the same points.

bool lex_less(const Vec3& a, const Vec3& b) {
  return a.x() < b.x() || (a.x() == b.x() && (a.y() < b.y() || (a.y() == b.y() && a.z() < b.z())));
}

// The coordinate axis a plane is perpendicular to, decided exactly from its defining points
// (three points, or two points and a direction), or −1.
int axis_plane(const ExactPlane& f) {
  if (!f.by_points()) return -1;
  const auto& p = f.points();
  for (int k = 0; k < 3; ++k) {
    const bool third = f.by_direction() ? p[2][k] == 0 : p[2][k] == p[0][k];
    if (p[0][k] == p[1][k] && third) return k;
  }
  return -1;
}

Vec3 canonical_crossing(const ExactPlane& f, Vec3 v, Vec3 w) {
  if (lex_less(w, v)) std::swap(v, w);
  double t = crossing(f, v, w).t;
  // Both plane values can round to the same double when the segment lies within rounding of
  // the plane (the exact signs still differ): then every point of it is within the bound.
  if (!std::isfinite(t)) t = 0.5;
  Vec3 p = point_at(v, w, t);
  // On a plane perpendicular to a coordinate axis the exact crossing has that plane's
  // coordinate: set it, so that pieces cut by one such plane (walls, floors, the cuts of a
  // decomposition) meet along exactly the same line.
  if (const int k = axis_plane(f); k >= 0) p[k] = f.points()[0][k];
  return p;
}

bool clip_convex(const Polygon3& in, const ConvexClipper& clipper, Polygon3& out, Polygon3& scratch,
                 std::vector<Sign>& side) {
  out = in;
  for (const ExactPlane& f : clipper.planes()) {
    const size_t n = out.size();
    side.resize(n);
    size_t pos = 0, neg = 0;
    for (size_t i = 0; i < n; ++i) {
      side[i] = side_of_plane(f, out[i]);
      pos += side[i] == Sign::Positive;
      neg += side[i] == Sign::Negative;
    }
    if (pos == 0) return false;
    if (neg == 0) continue;
    scratch.clear();
    for (size_t i = 0; i < n; ++i) {
      const size_t j = (i + 1) % n;
      if (side[i] != Sign::Negative) scratch.push_back(out[i]);
      if ((side[i] == Sign::Positive && side[j] == Sign::Negative) ||
          (side[i] == Sign::Negative && side[j] == Sign::Positive))
        scratch.push_back(canonical_crossing(f, out[i], out[j]));
    }
    std::swap(out, scratch);
    if (out.size() < 3) return false;
  }
  return true;
}

// A clipped piece in 2D, made strictly convex: repeated points, straight vertices and the
// (rounding-sized) reflex dents that rounded crossings can leave are dropped.
bool to_convex_ring(const FaceData& fd, const Polygon3& poly, Ring2& ring) {
  ring = fd.project(poly);
  Ring2 r;
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

// ---- Pieces and the broad phase ----

struct PieceData {
  explicit PieceData(Body b) : shape(std::move(b)) {}
  int body = 0;  // index into Impl::bodies
  Body shape;
  std::vector<ExactPlane> planes;  // face planes (face_plane)
  Eigen::AlignedBox3d box;
  Vec3 centre = Vec3::Zero();
  double radius = 0;
};

struct BodyData {
  explicit BodyData(Body b) : body(std::move(b)) {}
  int scene_index = 0;
  std::string name;
  Body body;
  bool convex = true;
  std::vector<int> pieces;
  std::vector<FaceData> faces;
  /// Non-convex body: for each face, its own pieces that have a face on the face's plane. Such
  /// a piece lies on the inner side of that plane and can never hide a point of the face from
  /// a viewpoint turned to it; its rounded coordinates (a rotated body) may put its face plane
  /// a few ulps off, which must not turn the face into "shadow".
  std::vector<std::vector<int>> own_adjacent;
  bool skips(int face, int piece) const {
    if (convex) return true;  // a convex body hides nothing of its own faces
    const auto& v = own_adjacent[static_cast<size_t>(face)];
    return std::find(v.begin(), v.end(), piece) != v.end();
  }
};

// Does a face of `piece` lie on the plane of face `fd` of its body, up to the rounding of the
// decomposition's coordinates (kRoundingPlanarity × scale, same orientation)?
bool piece_on_face_plane(const Body& piece, const FaceData& fd, double scale) {
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

// For one viewpoint: which pieces can hide part of a face. Parallel view: a uniform grid over
// the pieces' boxes projected onto a plane across the direction, plus depth (a piece can only
// shadow what lies beyond its nearest point). Finite viewpoint: bounding cones from the point.
class CasterIndex {
 public:
  CasterIndex(const std::vector<PieceData>& pieces, const std::vector<OcclusionVolume>& volumes,
              const Viewpoint& view, double scale)
      : pieces_(pieces), volumes_(volumes), view_(view), margin_(1e-9 * scale) {
    if (!view.at_infinity) {
      for (size_t p = 0; p < pieces.size(); ++p)
        if (volumes[p].clipper) active_.push_back(static_cast<int>(p));
      return;
    }
    dir_ = view.direction.normalized();
    e1_ = dir_.unitOrthogonal();
    e2_ = dir_.cross(e1_);
    std::vector<int> ids;
    for (size_t p = 0; p < pieces.size(); ++p) {
      if (!volumes[p].clipper) continue;
      Bounds b = bounds(pieces[p].shape.vertices());
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

  // Calls f(piece) for each piece that may hide part of a region (a face, or a point): its
  // corners, and a bounding sphere (each piece once, in a deterministic order).
  template <class F>
  void candidates(const std::vector<Vec3>& corners, const Vec3& centre, double radius,
                  F&& f) const {
    if (!view_.at_infinity) {
      const Vec3 fc = centre - view_.point;
      const double fd = fc.norm();
      for (int p : active_) {
        const PieceData& piece = pieces_[static_cast<size_t>(p)];
        const Vec3 pc = piece.centre - view_.point;
        const double pd = pc.norm();
        const double pr = piece.radius + margin_, fr = radius + margin_;
        // Depth: the face's farthest point must lie beyond the piece's nearest.
        if (fd + fr < pd - pr) continue;
        if (pd > pr && fd > fr) {
          const double a = std::asin(std::min(1.0, pr / pd)) + std::asin(std::min(1.0, fr / fd));
          const double cosang = std::clamp(pc.dot(fc) / (pd * fd), -1.0, 1.0);
          if (a < std::numbers::pi && std::acos(cosang) > a + 1e-9) continue;
        }
        f(p);
      }
      return;
    }
    if (ids_.empty()) return;
    const Bounds fb = bounds(corners);
    // Each piece once: a per-thread stamp per piece (cell order is deterministic).
    thread_local std::vector<unsigned> stamp;
    thread_local unsigned generation = 0;
    if (stamp.size() < boxes_.size()) stamp.assign(boxes_.size(), 0);
    if (++generation == 0) {
      std::fill(stamp.begin(), stamp.end(), 0);
      generation = 1;
    }
    for_cells(fb, [&](size_t c) {
      for (int q = cells_[c]; q < cells_[c + 1]; ++q) {
        const size_t k = static_cast<size_t>(items_[static_cast<size_t>(q)]);
        if (stamp[k] == generation) continue;
        stamp[k] = generation;
        const Bounds& b = boxes_[k];
        if (b.lo.x() > fb.hi.x() || fb.lo.x() > b.hi.x() || b.lo.y() > fb.hi.y() ||
            fb.lo.y() > b.hi.y())
          continue;
        if (fb.depth_hi < b.depth_lo) continue;  // the face lies wholly before the piece
        f(ids_[k]);
      }
    });
  }

 private:
  struct Bounds {
    Vec2 lo, hi;
    double depth_lo, depth_hi;
  };
  Bounds bounds(const std::vector<Vec3>& pts) const {
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
  size_t cell(double v, double lo, double inv) const {
    const double x = (v - lo) * inv;
    if (!(x > 0)) return 0;
    return static_cast<size_t>(std::min(x, static_cast<double>(n_ - 1)));
  }
  template <class F>
  void for_cells(const Bounds& b, F&& f) const {
    const size_t x0 = cell(b.lo.x(), lo_.x(), inv_.x()), x1 = cell(b.hi.x(), lo_.x(), inv_.x());
    const size_t y0 = cell(b.lo.y(), lo_.y(), inv_.y()), y1 = cell(b.hi.y(), lo_.y(), inv_.y());
    for (size_t y = y0; y <= y1; ++y)
      for (size_t x = x0; x <= x1; ++x) f(y * static_cast<size_t>(n_) + x);
  }

  const std::vector<PieceData>& pieces_;
  const std::vector<OcclusionVolume>& volumes_;
  Viewpoint view_;
  double margin_;
  std::vector<int> active_;  // finite viewpoint
  Vec3 dir_ = Vec3::UnitZ(), e1_ = Vec3::UnitX(), e2_ = Vec3::UnitY();
  std::vector<Bounds> boxes_;
  std::vector<int> ids_;
  Vec2 lo_ = Vec2::Zero(), inv_ = Vec2::Ones();
  int n_ = 1;
  std::vector<int> cells_, items_;
};

ShadowPolygon lift_polygon(const FaceData& fd, const PolygonWithHoles2& p) {
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

// occlusion_volume() of occlusion.h on cached face planes: the same planes, built the
// same way (front faces, then the planes through the silhouette edges and the viewpoint or
// parallel to its direction, each oriented by a vertex strictly off it). Only the clipper is
// filled in (front_faces and silhouette stay empty: nothing here reads them).
OcclusionVolume volume_of(const PieceData& piece, const Viewpoint& view) {
  OcclusionVolume out;
  const Body& body = piece.shape;
  const size_t n = piece.planes.size();
  std::vector<char> front(n, 0);
  std::vector<ExactPlane> planes;
  for (size_t f = 0; f < n; ++f) {
    if (facing_of(piece.planes[f], view) != Facing::Front) continue;
    front[f] = 1;
    planes.push_back(piece.planes[f]);
  }
  if (planes.empty()) return out;
  const auto& v = body.vertices();
  for (const Edge& e : body.edges()) {
    if (front[static_cast<size_t>(e.left_face)] == front[static_cast<size_t>(e.right_face)])
      continue;
    const Vec3 &a = v[static_cast<size_t>(e.v0)], &b = v[static_cast<size_t>(e.v1)];
    ExactPlane plane;
    try {
      plane = view.at_infinity ? ExactPlane::through_direction(a, b, view.direction)
                               : ExactPlane::through(a, b, view.point);
    } catch (const InvalidInput&) {
      continue;  // the viewpoint on the edge's line: the front face bounds the volume there
    }
    // Orient by the vertex farthest from the plane (in double: only the choice of vertex),
    // which the exact test decides without its slow path.
    size_t far = 0;
    double far_value = -1;
    for (size_t k = 0; k < v.size(); ++k) {
      const double a = std::abs(plane.value(v[k]));
      if (a > far_value) {
        far_value = a;
        far = k;
      }
    }
    const Sign side = side_of_plane(plane, v[far]);
    if (side != Sign::Zero) planes.push_back(side == Sign::Positive ? plane : plane.flipped());
  }
  out.clipper = ConvexClipper::from_planes(std::move(planes));
  return out;
}

// Exact convexity (hedra/mesh/convexity.h's test: no vertex strictly outside a face plane) on the
// cached planes.
bool convex_by_planes(const Body& body, const std::vector<ExactPlane>& planes) {
  std::vector<int> on_face(static_cast<size_t>(body.vertex_count()), -1);
  for (size_t f = 0; f < planes.size(); ++f) {
    for (const auto& loop : body.faces()[f].loops)
      for (int id : loop) on_face[static_cast<size_t>(id)] = static_cast<int>(f);
    for (size_t k = 0; k < on_face.size(); ++k)
      if (on_face[k] != static_cast<int>(f) &&
          side_of_plane(planes[f], body.vertices()[k]) == Sign::Negative)
        return false;
  }
  return true;
}

template <class F>
void parallel_for_n(size_t n, int threads, F&& f) {
  auto run = [&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i != r.end(); ++i) f(i);
                      });
  };
  if (threads == 1) {
    for (size_t i = 0; i < n; ++i) f(i);
  } else if (threads > 1) {
    tbb::task_arena arena(threads);
    arena.execute(run);
  } else {
    run();
  }
}

}  // namespace

double FaceShadow::lit_fraction() const {
  if (area <= 0) return 0;
  return std::clamp(1 - shadow_area / area, 0.0, 1.0);
}

struct ShadowScene::Impl {
  Camera camera;
  std::vector<BodyData> bodies;
  std::vector<PieceData> pieces;
  std::vector<int> first_face;             // per scene body
  std::vector<std::pair<int, int>> faces;  // (body data, face) in result order
  double scale = 1;

  // The 2D shadow pieces of face (b, f) from a viewpoint: the face's convex parts clipped
  // against the occlusion volumes of the candidate pieces.
  void hidden_pieces(int b, int f, const CasterIndex& index,
                     const std::vector<OcclusionVolume>& volumes, std::vector<Ring2>& out) const {
    const BodyData& bd = bodies[static_cast<size_t>(b)];
    const FaceData& fd = bd.faces[static_cast<size_t>(f)];
    const std::vector<Vec3>& corners = fd.corners;
    thread_local Polygon3 clipped, scratch;
    thread_local std::vector<Sign> side;
    thread_local Ring2 ring;
    index.candidates(corners, fd.centre, fd.radius, [&](int p) {
      // A convex body never hides its own faces; pieces of a non-convex one may.
      if (pieces[static_cast<size_t>(p)].body == b && bd.skips(f, p)) return;
      const ConvexClipper& clipper = *volumes[static_cast<size_t>(p)].clipper;
      fd.for_parts([&](const Polygon3& part) {
        if (clip_convex(part, clipper, clipped, scratch, side) && to_convex_ring(fd, clipped, ring))
          out.push_back(ring);
      });
    });
  }

  bool point_hidden(int b, int f, const Vec3& p, const CasterIndex& index,
                    const std::vector<OcclusionVolume>& volumes) const {
    const BodyData& bd = bodies[static_cast<size_t>(b)];
    const FaceData& fd = bd.faces[static_cast<size_t>(f)];
    bool hidden = false;
    index.candidates({p}, p, 0, [&](int q) {
      if (hidden || (pieces[static_cast<size_t>(q)].body == b && bd.skips(f, q))) return;
      hidden = hides(volumes[static_cast<size_t>(q)], p);
    });
    return hidden;
  }

  std::vector<OcclusionVolume> volumes(const Viewpoint& view, int threads) const {
    std::vector<OcclusionVolume> v(pieces.size());
    parallel_for_n(pieces.size(), threads, [&](size_t p) { v[p] = volume_of(pieces[p], view); });
    return v;
  }
};

ShadowScene::ShadowScene(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.camera = scene.camera;
  const Eigen::AlignedBox3d box = scene.bbox();
  m.scale = box.isEmpty() ? 1
                          : std::max({box.diagonal().norm(), box.min().cwiseAbs().maxCoeff(),
                                      box.max().cwiseAbs().maxCoeff(), 1e-300});
  m.first_face.assign(scene.bodies().size(), -1);
  int next_face = 0;
  m.bodies.reserve(scene.bodies().size());
  for (size_t s = 0; s < scene.bodies().size(); ++s) {
    const SceneBody& sb = scene.bodies()[s];
    if (sb.hidden) continue;
    BodyData bd(sb.body);
    bd.scene_index = static_cast<int>(s);
    bd.name = sb.name;
    m.first_face[s] = next_face;
    next_face += sb.body.face_count();
    m.bodies.push_back(std::move(bd));
  }
  // Convex pieces (decomposing only the non-convex bodies) and face data, in parallel.
  std::vector<std::vector<Body>> pieces(m.bodies.size());
  std::vector<std::vector<std::vector<ExactPlane>>> piece_planes(m.bodies.size());
  parallel_for_n(m.bodies.size(), 0, [&](size_t b) {
    BodyData& bd = m.bodies[b];
    bd.faces.reserve(static_cast<size_t>(bd.body.face_count()));
    for (int f = 0; f < bd.body.face_count(); ++f) bd.faces.push_back(make_face(bd.body, f));
    std::vector<ExactPlane> planes;
    for (const FaceData& fd : bd.faces) planes.push_back(fd.plane);
    bd.convex = convex_by_planes(bd.body, planes);
    if (bd.convex) {
      pieces[b].push_back(bd.body);
      piece_planes[b].push_back(std::move(planes));
    } else {
      try {
        pieces[b] = decompose(bd.body).pieces;
      } catch (const InvalidInput& e) {
        throw InvalidInput("body '" + bd.name + "': " + e.what());
      }
      for (const Body& piece : pieces[b]) {
        std::vector<ExactPlane> pp;
        for (int f = 0; f < piece.face_count(); ++f) pp.push_back(face_plane(piece, f));
        piece_planes[b].push_back(std::move(pp));
      }
    }
  });
  size_t total_pieces = 0;
  for (const auto& p : pieces) total_pieces += p.size();
  m.pieces.reserve(total_pieces);
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    for (size_t k = 0; k < pieces[b].size(); ++k) {
      PieceData pd(std::move(pieces[b][k]));
      pd.planes = std::move(piece_planes[b][k]);
      pd.body = static_cast<int>(b);
      pd.box = pd.shape.bbox();
      pd.centre = pd.box.center();
      pd.radius = 0.5 * pd.box.diagonal().norm();
      m.bodies[b].pieces.push_back(static_cast<int>(m.pieces.size()));
      m.pieces.push_back(std::move(pd));
    }
    BodyData& bd = m.bodies[b];
    if (!bd.convex) {
      bd.own_adjacent.resize(bd.faces.size());
      const double scale = bd.body.scale();
      for (size_t f = 0; f < bd.faces.size(); ++f)
        for (int p : bd.pieces)
          if (piece_on_face_plane(m.pieces[static_cast<size_t>(p)].shape, bd.faces[f], scale))
            bd.own_adjacent[f].push_back(p);
    }
    for (int f = 0; f < bd.body.face_count(); ++f) m.faces.emplace_back(static_cast<int>(b), f);
  }
}

ShadowScene::~ShadowScene() = default;
ShadowScene::ShadowScene(ShadowScene&&) noexcept = default;
ShadowScene& ShadowScene::operator=(ShadowScene&&) noexcept = default;

int ShadowScene::piece_count() const { return static_cast<int>(impl_->pieces.size()); }

ShadowResult ShadowScene::compute(const std::vector<Light>& lights,
                                  const ShadowOptions& options) const {
  const Impl& m = *impl_;
  ShadowResult result;
  result.first_face = m.first_face;
  const size_t nf = m.faces.size();
  const bool keep_pieces =
      options.polygons && (options.visible_parts || (options.counts && lights.size() >= 2));
  // 2D shadow pieces per light and face, kept for the visible parts and the counts.
  std::vector<std::vector<std::vector<Ring2>>> kept(lights.size());

  for (size_t l = 0; l < lights.size(); ++l) {
    lights[l].validate();
    const Viewpoint view = Viewpoint::of(lights[l]);
    const Viewpoint eye = Viewpoint::of(m.camera);
    LightShadows ls;
    ls.light = lights[l];
    ls.faces.resize(nf);
    std::vector<OcclusionVolume> volumes;
    std::optional<CasterIndex> index;
    if (options.cast) {
      volumes = m.volumes(view, options.threads);
      index.emplace(m.pieces, volumes, view, m.scale);
    }
    if (keep_pieces) kept[l].resize(nf);
    parallel_for_n(nf, options.threads, [&](size_t i) {
      const auto [b, f] = m.faces[i];
      const BodyData& bd = m.bodies[static_cast<size_t>(b)];
      const FaceData& fd = bd.faces[static_cast<size_t>(f)];
      FaceShadow& fs = ls.faces[i];
      fs.body = bd.scene_index;
      fs.face = f;
      fs.area = fd.area;
      fs.to_light = facing_of(fd.plane, view);
      fs.visible = facing_of(fd.plane, eye) == Facing::Front;
      if (fs.to_light == Facing::Back) {
        fs.shadow_area = fs.area;
        if (options.polygons) fs.polygons.push_back(whole_face(bd.body, f));
        if (keep_pieces) kept[l][i] = fd.parts2d();
        return;
      }
      if (!options.cast) return;
      std::vector<Ring2> rings;
      m.hidden_pieces(b, f, *index, volumes, rings);
      if (rings.empty()) return;
      const UnionResult u = unite_convex(rings, options.polygons);
      fs.shadow_area = std::min(u.area * fd.area_factor, fs.area);
      for (const PolygonWithHoles2& p : u.polygons) fs.polygons.push_back(lift_polygon(fd, p));
      if (keep_pieces) kept[l][i] = std::move(rings);
    });
    result.lights.push_back(std::move(ls));
  }

  // Visible parts: the shadow minus what other pieces hide from the eye.
  if (options.polygons && options.visible_parts && !lights.empty()) {
    const Viewpoint eye = Viewpoint::of(m.camera);
    const std::vector<OcclusionVolume> eye_volumes = m.volumes(eye, options.threads);
    const CasterIndex eye_index(m.pieces, eye_volumes, eye, m.scale);
    parallel_for_n(nf, options.threads, [&](size_t i) {
      const auto [b, f] = m.faces[i];
      const FaceData& fd = m.bodies[static_cast<size_t>(b)].faces[static_cast<size_t>(f)];
      bool any = false;
      for (size_t l = 0; l < lights.size(); ++l) any = any || !kept[l][i].empty();
      if (!any || !result.lights[0].faces[i].visible) return;
      std::vector<Ring2> hidden;
      m.hidden_pieces(b, f, eye_index, eye_volumes, hidden);
      for (size_t l = 0; l < lights.size(); ++l) {
        FaceShadow& fs = result.lights[l].faces[i];
        if (kept[l][i].empty()) continue;
        if (hidden.empty()) {
          fs.visible_polygons = fs.polygons;
          fs.visible_shadow_area = fs.shadow_area;
          continue;
        }
        const UnionResult v = cgal_difference(kept[l][i], hidden);
        for (const PolygonWithHoles2& p : v.polygons)
          fs.visible_polygons.push_back(lift_polygon(fd, p));
        fs.visible_shadow_area = v.area * fd.area_factor;
      }
    });
  }

  // Several lights: regions by the number of lights they are shadowed from.
  if (options.polygons && options.counts && lights.size() >= 2) {
    std::vector<std::vector<ShadowCount>> per_face(nf);
    parallel_for_n(nf, options.threads, [&](size_t i) {
      const auto [b, f] = m.faces[i];
      const BodyData& bd = m.bodies[static_cast<size_t>(b)];
      const FaceData& fd = bd.faces[static_cast<size_t>(f)];
      // A light the face turns its back to shadows all of it: it adds one to every count.
      // Only the lights with cast shadows need Boolean operations.
      int whole = 0;
      std::vector<size_t> partial;
      for (size_t l = 0; l < lights.size(); ++l) {
        if (result.lights[l].faces[i].to_light == Facing::Back)
          ++whole;
        else if (!kept[l][i].empty())
          partial.push_back(l);
      }
      if (whole == 0 && partial.empty()) return;
      auto add = [&, f = f](int count, double area, std::vector<ShadowPolygon> polys) {
        per_face[i].push_back({bd.scene_index, f, count, area, std::move(polys)});
      };
      auto lifted = [&](const UnionResult& u) {
        std::vector<ShadowPolygon> polys;
        for (const PolygonWithHoles2& p : u.polygons) polys.push_back(lift_polygon(fd, p));
        return polys;
      };
      if (partial.empty()) {
        add(whole, fd.area, {whole_face(bd.body, f)});
        return;
      }
      // The face outside every cast shadow keeps the count of the wholly shadowing lights.
      if (whole > 0) {
        std::vector<Ring2> all;
        for (size_t l : partial) all.insert(all.end(), kept[l][i].begin(), kept[l][i].end());
        const UnionResult rest = cgal_difference(fd.parts2d(), all);
        if (!rest.polygons.empty()) add(whole, rest.area * fd.area_factor, lifted(rest));
      }
      if (partial.size() == 1) {
        const FaceShadow& fs = result.lights[partial[0]].faces[i];
        add(whole + 1, fs.shadow_area, fs.polygons);
        return;
      }
      std::vector<std::vector<Ring2>> sets;
      for (size_t l : partial) sets.push_back(kept[l][i]);
      const std::vector<UnionResult> levels = cgal_coverage_levels(sets);
      for (size_t k = 0; k < levels.size(); ++k)
        if (!levels[k].polygons.empty())
          add(whole + static_cast<int>(k + 1), levels[k].area * fd.area_factor, lifted(levels[k]));
    });
    for (auto& v : per_face)
      for (ShadowCount& c : v) result.counts.push_back(std::move(c));
  }
  return result;
}

ShadowResult compute_shadows(const Scene& scene, const ShadowOptions& options) {
  return ShadowScene(scene).compute(scene.lights, options);
}

bool in_shadow(const Scene& scene, const Light& light, int body, int face, const Vec3& p) {
  const SceneBody& sb = scene.bodies().at(static_cast<size_t>(body));
  if (sb.hidden || face < 0 || face >= sb.body.face_count())
    throw InvalidInput("in_shadow: no such face of a visible body");
  light.validate();
  const ShadowScene prepared(scene);
  const ShadowScene::Impl& m = *prepared.impl_;
  int b = 0;
  while (m.bodies[static_cast<size_t>(b)].scene_index != body) ++b;
  const Viewpoint view = Viewpoint::of(light);
  if (facing_of(m.bodies[static_cast<size_t>(b)].faces[static_cast<size_t>(face)].plane, view) ==
      Facing::Back)
    return true;
  const std::vector<OcclusionVolume> volumes = m.volumes(view, 1);
  const CasterIndex index(m.pieces, volumes, view, m.scale);
  return m.point_hidden(b, face, p, index, volumes);
}

bool point_in_polygons(const std::vector<ShadowPolygon>& polygons, const Vec3& p) {
  // One projection for all: the polygons lie on one plane and share the orientation of their
  // outer rings, so the sum of their Newell vectors is the plane's normal (a sliver alone
  // could point anywhere).
  Vec3 n = Vec3::Zero();
  for (const ShadowPolygon& poly : polygons) n += polygon_normal(poly.outer);
  int k;
  n.cwiseAbs().maxCoeff(&k);
  for (const ShadowPolygon& poly : polygons) {
    auto inside = [&](const Polygon3& ring, bool& on) {
      const Vec2 q = drop(p, k);
      bool in = false;
      on = false;
      for (size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
        const Vec2 a = drop(ring[i], k), b = drop(ring[j], k);
        if (orient2d(a, b, q) == Sign::Zero && q.x() >= std::min(a.x(), b.x()) &&
            q.x() <= std::max(a.x(), b.x()) && q.y() >= std::min(a.y(), b.y()) &&
            q.y() <= std::max(a.y(), b.y())) {
          on = true;
          return true;
        }
        if ((a.y() > q.y()) != (b.y() > q.y())) {
          // Crossing of the horizontal ray to the right: decided by orientation.
          const Sign s = orient2d(a, b, q);
          if ((b.y() > a.y()) == (s == Sign::Negative)) in = !in;
        }
      }
      return in;
    };
    bool on = false;
    if (!inside(poly.outer, on)) continue;
    if (on) return true;
    bool in_hole = false;
    for (const Polygon3& h : poly.holes) {
      bool on_hole = false;
      if (inside(h, on_hole) && !on_hole) in_hole = true;
    }
    if (!in_hole) return true;
  }
  return false;
}

// ---- Time ----

namespace {

// Days from 1970-01-01 to y-m-d (proleptic Gregorian; H. Hinnant's algorithm).
int64_t days_from_civil(int64_t y, unsigned m, unsigned d) {
  y -= m <= 2;
  const int64_t era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<int64_t>(doe) - 719468;
}

void civil_from_days(int64_t z, int& y, int& m, int& d) {
  z += 719468;
  const int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const unsigned doe = static_cast<unsigned>(z - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  d = static_cast<int>(doy - (153 * mp + 2) / 5 + 1);
  m = static_cast<int>(mp < 10 ? mp + 3 : mp - 9);
  y = static_cast<int>(static_cast<int64_t>(yoe) + era * 400 + (m <= 2));
}

double seconds_of(const UtcTime& t) {
  return static_cast<double>(days_from_civil(t.year, static_cast<unsigned>(t.month),
                                             static_cast<unsigned>(t.day))) *
             86400.0 +
         t.hour * 3600.0 + t.minute * 60.0 + t.second;
}

}  // namespace

double minutes_between(const UtcTime& a, const UtcTime& b) {
  return (seconds_of(b) - seconds_of(a)) / 60;
}

UtcTime add_minutes(const UtcTime& t, double minutes) {
  const double s = seconds_of(t) + minutes * 60;
  const double day = std::floor(s / 86400);
  double rest = s - day * 86400;
  UtcTime out;
  civil_from_days(static_cast<int64_t>(day), out.year, out.month, out.day);
  // Round to the millisecond so that steps of whole minutes stay whole.
  rest = std::round(rest * 1000) / 1000;
  if (rest >= 86400) rest = 86399.999;
  out.hour = static_cast<int>(rest / 3600);
  rest -= out.hour * 3600.0;
  out.minute = static_cast<int>(rest / 60);
  out.second = rest - out.minute * 60.0;
  if (out.second < 0) out.second = 0;
  return out;
}

// ---- Sun studies ----

SunStudy sun_study(const Scene& scene, const SunStudyOptions& options) {
  if (!(options.step_minutes > 0) || !std::isfinite(options.step_minutes))
    throw InvalidInput("sun study: the step must be a positive number of minutes");
  const double span = minutes_between(options.start, options.end);
  if (span < 0)
    throw InvalidInput("sun study: the end " + options.end.to_string() + " is before the start " +
                       options.start.to_string());
  const double count = std::floor(span / options.step_minutes + 1e-9);
  if (count > 10000) throw InvalidInput("sun study: more than 10000 steps");
  sun_position(options.latitude, options.longitude, options.start);  // validates the place

  const ShadowScene prepared(scene);
  const ShadowScene::Impl& m = *prepared.impl_;
  SunStudy study;
  study.first_face = m.first_face;
  const size_t nf = m.faces.size();
  study.sun_hours.assign(nf, 0);

  // The grid on the chosen face.
  int grid_b = -1, grid_f = options.grid_face;
  if (!options.grid_body.empty()) {
    for (size_t b = 0; b < m.bodies.size(); ++b)
      if (m.bodies[b].name == options.grid_body) grid_b = static_cast<int>(b);
    if (grid_b < 0)
      throw InvalidInput("sun study: no visible body named '" + options.grid_body + "'");
    const Body& body = m.bodies[static_cast<size_t>(grid_b)].body;
    if (grid_f < 0 || grid_f >= body.face_count())
      throw InvalidInput("sun study: body '" + options.grid_body + "' has no face " +
                         std::to_string(grid_f));
    if (!(options.grid_spacing > 0))
      throw InvalidInput("sun study: the grid spacing must be positive");
    const FaceData& fd = m.bodies[static_cast<size_t>(grid_b)].faces[static_cast<size_t>(grid_f)];
    // Sample the face's 2D box at cell centres; keep points strictly inside a convex part.
    Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
    const std::vector<Ring2> parts2d = fd.parts2d();
    for (const Ring2& r : parts2d)
      for (const Vec2& q : r) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
    const double s = options.grid_spacing / std::sqrt(fd.area_factor);  // spacing along the face
    // Counted in double first: a tiny spacing would overflow a long (1e-300 gives 1e300).
    const double cells_x = std::ceil((hi.x() - lo.x()) / s), cells_y = std::ceil((hi.y() - lo.y()) / s);
    if (!(cells_x * cells_y <= 1000000))
      throw InvalidInput("sun study: the grid has more than a million points");
    const long nx = static_cast<long>(cells_x), ny = static_cast<long>(cells_y);
    for (long y = 0; y < ny; ++y)
      for (long x = 0; x < nx; ++x) {
        const Vec2 q(lo.x() + (x + 0.5) * s, lo.y() + (y + 0.5) * s);
        bool inside = false;
        for (const Ring2& r : parts2d) {
          bool in = true;
          for (size_t i = 0; i < r.size() && in; ++i)
            in = orient2d(r[i], r[(i + 1) % r.size()], q) == Sign::Positive;
          inside = inside || in;
        }
        if (inside) study.grid_points.push_back(fd.lift(q));
      }
    study.grid_hours.assign(study.grid_points.size(), 0);
  }

  std::vector<double> grid_prev(study.grid_points.size(), 0);
  ShadowOptions so;
  so.polygons = false;
  so.counts = false;
  so.threads = options.threads;
  const long steps = static_cast<long>(count);
  double prev_time = 0;
  for (long k = 0; k <= steps + 1; ++k) {
    double minutes = k * options.step_minutes;
    if (k == steps + 1) {
      if (span - steps * options.step_minutes <= 1e-9) break;  // end already sampled
      minutes = span;
    }
    SunStep step;
    step.time = add_minutes(options.start, minutes);
    const SunPosition sun = sun_position(options.latitude, options.longitude, step.time);
    step.elevation_deg = sun.elevation_deg;
    step.azimuth_deg = sun.azimuth_deg;
    step.sun_up = sun.elevation_deg > 0;
    step.lit_fraction.assign(nf, 0);
    std::vector<double> grid_now(study.grid_points.size(), 0);
    if (step.sun_up) {
      Light light;
      light.type = Light::Type::Sun;
      light.latitude = options.latitude;
      light.longitude = options.longitude;
      light.time = step.time;
      light.direction = -sun.towards_sun;
      const ShadowResult r = prepared.compute({light}, so);
      for (size_t i = 0; i < nf; ++i) {
        const FaceShadow& fs = r.lights[0].faces[i];
        step.lit_fraction[i] = fs.to_light == Facing::Front ? fs.lit_fraction() : 0;
      }
      if (!study.grid_points.empty()) {
        const Viewpoint view = Viewpoint::of(light);
        const BodyData& bd = m.bodies[static_cast<size_t>(grid_b)];
        if (facing_of(bd.faces[static_cast<size_t>(grid_f)].plane, view) == Facing::Front) {
          const std::vector<OcclusionVolume> volumes = m.volumes(view, options.threads);
          const CasterIndex index(m.pieces, volumes, view, m.scale);
          parallel_for_n(study.grid_points.size(), options.threads, [&](size_t g) {
            grid_now[g] =
                m.point_hidden(grid_b, grid_f, study.grid_points[g], index, volumes) ? 0 : 1;
          });
        }
      }
    }
    // Trapezoid rule between this step and the previous one.
    if (!study.steps.empty()) {
      const double hours = (minutes - prev_time) / 60;
      const SunStep& last = study.steps.back();
      for (size_t i = 0; i < nf; ++i)
        study.sun_hours[i] += 0.5 * (last.lit_fraction[i] + step.lit_fraction[i]) * hours;
      for (size_t g = 0; g < grid_now.size(); ++g)
        study.grid_hours[g] += 0.5 * (grid_prev[g] + grid_now[g]) * hours;
    }
    prev_time = minutes;
    grid_prev = std::move(grid_now);
    study.steps.push_back(std::move(step));
  }
  return study;
}

}  // namespace hedra
