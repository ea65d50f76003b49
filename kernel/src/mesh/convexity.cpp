#include "hedra/mesh/convexity.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mpzf.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <optional>
#include <cmath>
#include <numbers>
#include <span>

#include "hedra/core/error.h"
#include "hedra/core/face_geometry.h"
#include "hedra/core/parallel.h"
#include "hedra/core/predicates.h"
#include "hedra/core/tolerance.h"
#include "hedra/core/transform.h"

namespace hedra {
namespace {

std::vector<char> on_face_mask(size_t vertex_count, const Face& face) {
  std::vector<char> on(vertex_count, 0);
  for (const auto& loop : face.loops)
    for (int v : loop) on[v] = 1;
  return on;
}

}  // namespace

namespace {

enum class Verdict { Convex, NotConvex, Unknown };

// nonconvex_faces_by_hull(): at least this many vertices per hull before the vertices are
// split into parts whose hulls are built in parallel.
constexpr int kHullPartVertices = 65536;

// A planar piece of the certified surface: a planar face (face >= 0, plane through its support
// triple) or one triangle of a quadrilateral whose rounded vertices are not coplanar.
struct Piece {
  std::array<int, 3> triple;
  int face;
  bool triangle;  // the piece is exactly its triple
};

// The exact 2D orientation of a, b, c projected along coordinate axis `drop`.
Sign orient_projected(const Vec3& a, const Vec3& b, const Vec3& c, int drop) {
  const int i = (drop + 1) % 3, j = (drop + 2) % 3;
  return orient2d(Vec2(a[i], a[j]), Vec2(b[i], b[j]), Vec2(c[i], c[j]));
}

int dominant_axis(const Vec3& a, const Vec3& b, const Vec3& c) {
  Vec3 n = (b - a).cross(c - a);
  int axis = 0;
  n.cwiseAbs().maxCoeff(&axis);
  return axis;
}

// The convexity certificate of is_convex() (see the header). Exact in every decision but the
// winding number when the counting ray meets an edge or a corner: then it is an integer read
// from a floating-point sum whose error is bounded explicitly.
class Certificate {
 public:
  explicit Certificate(const Body& body, std::optional<Vec3> ray = std::nullopt)
      : body_(body), v_(body.vertices()), faces_(body.faces()), ray_(ray) {}

  // Every stage runs in parallel over fixed chunks of kChunk faces, edges or pieces; where the
  // sequential certificate stops at the first failure, the failure of the lowest index wins, and
  // the winding sum adds the chunks' partial sums in chunk order, so the verdict never depends
  // on the threads.
  Verdict run() {
    // Stage 1: the pieces. Exactly planar faces are one piece; a rounded quadrilateral is
    // split along the diagonal that makes it convex; anything else is left to the fallback.
    const int n = body_.face_count();
    std::vector<FaceKind> kind(static_cast<size_t>(n));
    std::atomic<bool> unknown{false};
    parallel_chunks(static_cast<size_t>(n), kChunk, [&](size_t, size_t begin, size_t end) {
      for (size_t f = begin; f != end && !unknown.load(std::memory_order_relaxed); ++f) {
        kind[f] = face_kind(static_cast<int>(f));
        if (kind[f] == kUnknown) unknown = true;
      }
    });
    if (unknown) return Verdict::Unknown;
    // Each face's first piece from a prefix sum over its piece count (two for a split
    // quadrilateral), then the pieces written in parallel, in face order.
    first_piece_.resize(static_cast<size_t>(n));
    split_.resize(static_cast<size_t>(n));
    std::vector<char> search(static_cast<size_t>(n), 0);  // stage 5: needs the local search
    int count = 0;
    for (int f = 0; f < n; ++f) {
      const FaceKind k = kind[static_cast<size_t>(f)];
      first_piece_[static_cast<size_t>(f)] = count;
      split_[static_cast<size_t>(f)] = k == kPlanar ? 0 : k == kSplit02 ? 1 : 2;
      count += k == kPlanar ? 1 : 2;
    }
    pieces_.resize(static_cast<size_t>(count));
    parallel_chunks(static_cast<size_t>(n), kChunk, [&](size_t, size_t begin, size_t end) {
      for (size_t f = begin; f != end; ++f) {
        const Face& face = faces_[f];
        Piece* out = &pieces_[static_cast<size_t>(first_piece_[f])];
        const int fi = static_cast<int>(f);
        if (!split_[f]) {
          out[0] = {body_.support(fi), fi, face.loops.size() == 1 && face.loops[0].size() == 3};
          continue;
        }
        const auto& q = face.loops[0];
        if (split_[f] == 1) {
          out[0] = {{q[0], q[1], q[2]}, fi, true};
          out[1] = {{q[0], q[2], q[3]}, fi, true};
        } else {
          out[0] = {{q[0], q[1], q[3]}, fi, true};
          out[1] = {{q[1], q[2], q[3]}, fi, true};
        }
        search[f] = !support_is_piece(fi);
      }
    });

    // The faces stage 5 searches around. Their vertex-face incidence (a serial pass over the
    // faces) is built alongside stages 2 to 4, which run in parallel.
    std::vector<int> searched;
    for (int f = 0; f < n; ++f)
      if (search[static_cast<size_t>(f)]) searched.push_back(f);
    std::optional<Verdict> verdict;
    if (searched.empty())
      verdict = surface_verdict();
    else
      run_alongside([this] { build_incidence(); }, [&] { verdict = surface_verdict(); });
    if (verdict) return *verdict;

    // Stage 5: the surface is convex. A planar face's support plane is a piece plane, so no
    // vertex lies outside it. A rounded quadrilateral's support plane (a, b, c) is not: check
    // it by a local search (see rounded_face_convex), unless stage 1 settled it in O(1), its
    // support plane being one of its pieces' planes (support_is_piece).
    std::atomic<bool> reflex_found{false};
    parallel_chunks(searched.size(), kChunk, [&](size_t, size_t begin, size_t end) {
      for (size_t k = begin; k != end && !reflex_found.load(std::memory_order_relaxed); ++k)
        if (!rounded_face_convex(searched[k])) reflex_found = true;
    });
    return reflex_found ? Verdict::NotConvex : Verdict::Convex;
  }

 private:
  // Stages 2 to 4: the verdict when they settle it, nullopt when the pieces form a convex
  // surface.
  std::optional<Verdict> surface_verdict() const {
    // Stage 2: local convexity at every edge between pieces. Quadrilateral diagonals are
    // convex by construction; the body's edges are tested here. The first failing edge decides.
    const auto& edges = body_.edges();
    const size_t chunks = (edges.size() + kChunk - 1) / kChunk;
    std::vector<char> failed(chunks, 0);
    std::vector<Verdict> chunk_verdict(chunks, Verdict::Unknown);
    std::atomic<size_t> first_failed{chunks};
    parallel_chunks(edges.size(), kChunk, [&](size_t c, size_t begin, size_t end) {
      if (c > first_failed.load(std::memory_order_relaxed)) return;  // a lower chunk decides
      for (size_t i = begin; i != end; ++i) {
        const std::optional<Verdict> v = edge_verdict(edges[i]);
        if (!v) continue;
        failed[c] = 1;
        chunk_verdict[c] = *v;
        size_t seen = first_failed.load();
        while (c < seen && !first_failed.compare_exchange_weak(seen, c)) {
        }
        return;
      }
    });
    for (size_t c = 0; c < chunks; ++c)
      if (failed[c]) return chunk_verdict[c];

    // Stages 3 and 4, in one pass over the pieces: a centre o strictly inside every piece's
    // plane, and the surface winds once around o.
    Vec3 sum = Vec3::Zero();
    for (const Vec3& x : v_) sum += x;
    if (!winds_once(sum / static_cast<double>(v_.size()))) return Verdict::Unknown;
    return std::nullopt;
  }

  static constexpr size_t kChunk = 4096;
  enum FaceKind : char { kPlanar, kSplit02, kSplit13, kUnknown };

  const Vec3& p(int i) const { return v_[static_cast<size_t>(i)]; }

  // Stage 1 for face f: planar, a rounded quadrilateral split along diagonal q0–q2 (q3 strictly
  // inside plane (q0, q1, q2)) or q1–q3 (convex_quad_split), or not settled here.
  // A quadrilateral off its plane has d = orient3d(q0, q1, q2, q3) ≠ 0 (orient3d is alternating
  // in its four points, so the support triple, three of the four, against the fourth is ±d):
  // no three of its corners are collinear, and both triangles of either split are proper.
  FaceKind face_kind(int f) const {
    // The constructor decided exact planarity already (Body::faces_off_plane()).
    if (!body_.face_off_plane(f)) return kPlanar;
    const Face& face = faces_[static_cast<size_t>(f)];
    if (face.loops.size() != 1 || face.loops[0].size() != 4) return kUnknown;
    const auto& q = face.loops[0];
    return convex_quad_split(p(q[0]), p(q[1]), p(q[2]), p(q[3]))[0][0] == 0 ? kSplit02 : kSplit13;
  }

  // Stage 2 for one edge: nullopt when it is locally convex (or flat), else the verdict.
  std::optional<Verdict> edge_verdict(const Edge& e) const {
    if (e.left_face == e.right_face) return Verdict::Unknown;
    const Piece& f1 = pieces_[static_cast<size_t>(piece_of(e.left_face, e.v0, e.v1))];
    const Piece& g1 = pieces_[static_cast<size_t>(piece_of(e.right_face, e.v1, e.v0))];
    int w = -1;
    bool left = true;
    if (!witness(g1, e.v1, e.v0, w, left)) return Verdict::Unknown;
    Sign side = orient3d(p(f1.triple[0]), p(f1.triple[1]), p(f1.triple[2]), p(w));
    if (!left) side = -side;
    if (side == Sign::Positive) return reflex(e.left_face, e.right_face);
    if (side == Sign::Zero && !same_orientation(f1, g1)) return Verdict::Unknown;  // folded
    return std::nullopt;
  }

  // The piece of face f that carries the directed boundary edge a → b.
  int piece_of(int f, int a, int b) const {
    const int first = first_piece_[static_cast<size_t>(f)];
    const int split = split_[static_cast<size_t>(f)];
    if (!split) return first;
    const auto& q = faces_[static_cast<size_t>(f)].loops[0];
    int i = 0;
    while (q[static_cast<size_t>(i)] != a) ++i;
    (void)b;
    // Split 1 (diagonal q0–q2): edges q0q1, q1q2 in the first triangle. Split 2 (q1–q3):
    // edges q0q1, q3q0 in the first triangle.
    if (split == 1) return first + (i <= 1 ? 0 : 1);
    return first + (i == 0 || i == 3 ? 0 : 1);
  }

  // A vertex w of piece g off the line of its edge b → a, and whether w lies on the piece's
  // side of that edge (left of b → a seen from outside).
  bool witness(const Piece& g, int b, int a, int& w, bool& left) const {
    if (g.triangle) {
      for (int x : g.triple)
        if (x != a && x != b) w = x;
      left = true;
      return w >= 0;
    }
    const auto& t = g.triple;
    for (int x : t)
      if (x != a && x != b && !collinear(p(a), p(b), p(x))) {
        w = x;
        break;
      }
    if (w < 0) return false;
    const int axis = dominant_axis(p(t[0]), p(t[1]), p(t[2]));
    const Sign ref = orient_projected(p(t[0]), p(t[1]), p(t[2]), axis);
    const Sign side = orient_projected(p(b), p(a), p(w), axis);
    if (ref == Sign::Zero || side == Sign::Zero) return false;
    left = side == ref;
    return true;
  }

  // Coplanar pieces on either side of an edge: flat (same outward normal) or folded back.
  bool same_orientation(const Piece& f, const Piece& g) const {
    const auto &a = f.triple, &b = g.triple;
    const int axis = dominant_axis(p(a[0]), p(a[1]), p(a[2]));
    const Sign sa = orient_projected(p(a[0]), p(a[1]), p(a[2]), axis);
    const Sign sb = orient_projected(p(b[0]), p(b[1]), p(b[2]), axis);
    return sa != Sign::Zero && sa == sb;
  }

  // A strictly reflex edge between faces f and g: some vertex of g not on f lies strictly
  // outside f's support plane (then f is a non-convex face by definition), or the edge lies
  // on a rounded face and the fallback decides.
  Verdict reflex(int f, int g) const {
    const auto& s = body_.support(f);
    const Face& ff = faces_[static_cast<size_t>(f)];
    auto on_f = [&](int x) {
      for (const auto& loop : ff.loops)
        for (int y : loop)
          if (y == x) return true;
      return false;
    };
    for (const auto& loop : faces_[static_cast<size_t>(g)].loops)
      for (int x : loop)
        if (orient3d(p(s[0]), p(s[1]), p(s[2]), p(x)) == Sign::Positive && !on_f(x))
          return Verdict::NotConvex;
    return Verdict::Unknown;
  }

  // Stages 3 and 4: o lies strictly inside every piece's plane (exact orient3d on the piece's
  // triple), and the surface winds once around o. Given the first, the central projection from o
  // maps each piece onto the sphere of directions keeping its orientation, and folds at no edge
  // (a locally convex edge's wedge contains o), so it is a branched covering of that sphere
  // whose degree is the winding number: the number of pieces a ray from o crosses, here along one
  // direction r, each crossing decided by orient_direction on the piece's corners (exact). Only
  // when r meets an edge or corner of a piece does the floating-point solid-angle sum decide.
  // Cost O(pieces): one orient3d and about two orient_direction a piece.
  bool winds_once(const Vec3& o) const {
    struct Partial {
      int crossings = 0;
      bool inside = true, degenerate = false;
    };
    // Toward a point inside piece 0, with weights no regular mesh lines up with.
    const auto& t0 = pieces_.front().triple;
    const Vec3 r = ray_ ? *ray_ : 0.4142 * p(t0[0]) + 0.3183 * p(t0[1]) + 0.2675 * p(t0[2]) - o;
    // A floating-point prefilter: (u, w) = (U·(x − o), W·(x − o)) with U, W unit vectors across
    // r. The line o + s·r has |U·(x − o)| ≤ |U·r̂|·|x − o| ≤ 1e-15·extent where it meets the
    // surface, and each computed coordinate is within 1e-15·extent of its exact value; so a
    // triangle whose corners all lie beyond `margin` (1e-9·extent) on one side in u or in w is
    // not met by the line, and crossing() would return 0 for it without a side effect: its
    // three exact orientations are skipped (the counting ray meets a few hundred of the
    // 150 000 fan triangles of a 75 000-face sphere).
    const Vec3 rn = r.normalized();
    int least = 0;
    rn.cwiseAbs().minCoeff(&least);
    const Vec3 U = rn.cross(Vec3::Unit(least)).normalized(), W = rn.cross(U).normalized();
    double extent = 0;
    for (const Vec3& x : v_) extent = std::max(extent, (x - o).cwiseAbs().maxCoeff());
    const double margin = 1e-9 * 2 * extent;
    const bool filter = std::isfinite(margin) && rn.allFinite() && U.allFinite() && W.allFinite();
    auto away = [&](int ia, int ib, int ic) {
      if (!filter) return false;
      const Vec3 a = p(ia) - o, b = p(ib) - o, c = p(ic) - o;
      const double ua = U.dot(a), ub = U.dot(b), uc = U.dot(c);
      if ((ua > margin && ub > margin && uc > margin) || (ua < -margin && ub < -margin && uc < -margin))
        return true;
      const double wa = W.dot(a), wb = W.dot(b), wc = W.dot(c);
      return (wa > margin && wb > margin && wc > margin) || (wa < -margin && wb < -margin && wc < -margin);
    };
    const size_t chunks = (pieces_.size() + kChunk - 1) / kChunk;
    std::vector<Partial> partial(chunks);
    parallel_chunks(pieces_.size(), kChunk, [&](size_t c, size_t begin, size_t end) {
      Partial& part = partial[c];
      // The ray's crossings of triangle (a, b, c) whose orientation seen from o is −facing:
      // ±1 through its interior (r = Σ λ_i (corner_i − o), all λ_i > 0), 0 when some λ_i < 0;
      // the ray on its boundary is degenerate.
      auto crossing = [&](int ia, int ib, int ic, Sign facing) {
        if (facing == Sign::Zero) return 0;  // a fan triangle over collinear vertices
        const Sign hit = -facing;            // the sign of det[a − o, b − o, r] inside
        bool zero = false;
        for (const auto& [x, y] : {std::pair{ia, ib}, std::pair{ib, ic}, std::pair{ic, ia}}) {
          const Sign s = orient_direction(o, p(x), p(y), r);
          if (s == -hit) return 0;
          zero = zero || s == Sign::Zero;
        }
        if (zero) part.degenerate = true;
        return zero ? 0 : hit == Sign::Positive ? 1 : -1;
      };
      for (size_t k = begin; k != end; ++k) {
        const Piece& piece = pieces_[k];
        const auto& t = piece.triple;
        const Sign inside = orient3d(p(t[0]), p(t[1]), p(t[2]), o);
        if (inside != Sign::Negative) {
          part.inside = false;
          return;
        }
        if (piece.triangle) {
          if (!away(t[0], t[1], t[2])) part.crossings += crossing(t[0], t[1], t[2], inside);
          continue;
        }
        // A planar face: the signed crossings of its loops' fans, its winding number about the
        // point where r meets its plane.
        for (const auto& loop : faces_[static_cast<size_t>(piece.face)].loops)
          for (size_t i = 1; i + 1 < loop.size(); ++i)
            if (!away(loop[0], loop[i], loop[i + 1]))
              part.crossings += crossing(loop[0], loop[i], loop[i + 1],
                                         orient3d(p(loop[0]), p(loop[i]), p(loop[i + 1]), o));
      }
    });
    int crossings = 0;
    bool degenerate = false;
    for (const Partial& part : partial) {
      if (!part.inside) return false;
      crossings += part.crossings;
      degenerate = degenerate || part.degenerate;
    }
    return degenerate ? winding_sum_is_one(o) : crossings == 1;
  }

  // The surface's total signed solid angle seen from o, in units of 4π, is 1, for o strictly
  // inside every piece's plane (winds_once). Each triangle (of a piece, or of a fan over a face
  // loop) contributes 2·atan2(|det|, d) (Van Oosterom and Strackee 1983) with the sign of the
  // exact orient3d, so that o close to a face plane cannot flip a term from +2π to −2π (for a
  // triangle piece that sign is known). The error of each term is bounded from the rounding of
  // det and d; the integer is accepted only when the bound leaves no doubt.
  bool winding_sum_is_one(const Vec3& o) const {
    constexpr double kPi = 3.14159265358979323846;
    struct Partial {
      double total = 0, error = 0;
      bool ok = true;
    };
    const size_t chunks = (pieces_.size() + kChunk - 1) / kChunk;
    std::vector<Partial> partial(chunks);
    parallel_chunks(pieces_.size(), kChunk, [&](size_t c, size_t begin, size_t end) {
      Partial& part = partial[c];
      // s: the exact orient3d(a, b, c, o) when the caller knows it.
      auto add = [&](int ia, int ib, int ic, Sign s) {
        if (s == Sign::Zero) return true;  // a fan triangle over collinear vertices
        const Vec3 a = p(ia) - o, b = p(ib) - o, cc = p(ic) - o;
        const double la = a.norm(), lb = b.norm(), lc = cc.norm();
        const double det = a.dot(b.cross(cc));
        const double d = la * lb * lc + a.dot(b) * lc + a.dot(cc) * lb + b.dot(cc) * la;
        // |det − exact| and |d − exact| ≤ 32ε·la·lb·lc (three roundings of the differences, a
        // handful in the products and sums), so atan2 moves by at most their sum over the radius.
        const double slack = 64 * kEpsilon * la * lb * lc;
        const double r = std::sqrt(det * det + d * d);
        if (!(r > 4 * slack)) return false;
        const double omega = 2 * std::atan2(std::abs(det), d);
        part.total += s == Sign::Negative ? omega : -omega;
        part.error += 2 * slack / (r - slack) + 8 * kEpsilon;
        return true;
      };
      for (size_t k = begin; k != end && part.ok; ++k) {
        const Piece& piece = pieces_[k];
        const auto& t = piece.triple;
        if (piece.triangle) {  // o is strictly inside its plane (winds_once)
          part.ok = add(t[0], t[1], t[2], Sign::Negative);
          continue;
        }
        for (const auto& loop : faces_[static_cast<size_t>(piece.face)].loops)
          for (size_t i = 1; i + 1 < loop.size() && part.ok; ++i)
            part.ok = add(loop[0], loop[i], loop[i + 1], orient3d(p(loop[0]), p(loop[i]), p(loop[i + 1]), o));
      }
    });
    // The chunks' sums in chunk order: fewer additions than terms, each covered like a term's
    // own addition by its 8ε.
    double total = 0, error = 0;
    for (const Partial& part : partial) {
      if (!part.ok) return false;
      total += part.total;
      error += part.error;
    }
    return std::abs(total - 4 * kPi) + error < 2 * kPi;
  }

  void build_incidence() {
    start_.assign(v_.size() + 1, 0);
    for (const Face& face : faces_)
      for (const auto& loop : face.loops)
        for (int x : loop) ++start_[static_cast<size_t>(x) + 1];
    for (size_t i = 1; i < start_.size(); ++i) start_[i] += start_[i - 1];
    incident_.resize(static_cast<size_t>(start_.back()));
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (size_t f = 0; f < faces_.size(); ++f)
      for (const auto& loop : faces_[f].loops)
        for (int x : loop) incident_[static_cast<size_t>(fill[static_cast<size_t>(x)]++)] = static_cast<int>(f);
  }

  // The support triple of rounded face f is often one of its two pieces (support_triple takes
  // a diagonal), in the same cyclic order: then its plane is a piece plane of the convex
  // surface, and no vertex is outside it. O(1).
  bool support_is_piece(int f) const {
    const auto& s = body_.support(f);
    const int first = first_piece_[static_cast<size_t>(f)];
    for (int k = first; k < first + 2; ++k) {
      const auto& t = pieces_[static_cast<size_t>(k)].triple;
      for (int r = 0; r < 3; ++r)
        if (t[static_cast<size_t>(r)] == s[0] && t[static_cast<size_t>((r + 1) % 3)] == s[1] &&
            t[static_cast<size_t>((r + 2) % 3)] == s[2])
          return true;
    }
    return false;
  }

  // Face f's support plane h (through a, b, c) against the vertices not on f, given that the
  // surface is convex (K its solid). φ = the side of h. If some vertex not on f had φ > 0, the
  // vertices with φ > 0 would form a set connected through shared faces (on a convex surface,
  // a vertex that is not a maximum of a linear function has a neighbour across a face with a
  // larger value, and the maxima form a face of K), so either it contains a vertex of f with
  // φ > 0 and a face-neighbour of it off f, or it contains none and a (φ = 0, not a maximum)
  // has such a neighbour. So the faces around f's vertices with φ > 0 decide when there are
  // any, and the faces around a when there are none. Cost O(size of those stars).
  // \pre build_incidence(); f's support triple is not one of its pieces (support_is_piece).
  bool rounded_face_convex(int f) const {
    const auto& s = body_.support(f);
    const auto& q = faces_[static_cast<size_t>(f)].loops[0];
    const PlaneOrientation side(p(s[0]), p(s[1]), p(s[2]));
    auto phi = [&](int x) { return side(p(x)); };
    auto on_f = [&](int x) { return x == q[0] || x == q[1] || x == q[2] || x == q[3]; };
    // A vertex of the star is on several of its faces: each is tested once (the first 32).
    auto star = [&](int x) {
      std::array<int, 32> seen;
      size_t n_seen = 0;
      for (int i = start_[static_cast<size_t>(x)]; i < start_[static_cast<size_t>(x) + 1]; ++i)
        for (const auto& loop : faces_[static_cast<size_t>(incident_[static_cast<size_t>(i)])].loops)
          for (int y : loop) {
            if (on_f(y) || std::find(seen.begin(), seen.begin() + n_seen, y) != seen.begin() + n_seen)
              continue;
            if (n_seen < seen.size()) seen[n_seen++] = y;
            if (phi(y) == Sign::Positive) return false;
          }
      return true;
    };
    // The fourth corner x lies strictly outside the support plane: of the four triples of a
    // quadrilateral with d ≠ 0 (stage 1), the two with the fourth corner strictly inside are
    // exactly the two pieces (orient3d alternates), and the support triple is neither. So
    // phi(x), the near-zero orientation stage 1 decided (often in exact arithmetic), is not
    // asked again.
    int x = q[0];
    for (int y : q)
      if (y != s[0] && y != s[1] && y != s[2]) x = y;
    HEDRA_EXPENSIVE_ASSERT(phi(x) == Sign::Positive, "convexity: a rounded face's fourth corner is not outside its support plane");
    return star(x);
  }

  const Body& body_;
  const std::vector<Vec3>& v_;
  const std::vector<Face>& faces_;
  std::optional<Vec3> ray_;  // the degree's direction, when a test sets it
  std::vector<Piece> pieces_;
  std::vector<int> first_piece_;
  std::vector<char> split_;
  std::vector<int> start_, incident_;
};

// Exact sign of n·(w − u), n = (b − a) × (c − a): which of w and u lies farther along the
// outer normal of plane (a, b, c). A static filter, then Mpzf (exact for sums and products of
// doubles).
Sign compare_along(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& w, const Vec3& u) {
  const Vec3 x = b - a, y = c - a, z = w - u;
  const double det = x.dot(y.cross(z));
  const double permanent = std::abs(x.x()) * (std::abs(y.y() * z.z()) + std::abs(y.z() * z.y())) +
                           std::abs(x.y()) * (std::abs(y.z() * z.x()) + std::abs(y.x() * z.z())) +
                           std::abs(x.z()) * (std::abs(y.x() * z.y()) + std::abs(y.y() * z.x()));
  if (permanent > 1e-250 && permanent < 1e250) {
    const double bound = 1e-14 * permanent;
    if (det > bound) return Sign::Positive;
    if (det < -bound) return Sign::Negative;
  }
  using M = CGAL::Mpzf;
  auto d = [](double p, double q) { return M(p) - M(q); };
  const M x0 = d(b.x(), a.x()), x1 = d(b.y(), a.y()), x2 = d(b.z(), a.z());
  const M y0 = d(c.x(), a.x()), y1 = d(c.y(), a.y()), y2 = d(c.z(), a.z());
  const M z0 = d(w.x(), u.x()), z1 = d(w.y(), u.y()), z2 = d(w.z(), u.z());
  const M e = x0 * (y1 * z2 - y2 * z1) + x1 * (y2 * z0 - y0 * z2) + x2 * (y0 * z1 - y1 * z0);
  const int sign = CGAL::sign(e);
  return sign > 0 ? Sign::Positive : (sign < 0 ? Sign::Negative : Sign::Zero);
}

// CGAL's exact hull traits with one predicate replaced: which of two points lies farther from
// a plane (quickhull's farthest point of an outside set) by compare_along (static filter, then
// Mpzf) instead of the kernel's filtered predicate, whose exact stage is Gmpq. The lat-long
// vertices of a tessellated sphere are symmetric, so exact ties are common: in CGAL's
// predicate they took 8% of `info` on a million-triangle mesh. The same exact answers.
using HullKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
struct HullTraits
    : CGAL::Convex_hull_traits_3<HullKernel, CGAL::Surface_mesh<HullKernel::Point_3>, CGAL::Tag_true> {
  using Base =
      CGAL::Convex_hull_traits_3<HullKernel, CGAL::Surface_mesh<HullKernel::Point_3>, CGAL::Tag_true>;
  struct Less_signed_distance_to_plane_3 {
    using result_type = bool;
    // CGAL's meaning: det(q − p, r − p, a − b) < 0 for the plane's points p, q, r.
    bool operator()(const Base::Plane_3& h, const HullKernel::Point_3& a,
                    const HullKernel::Point_3& b) const {
      auto vec = [](const HullKernel::Point_3& x) { return Vec3(x.x(), x.y(), x.z()); };
      return compare_along(vec(h.p()), vec(h.q()), vec(h.r()), vec(a), vec(b)) == Sign::Negative;
    }
  };
  Less_signed_distance_to_plane_3 less_signed_distance_to_plane_3_object() const { return {}; }
};

// The non-convex faces, by the definition, through the convex hull of the vertices: a linear
// function's maximum over the vertices is reached at a hull vertex, and on a convex polytope a
// vertex no neighbour of which is higher is a maximum. So for a face whose vertices all lie on
// its support plane, "some vertex not on f is strictly outside" means "the hull's highest
// vertex along f's outer normal is strictly outside": from a support vertex of f on the hull,
// look at its hull neighbours; otherwise climb the hull graph with exact comparisons. A face
// with a vertex of its own strictly outside its plane (rounded) is checked against every vertex.
// With k parts (slabs of the sorted vertices, hulls built in parallel), each part's hull graph
// answers for its vertices. Cost O(V log V) for the hulls, then O(k · hull degree) per face
// with a vertex on a hull, plus the climbs.
std::vector<int> nonconvex_faces_by_hull(const Body& body, int requested_parts = 0) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  const auto& v = body.vertices();
  const int n = body.vertex_count();
  std::vector<int> by_position(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) by_position[static_cast<size_t>(i)] = i;
  auto less = [&](int i, int j) {
    const Vec3 &p = v[static_cast<size_t>(i)], &q = v[static_cast<size_t>(j)];
    return std::tie(p.x(), p.y(), p.z()) < std::tie(q.x(), q.y(), q.z());
  };
  std::sort(by_position.begin(), by_position.end(), less);
  // The vertices in `parts` runs of the sorted order (slabs along x), each with its own hull,
  // built in parallel: a face is non-convex when some part has a vertex outside its plane, and
  // each part's hull graph answers that for its part. One part below kHullPartVertices
  // vertices per part, or when a part is flat (its hull would not be a polytope).
  const int parts = [&] {
    int k = requested_parts > 0 ? std::min(requested_parts, std::max(1, n / 4))
                                : std::clamp(n / kHullPartVertices, 1, std::max(1, bounded_threads(0)));
    for (int p = 0; p < k && k > 1; ++p) {
      const size_t lo = static_cast<size_t>(p) * static_cast<size_t>(n) / static_cast<size_t>(k),
                   hi = static_cast<size_t>(p + 1) * static_cast<size_t>(n) / static_cast<size_t>(k);
      auto at = [&](size_t i) {
        const Vec3& q = v[static_cast<size_t>(by_position[i])];
        return K::Point_3(q.x(), q.y(), q.z());
      };
      // Flat unless four points span space: a, then b ≠ a, then c off line ab, then d off plane abc.
      size_t ib = lo + 1;
      while (ib < hi && at(ib) == at(lo)) ++ib;
      size_t ic = ib + 1;
      while (ic < hi && CGAL::collinear(at(lo), at(ib), at(ic))) ++ic;
      size_t id = ic + 1;
      while (id < hi && CGAL::coplanar(at(lo), at(ib), at(ic), at(id))) ++id;
      if (ib >= hi || ic >= hi || id >= hi) k = 1;
    }
    return k;
  }();
  auto part_begin = [&](int p) {
    return static_cast<size_t>(p) * static_cast<size_t>(n) / static_cast<size_t>(parts);
  };
  std::vector<int> part_of(v.size(), 0);
  for (int p = 0; p < parts; ++p)
    for (size_t i = part_begin(p); i < part_begin(p + 1); ++i)
      part_of[static_cast<size_t>(by_position[i])] = p;
  // The hulls as indexed triangle sets: no halfedge mesh is built from CGAL's triangulation
  // (copying it into a Surface_mesh through hash maps took longer than the hull). The traits
  // are the exact ones CGAL picks for a Surface_mesh; CGAL 5.5's own indexed-triangle-set
  // overload takes the kernel's rounded Plane_3 instead, whose hull is not exact. Hull
  // triangles are stored with body vertex indices (found in the part's run of the sorted order).
  std::vector<std::vector<std::array<int, 3>>> hull_triangles(static_cast<size_t>(parts));
  std::vector<char> on_hull(v.size(), 0);
  parallel_for(static_cast<size_t>(parts), 0, [&](size_t p) {
    const size_t lo = part_begin(static_cast<int>(p)), hi = part_begin(static_cast<int>(p) + 1);
    std::vector<K::Point_3> points;
    points.reserve(hi - lo);
    for (size_t i = lo; i < hi; ++i) {
      const Vec3& q = v[static_cast<size_t>(by_position[i])];
      points.emplace_back(q.x(), q.y(), q.z());
    }
    std::vector<K::Point_3> hull_points;
    std::vector<std::array<std::size_t, 3>> triangles;
    {
      CGAL::Convex_hull_3::internal::Indexed_triangle_set<std::vector<K::Point_3>,
                                                          std::vector<std::array<std::size_t, 3>>>
          its(hull_points, triangles);
      CGAL::convex_hull_3(points.begin(), points.end(), its, HullTraits());
    }
    std::vector<int> body_id(hull_points.size(), -1);
    for (size_t h = 0; h < hull_points.size(); ++h) {
      const K::Point_3& q = hull_points[h];
      const Vec3 x(q.x(), q.y(), q.z());
      auto it = std::lower_bound(by_position.begin() + static_cast<std::ptrdiff_t>(lo),
                                 by_position.begin() + static_cast<std::ptrdiff_t>(hi), -1,
                                 [&](int i, int) {
                                   const Vec3& r = v[static_cast<size_t>(i)];
                                   return std::tie(r.x(), r.y(), r.z()) < std::tie(x.x(), x.y(), x.z());
                                 });
      body_id[h] = *it;
      on_hull[static_cast<size_t>(*it)] = 1;  // each vertex is in one part: no race
    }
    auto& out = hull_triangles[p];
    out.reserve(triangles.size());
    for (const auto& t : triangles)
      out.push_back({body_id[t[0]], body_id[t[1]], body_id[t[2]]});
  });
  // Neighbours of body vertex x on its part's hull: neighbour[neighbour_start[x] …
  // neighbour_start[x + 1]), from both other corners of every hull triangle at x (so each
  // hull neighbour is listed twice).
  std::vector<int> neighbour_start(v.size() + 1, 0), neighbour;
  for (const auto& list : hull_triangles)
    for (const auto& t : list)
      for (int a : t) neighbour_start[static_cast<size_t>(a) + 1] += 2;
  for (size_t x = 0; x < v.size(); ++x) neighbour_start[x + 1] += neighbour_start[x];
  neighbour.resize(static_cast<size_t>(neighbour_start[v.size()]));
  {
    std::vector<int> fill(neighbour_start.begin(), neighbour_start.end() - 1);
    for (const auto& list : hull_triangles)
      for (const auto& t : list)
        for (size_t i = 0; i < 3; ++i) {
          const size_t a = static_cast<size_t>(t[i]);
          neighbour[static_cast<size_t>(fill[a]++)] = t[(i + 1) % 3];
          neighbour[static_cast<size_t>(fill[a]++)] = t[(i + 2) % 3];
        }
  }
  auto neighbours = [&](int x) {
    return std::span<const int>(neighbour.data() + neighbour_start[static_cast<size_t>(x)],
                                neighbour.data() + neighbour_start[static_cast<size_t>(x) + 1]);
  };

  // Each face on its own, in parallel blocks: a face's answer is the sign of the largest
  // value along its normal, whichever hull vertex the climb starts from, so the list does not
  // depend on the blocks or threads. Each block keeps its own start and stamps.
  std::vector<int> first_top(static_cast<size_t>(parts), -1);
  for (int i = 0; i < n; ++i)
    if (on_hull[static_cast<size_t>(i)] && first_top[static_cast<size_t>(part_of[static_cast<size_t>(i)])] < 0)
      first_top[static_cast<size_t>(part_of[static_cast<size_t>(i)])] = i;
  const int face_count = body.face_count();
  std::vector<char> nonconvex(static_cast<size_t>(face_count), 0);
  parallel_blocks(static_cast<size_t>(face_count), 0, 2048, [&](size_t begin, size_t end) {
    std::vector<int> top = first_top;  // last maximum found in each part: a good start for the next
    std::vector<int> stamp;  // sized on the first face with a vertex outside its own plane
    for (int f = static_cast<int>(begin); f < static_cast<int>(end); ++f) {
      const auto& s = body.support(f);
      const Vec3 &a = v[static_cast<size_t>(s[0])], &b = v[static_cast<size_t>(s[1])],
                 &c = v[static_cast<size_t>(s[2])];
      auto phi = [&](int x) { return orient3d(a, b, c, v[static_cast<size_t>(x)]); };
      const auto& loops = body.faces()[static_cast<size_t>(f)].loops;
      bool own_outside = false;
      for (const auto& loop : loops)
        for (int x : loop)
          if (x != s[0] && x != s[1] && x != s[2] && phi(x) == Sign::Positive) own_outside = true;
      bool outside = false;
      if (own_outside) {
        if (stamp.empty()) stamp.assign(v.size(), -1);
        for (const auto& loop : loops)
          for (int x : loop) stamp[static_cast<size_t>(x)] = f;
        for (int x = 0; x < n && !outside; ++x)
          outside = stamp[static_cast<size_t>(x)] != f && phi(x) == Sign::Positive;
      } else {
        // Every vertex of f is on or inside its plane, so a vertex strictly outside is not on f.
        // In each part: from a support vertex of f on the part's hull, its hull neighbours;
        // otherwise the climb to the part's highest vertex.
        for (int part = 0; part < parts && !outside; ++part) {
          int start = -1;
          for (int x : s)
            if (on_hull[static_cast<size_t>(x)] && part_of[static_cast<size_t>(x)] == part) start = x;
          if (start >= 0) {
            for (int w : neighbours(start))
              if (phi(w) == Sign::Positive) { outside = true; break; }
            continue;
          }
          int u = top[static_cast<size_t>(part)];
          for (bool moved = true; moved;) {
            moved = false;
            for (int w : neighbours(u))
              if (compare_along(a, b, c, v[static_cast<size_t>(w)], v[static_cast<size_t>(u)]) ==
                  Sign::Positive) {
                u = w;
                moved = true;
                break;
              }
          }
          top[static_cast<size_t>(part)] = u;
          outside = phi(u) == Sign::Positive;
        }
      }
      nonconvex[static_cast<size_t>(f)] = outside;
    }
  });
  std::vector<int> out;
  for (int f = 0; f < face_count; ++f)
    if (nonconvex[static_cast<size_t>(f)]) out.push_back(f);
  return out;
}

}  // namespace

ConvexityCertificate certify_convexity(const Body& body) { return internal::certify_convexity_along(body, std::nullopt); }

namespace internal {

std::vector<int> nonconvex_faces_in_parts(const Body& body, int parts) {
  return nonconvex_faces_by_hull(body, parts);
}

ConvexityCertificate certify_convexity_along(const Body& body, const std::optional<Vec3>& ray) {
  switch (Certificate(body, ray).run()) {
    case Verdict::Convex: return ConvexityCertificate::Convex;
    case Verdict::NotConvex: return ConvexityCertificate::NotConvex;
    case Verdict::Unknown: break;
  }
  return ConvexityCertificate::Undecided;
}

}  // namespace internal

bool is_convex(const Body& body) {
  // Decided once per body (Body::convexity_memo): hidden lines and shadows ask on every call.
  if (const int memo = body.convexity_memo(); memo >= 0) return memo == 1;
  bool convex = false;
  switch (Certificate(body).run()) {
    case Verdict::Convex: convex = true; break;
    case Verdict::NotConvex: convex = false; break;
    case Verdict::Unknown: convex = nonconvex_faces_by_hull(body).empty(); break;
  }
  body.set_convexity_memo(convex);
  return convex;
}

ConvexityReport convexity(const Body& body) {
  ConvexityReport report;
  const Verdict verdict = Certificate(body).run();
  if (verdict == Verdict::Convex) {
    report.convex = true;
    return report;
  }
  report.nonconvex_faces = nonconvex_faces_by_hull(body);
  report.convex = report.nonconvex_faces.empty();
  return report;
}

ConvexityReport convexity(const std::vector<Vec3>& vertices, const std::vector<Face>& faces) {
  ConvexityReport report;
  bool any_off_plane = false;
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto& loop = faces[f].loops.at(0);
    Vec3 normal = newell_normal(vertices, loop);
    if (normal.isZero()) continue;  // a collinear face carries no plane
    std::array<int, 3> s = support_triple(vertices, loop, normal);
    if (s[2] < 0) continue;
    std::vector<char> on = on_face_mask(vertices.size(), faces[f]);
    int positive = 0, negative = 0;
    for (size_t v = 0; v < vertices.size(); ++v) {
      if (on[v]) continue;
      // orient3d is Positive on the outer side (loops run counter-clockwise from outside).
      Sign side = orient3d(vertices[s[0]], vertices[s[1]], vertices[s[2]], vertices[v]);
      if (side == Sign::Positive) ++positive;
      if (side == Sign::Negative) ++negative;
    }
    if (positive || negative) any_off_plane = true;
    if (positive) report.nonconvex_faces.push_back(static_cast<int>(f));
  }
  report.flat = !any_off_plane;
  report.convex = !report.flat && report.nonconvex_faces.empty();
  return report;
}

ConvexityReport convexity_by_rotation(const std::vector<Vec3>& vertices,
                                      const std::vector<Face>& faces, double zero_tolerance) {
  double scale = 0;
  for (const Vec3& p : vertices) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  if (zero_tolerance < 0) zero_tolerance = kRotationConvexityZero;
  const double zero = zero_tolerance * std::max(scale, 1e-300);

  ConvexityReport report;
  bool any_off_plane = false;
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto& loop = faces[f].loops.at(0);
    // Step 1: the first vertex of the face to the origin.
    const Vec3 p0 = vertices[loop[0]];
    Transform t = Transform::translation(-p0);
    // Step 2: rotate so that the edge p0 → p1 lies on the positive x axis: first about OZ to
    // bring it into the XOZ plane, then about OY to lay it on OX.
    Vec3 e = vertices[loop[1]] - p0;
    double az = std::atan2(e.y(), e.x()) * 180 / std::numbers::pi;
    t = t * Transform::rotation_z(-az);
    e = t.apply(vertices[loop[1]]);
    double ay = std::atan2(e.z(), e.x()) * 180 / std::numbers::pi;
    t = t * Transform::rotation_y(ay);
    // Step 3: rotate about OX so that the face lies in z = 0, choosing the vertex of the face
    // farthest from the x axis to fix the angle; its y becomes positive, so the face's
    // outward normal (counter-clockwise loop) becomes +z when the loop turns left there.
    Vec3 best = Vec3::Zero();
    for (int v : loop) {
      Vec3 q = t.apply(vertices[v]);
      if (q.y() * q.y() + q.z() * q.z() > best.y() * best.y() + best.z() * best.z()) best = q;
    }
    double ax = std::atan2(best.z(), best.y()) * 180 / std::numbers::pi;
    t = t * Transform::rotation_x(-ax);
    // The outward normal of the face after the rotations: +z or −z.
    Vec3 normal = t.apply_vector(newell_normal(vertices, faces[f].loops));
    const double outward_sign = normal.z() >= 0 ? 1.0 : -1.0;

    // Step 4: signs of z of the vertices not on the face.
    std::vector<char> on = on_face_mask(vertices.size(), faces[f]);
    int outer = 0, inner = 0;
    for (size_t v = 0; v < vertices.size(); ++v) {
      if (on[v]) continue;
      double z = t.apply(vertices[v]).z() * outward_sign;
      if (z > zero) ++outer;
      if (z < -zero) ++inner;
    }
    if (outer || inner) any_off_plane = true;
    if (outer) report.nonconvex_faces.push_back(static_cast<int>(f));
  }
  report.flat = !any_off_plane;
  report.convex = !report.flat && report.nonconvex_faces.empty();
  return report;
}

ConvexityReport convexity_by_rotation(const Body& body) {
  return convexity_by_rotation(body.vertices(), body.faces());
}

}  // namespace hedra
