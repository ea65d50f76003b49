// Internals of shadows (hedra/visibility/shadows.h, sun_study.h): faces in their 2D frames
// and their convex parts (shadow_faces.cpp), the convex pieces and the caster index
// (shadow_casters.cpp), the prepared scene (shadows.cpp) and sun studies (sun_study.cpp).
#pragma once

#include <Eigen/Geometry>

#include <algorithm>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <array>
#include <optional>
#include <span>
#include <vector>

#include "hedra/decompose/decompose.h"
#include "hedra/visibility/polygon_union.h"
#include "hedra/visibility/shadows.h"

namespace hedra::internal {

// ---- Faces in their own 2D frame ----
//
// A face is projected onto the coordinate plane of its normal's dominant axis k, keeping
// (p[k+1], p[k+2]) (cyclic): dropping a coordinate is exact, so exact 3D input points stay
// exact 2D points, and the 2D predicates on them decide exactly. 2D rings are
// counter-clockwise; `flip` says the face's own orientation (counter-clockwise seen from
// outside) is clockwise in 2D.

inline Vec2 drop(const Vec3& p, int k) { return {p[(k + 1) % 3], p[(k + 2) % 3]}; }

struct ShadowFace {
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
  Vec3 centre = Vec3::Zero();
  double radius = 0;
  ExactPlane plane;           // through the face's support triple: Positive inner (face_side)
  bool planar = true;         // every vertex exactly on `plane` (else planar within rounding)
  std::vector<Vec3> corners;  // the outer loop
  // A convex face off its plane: `parts` are its triangles along the diagonals that keep the
  // body convex (convex_polygon_split, exactly_planar_convex's), each on its own exact plane here, so that the
  // face receives on the surface that occludes; empty: every part lies on `plane`.
  std::vector<ExactPlane> part_planes;
  // Those triangles as positions in `corners` (convex_polygon_split's), for the body's convex
  // piece (exactly_planar_convex), which then need not cut the face again.
  std::vector<std::array<int, 3>> split;
  // Strictly on the outer side of the face (of one of its parts' planes): a point that can lie
  // between the viewpoint and some point of the face. Exact.
  bool outside(const Vec3& p) const {
    if (side_of_plane(plane, p) == Sign::Negative) return true;
    for (const ExactPlane& q : part_planes)
      if (side_of_plane(q, p) == Sign::Negative) return true;
    return false;
  }

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

/// The face's data: its exact plane, 2D frame, box and convex parts. Cost O(n²) in the face's
/// triangles when it is not convex (greedy merging), else O(n).
ShadowFace make_face(const Body& body, int f);

/// A clipped piece in 2D, made strictly convex (see shadow_faces.cpp); false when nothing of
/// positive area is left. Cost O(n²) worst case, O(n) in practice.
bool to_convex_ring(const ShadowFace& fd, const Polygon3& poly, Ring2& ring);

/// A 2D polygon of the face lifted onto the face's plane, with its 3D area, rounding debris
/// removed (kShadowDebris × scale, the scene's scale): appended to `out` unless its outer ring
/// is debris. Cost O(n).
void lift_polygon(const ShadowFace& fd, const PolygonWithHoles2& p, double scale,
                  std::vector<ShadowPolygon>& out);

/// The whole face as a shadow polygon (self shadow). Cost O(n).
ShadowPolygon whole_face(const Body& body, int f);

// ---- Pieces and the broad phase ----

struct ShadowPiece {
  int body = 0;  // index into Impl::bodies
  // A triangle of a face of a body occluding by its faces (Occluders::Faces): that face. It
  // occludes only from viewpoints its face 0 (the body face's orientation) turns to.
  int face = -1;
  // A convex piece: its Body, face planes and exact faces. Null for a triangle of a body
  // occluding by its faces, which keeps only its corners: a million-face mesh makes a million
  // triangles, so they carry no Body and no empty vectors (136 bytes a triangle, not 208).
  struct Convex {
    explicit Convex(Body b) : shape(std::move(b)) {}
    Body shape;
    std::vector<ExactPlane> planes;  // its face planes (exact_face_plane)
    // The exact piece's faces (Decomposition::piece_planes); empty: none given.
    std::vector<std::pair<int, int>> exact_planes;
    // The exact piece as planes (Decomposition::exact_pieces); null: none (a convex body, a
    // piece that is not exactly convex). When set, its occlusion volume is built from it.
    std::shared_ptr<const ExactConvex> exact;
    int slot = 0;  // its occlusion volume in PieceVolumes::volumes
  };
  std::unique_ptr<Convex> convex;
  std::array<Vec3, 3> triangle{};
  std::span<const Vec3> vertices() const {
    if (convex) return convex->shape.vertices();
    return triangle;
  }
  // A triangle: its exact plane, triangle_plane(triangle). That is the plane of its face when
  // the face is a triangle listed from the same corner (ShadowFace::plane, not copied: 160
  // bytes a triangle), else own_triangle_plane.
  const ExactPlane* triangle_plane = nullptr;
  std::unique_ptr<ExactPlane> own_triangle_plane;
  // A triangle of a two-sided surface (Body::two_sided_surface): the plane of its other side,
  // the triangle reversed (its twin face's plane when that is the same triangle, else
  // own_back_plane). The surface keeps one piece per triangle of its front side, which
  // occludes from either side: from a viewpoint its face turns away from, as the triangle
  // reversed (PieceVolumes::active 2), so the other side's coincident triangles are not pieces.
  const ExactPlane* back_plane = nullptr;
  std::unique_ptr<ExactPlane> own_back_plane;
  Vec3 centre = Vec3::Zero();
  double radius = 0;
  // The triangle as it occludes from a viewpoint on the side `active` says (1 front, 2 back).
  std::array<Vec3, 3> turned(char active) const {
    return active == 2 ? std::array<Vec3, 3>{triangle[0], triangle[2], triangle[1]} : triangle;
  }
  const ExactPlane& turned_plane(char active) const { return active == 2 ? *back_plane : *triangle_plane; }
};

struct ShadowBody {
  explicit ShadowBody(Body b) : body(std::move(b)) {}
  int scene_index = 0;
  std::string name;
  Body body;
  bool convex = true;
  std::vector<int> pieces;
  std::vector<ShadowFace> faces;
  /// Non-convex body: for each face, its own pieces that have a face on the face's plane. Such
  /// a piece lies on the inner side of that plane and can never hide a point of the face from
  /// a viewpoint turned to it; its rounded coordinates (a rotated body) may put its face plane
  /// a few ulps off, which must not turn the face into "shadow".
  std::vector<std::vector<int>> own_adjacent;
  InputPlanes input_planes;  // non-convex body: its decomposition's exact planes
  // Non-convex, occluding by its faces: its pieces are its faces' triangles (ShadowPiece::face).
  bool faceted = false;
  bool skips(int face, int piece, const ShadowPiece& pd) const {
    if (convex) return true;  // a convex body hides nothing of its own faces
    // A triangle of the face itself lies on it (a face planar within rounding: an ulp off).
    if (faceted) return pd.face == face || (body.two_sided() && pd.face == body.twin_face(face));
    const auto& v = own_adjacent[static_cast<size_t>(face)];
    return std::find(v.begin(), v.end(), piece) != v.end();
  }
};

/// Does a face of `piece` lie on the plane of face `fd` of its body, up to the rounding of the
/// decomposition's coordinates (kRoundingPlanarity × scale, same orientation)? The fallback
/// where the decomposition gave no exact planes; otherwise the exact piece has a face on one
/// of the face's canonical planes with the same sign (Decomposition::piece_planes,
/// InputPlanes::face_planes), which shadows.cpp decides. Cost O(faces).
bool piece_on_face_plane(const Body& piece, const ShadowFace& fd, double scale);

// The pieces' occlusion from one viewpoint (ShadowScene::Impl::volumes): which pieces occlude
// at all (a face turned to the viewpoint) and the occlusion volumes of the convex pieces. A
// triangle of a body occluding by its faces keeps no volume: a million-face mesh made half a
// million of them (0.7 s and about 500 MB), of which a shadow clips against few, since most
// candidates are settled before (projected whole, or behind the face). volume_of builds it when
// a clip needs it.
struct PieceVolumes {
  std::vector<OcclusionVolume> volumes;  // per convex piece (ShadowPiece::Convex::slot)
  // Per piece: it occludes from the viewpoint (1; 2 for a two-sided surface's triangle seen
  // from its back, which occludes reversed: ShadowPiece::back_plane).
  std::vector<char> active;
  Viewpoint view;
  // The volume of piece p (active): the stored one, or a triangle's built in a per-thread
  // scratch, valid until this thread's next call. Cost O(1) for a triangle.
  const OcclusionVolume& volume_of(const std::vector<ShadowPiece>& pieces, int p) const {
    const ShadowPiece& piece = pieces[static_cast<size_t>(p)];
    if (piece.convex) return volumes[static_cast<size_t>(piece.convex->slot)];
    thread_local OcclusionVolume scratch;
    const char side = active[static_cast<size_t>(p)];
    scratch = triangle_occlusion_volume(piece.turned(side), piece.turned_plane(side), view);
    return scratch;
  }
};

// For one viewpoint: which pieces can hide part of a face. Parallel view: a uniform grid over
// the pieces' boxes projected onto a plane across the direction, plus depth (a piece can only
// shadow what lies beyond its nearest point). Finite viewpoint: bounding cones from the point.
class CasterIndex {
 public:
  // Cost O(pieces + cells listed); `threads` as ShadowOptions::threads.
  CasterIndex(const std::vector<ShadowPiece>& pieces, const PieceVolumes& volumes,
              const Viewpoint& view, double scale, int threads = 0);

  const Viewpoint& view() const { return view_; }

  // Calls f(piece) for each piece that may hide part of a region (a face, or a point): its
  // corners, and a bounding sphere (each piece once, in a deterministic order).
  template <class F>
  void candidates(const std::vector<Vec3>& corners, const Vec3& centre, double radius,
                  F&& f) const {
    if (!view_.at_infinity) {
      const Vec3 fc = centre - view_.point;
      const double fd = fc.norm();
      const double fr = radius + margin_;
      const double sb = std::min(1.0, fr / fd), cb = std::sqrt(1 - sb * sb);
      // The pieces whose cones of directions may meet the region's, from the angular grid,
      // in ascending order (the order of a plain scan: results do not depend on the index).
      // Each candidate is tested as it is found and only the survivors are sorted (on a
      // million-face mesh the sort of every candidate was 5 % of `render`).
      const auto keep = [&](int slot) {
        const ConeTest& t = tests_[static_cast<size_t>(slot)];
        // Depth: the face's farthest point must lie beyond the piece's nearest.
        if (fd + fr < t.pd - t.pr) return false;
        if (t.pd > t.pr && fd > fr) {
          // The cones (half-angles α, β: sin α = pr / pd, sin β = fr / fd) are apart when the
          // angle between their axes exceeds α + β + 1e-9: its cosine below cos(α + β + 1e-9)
          // ≈ cos(α + β) − 1e-9 sin(α + β), less a rounding slack (no asin or acos: this runs
          // for every candidate of every face; the piece's half is computed once, ConeTest).
          const double cos_sum = t.ca * cb - t.sa * sb, sin_sum = t.sa * cb + t.ca * sb;
          if (t.pc.dot(fc) / (t.pd * fd) < cos_sum - 1e-9 * sin_sum - 1e-14) return false;
        }
        return true;
      };
      thread_local std::vector<int> found;
      thread_local std::vector<unsigned> seen;
      thread_local unsigned visit = 0;
      found.clear();
      for (int slot : always_)
        if (keep(slot)) found.push_back(slot);
      if (seen.size() < tests_.size()) seen.assign(tests_.size(), 0);
      if (++visit == 0) {
        std::fill(seen.begin(), seen.end(), 0);
        visit = 1;
      }
      for_cone(cone_of(fc, fd, fr), [&](size_t c) {
        for (int q = cells_[c]; q < cells_[c + 1]; ++q) {
          const int slot = items_[static_cast<size_t>(q)];
          if (seen[static_cast<size_t>(slot)] == visit) continue;
          seen[static_cast<size_t>(slot)] = visit;
          if (keep(slot)) found.push_back(slot);
        }
      });
      // Slots follow piece order: sorted slots are pieces in ascending order.
      std::sort(found.begin(), found.end());
      for (int slot : found) f(ids_[static_cast<size_t>(slot)]);
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
  Bounds bounds(std::span<const Vec3> pts) const;
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

  // Finite viewpoint: a grid over the directions from it, in a frame whose equator passes
  // through the mean direction of the pieces (φ = 0 there: the poles and the seam at φ = ±π
  // lie away from them): colatitude θ from axis az_, longitude φ from ax_ towards ay_. The grid
  // spans the θ and φ ranges of the small pieces' cones, n_theta_ × n_phi_ cells; a piece is
  // listed in every cell its cone of directions (its bounding sphere seen from the viewpoint,
  // widened by a margin) may meet; pieces with a wide cone (containing the viewpoint, near a
  // pole, or wider than kWideCone) are in always_. Coordinates outside the ranges clamp to the
  // border cells, for pieces and queries alike, so a shared direction stays a shared cell.
  struct Cone {
    double t0, t1, p0, p1;
    bool all_phi;
  };
  static constexpr double kWideCone = 0.25;  // radians
  Cone cone_of(const Vec3& c, double d, double r) const {
    const double pi = std::numbers::pi;
    Cone k{0, pi, -pi, pi, true};
    if (!(d > r) || !(d > 0)) return k;
    const double a = std::asin(std::min(1.0, r / d)) + 1e-9;
    const double tc = std::acos(std::clamp(c.dot(az_) / d, -1.0, 1.0));
    k.t0 = tc - a;
    k.t1 = tc + a;
    if (k.t0 > 0 && k.t1 < pi) {
      const double s = std::sin(a) / std::min(std::sin(k.t0), std::sin(k.t1));
      if (s < 1) {
        const double pc = std::atan2(c.dot(ay_), c.dot(ax_)), w = std::asin(s) + 1e-9;
        k.p0 = pc - w;
        k.p1 = pc + w;
        k.all_phi = false;
      }
    }
    return k;
  }
  // Calls f(cell) for the cells of a cone.
  template <class F>
  void for_cone(const Cone& k, F&& f) const {
    if (n_phi_ == 0) return;
    const auto index = [](double v, double lo, double scale, int n) {
      return static_cast<int>(std::clamp(std::floor((v - lo) * scale), 0.0, n - 1.0));
    };
    const int y0 = index(k.t0, t_lo_, t_scale_, n_theta_), y1 = index(k.t1, t_lo_, t_scale_, n_theta_);
    int x0 = 0, x1 = n_phi_ - 1;
    if (!k.all_phi) {
      // A cone across the seam φ = ±π: its φ interval taken whole (the grid does not wrap).
      const double pi = std::numbers::pi;
      if (k.p0 >= -pi && k.p1 <= pi) {
        x0 = index(k.p0, p_lo_, p_scale_, n_phi_);
        x1 = index(k.p1, p_lo_, p_scale_, n_phi_);
      }
    }
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) f(static_cast<size_t>(y) * static_cast<size_t>(n_phi_) + static_cast<size_t>(x));
  }
  Vec3 ax_ = Vec3::UnitX(), ay_ = Vec3::UnitY(), az_ = Vec3::UnitZ();
  double t_lo_ = 0, t_scale_ = 1, p_lo_ = 0, p_scale_ = 1;
  int n_theta_ = 0, n_phi_ = 0;
  // Finite viewpoint: the active pieces are slots 0, 1, … in piece order (ids_ maps a slot to
  // its piece); always_ and items_ hold slots. Per slot, the piece's half of the cone test in
  // candidates(), computed once: its centre from the viewpoint, distance, radius with the
  // margin, and sin and cos of its cone's half-angle (the same doubles the test computed per
  // candidate before, so the same verdicts).
  struct ConeTest {
    Vec3 pc;
    double pd, pr, sa, ca;
  };
  std::vector<ConeTest> tests_;
  std::vector<int> always_;

  const std::vector<ShadowPiece>& pieces_;
  Viewpoint view_;
  double margin_;
  Vec3 dir_ = Vec3::UnitZ(), e1_ = Vec3::UnitX(), e2_ = Vec3::UnitY();
  std::vector<Bounds> boxes_;
  std::vector<int> ids_;
  Vec2 lo_ = Vec2::Zero(), inv_ = Vec2::Ones();
  int n_ = 1;
  std::vector<int> cells_, items_;
};

/// The friend of ShadowScene through which the internals reach its Impl.
struct ShadowSceneAccess {
  static const ShadowScene::Impl& impl(const ShadowScene& scene) { return *scene.impl_; }
};

}  // namespace hedra::internal

namespace hedra {

struct ShadowScene::Impl {
  Camera camera;
  std::vector<internal::ShadowBody> bodies;
  std::vector<internal::ShadowPiece> pieces;
  int convex_pieces = 0;  // pieces with a ShadowPiece::Convex (slots 0 … convex_pieces − 1)
  std::vector<int> first_face;             // per scene body
  std::vector<std::pair<int, int>> faces;  // (body data, face) in result order
  double scale = 1;

  // The 2D shadow pieces of face (b, f) from a viewpoint: the face's convex parts clipped
  // against the occlusion volumes of the candidate pieces.
  void hidden_pieces(int b, int f, const internal::CasterIndex& index,
                     const internal::PieceVolumes& volumes, std::vector<Ring2>& out) const;
  // Whether p (on face (b, f)) lies strictly inside a candidate's occlusion volume.
  bool point_hidden(int b, int f, const Vec3& p, const internal::CasterIndex& index,
                    const internal::PieceVolumes& volumes) const;
  // The pieces' occlusion from a viewpoint (cached face planes and facings).
  internal::PieceVolumes volumes(const Viewpoint& view, int threads) const;
  Occluders occluders = Occluders::Auto;
};

}  // namespace hedra
