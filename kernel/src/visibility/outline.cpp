#include "hedra/visibility/outline.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include "hedra/core/parallel.h"
#include "visibility/contour.h"

namespace hedra {
namespace {

Vec3 outward_normal(const Body& body, int f) { return -body.inner_normal(f); }

Vec3 face_centre(const Body& body, int f) {
  const auto& loop = body.faces()[static_cast<size_t>(f)].loops[0];
  Vec3 c = Vec3::Zero();
  for (int v : loop) c += body.vertices()[static_cast<size_t>(v)];
  return c / static_cast<double>(loop.size());
}

// classify_edges runs over chunks of this many edges (one chunk, no task, below it).
constexpr size_t kClassChunk = 16384;

bool curved(const SmoothSurface& surface, const Vec3& outward) {
  return surface.is_smooth() && surface.curved_face(outward);
}

}  // namespace

std::vector<EdgeClass> classify_edges(const Body& body, double crease_angle_deg,
                                      const SmoothSurface& surface) {
  const double cos_crease = std::cos(crease_angle_deg * std::numbers::pi / 180);
  const std::vector<Edge>& edges = body.edges();
  std::vector<EdgeClass> out(edges.size());
  // Each edge's class in its own place: a large body's in parallel chunks.
  parallel_chunks(edges.size(), kClassChunk, [&](size_t, size_t begin, size_t end) {
    for (size_t i = begin; i != end; ++i) {
      const Edge& e = edges[i];
      // A two-sided body's boundary edge folds a face onto its other side (180°): sharp at any
      // crease angle, which at 180° rounding would decide.
      if (body.two_sided() && e.left_face == body.twin_face(e.right_face)) {
        out[i] = EdgeClass::Sharp;
        continue;
      }
      const Vec3 a = outward_normal(body, e.left_face), b = outward_normal(body, e.right_face);
      const bool smooth = (curved(surface, a) && curved(surface, b)) || a.dot(b) >= cos_crease;
      out[i] = smooth ? EdgeClass::Smooth : EdgeClass::Sharp;
    }
  });
  return out;
}

namespace {

// Outlines run over fixed chunks of vertices and triangles (parallel_chunks).
constexpr size_t kChunk = 4096;

// The corner normals of corner_normals(), one corner at a time, without the per-corner table:
// a vertex whose faces all lie within half the crease angle of its first face (less a margin
// that rounding cannot cross) has every pair of its faces within the crease angle, so each of
// its non-analytic corners gets the same sum, in the same order, as corner_normals() computes:
// it is computed once per vertex. Other corners are summed as corner_normals() does. O(corners)
// to build; O(1) per corner asked for at a shared vertex, O(degree) otherwise.
class CornerNormals {
 public:
  CornerNormals(const Body& body, double crease_angle_deg, const SmoothSurface& surface)
      : body_(body), surface_(surface), v_(body.vertices()), faces_(body.faces()) {
    const double crease = crease_angle_deg * std::numbers::pi / 180;
    cos_crease_ = std::cos(crease);
    const size_t nv = v_.size(), nf = faces_.size();
    normal_.resize(nf);
    analytic_.assign(nf, 0);
    bool all_analytic = true;
    for (size_t f = 0; f < nf; ++f) {
      normal_[f] = outward_normal(body, static_cast<int>(f));
      analytic_[f] = curved(surface, normal_[f]);
      all_analytic = all_analytic && analytic_[f];
    }
    shared_.assign(nv, 0);
    // Every corner analytic (a sphere): normal() never reads the faces around a vertex.
    if (all_analytic) return;
    // Faces around each vertex (CSR), in ascending face order.
    start_.assign(nv + 1, 0);
    for (const Face& face : faces_)
      for (const auto& loop : face.loops)
        for (int x : loop) ++start_[static_cast<size_t>(x) + 1];
    for (size_t i = 1; i < start_.size(); ++i) start_[i] += start_[i - 1];
    around_.resize(static_cast<size_t>(start_.back()));
    {
      std::vector<int> fill(start_.begin(), start_.end() - 1);
      for (size_t f = 0; f < nf; ++f)
        for (const auto& loop : faces_[f].loops)
          for (int x : loop)
            around_[static_cast<size_t>(fill[static_cast<size_t>(x)]++)] = static_cast<int>(f);
    }
    // Shared vertices: computed dot ≥ cos(crease/2 − 1e-6) + 1e-12 makes the true angle to the
    // first face at most crease/2 − 1e-6, so any two faces are at most crease − 2e-6 apart and
    // their computed dot (error ~1e-15) is ≥ cos_crease.
    const double half = crease / 2 - 1e-6;
    shared_normal_.assign(nv, Vec3::Zero());
    if (half > 0) {
      const double cos_half = std::cos(half) + 1e-12;
      for (size_t x = 0; x < nv; ++x) {
        const int b = start_[x], e = start_[x + 1];
        if (e - b < 2) continue;
        const Vec3& n0 = normal_[static_cast<size_t>(around_[static_cast<size_t>(b)])];
        bool all = true;
        Vec3 sum = Vec3::Zero();
        for (int i = b; i < e && all; ++i) {
          const int g = around_[static_cast<size_t>(i)];
          all = normal_[static_cast<size_t>(g)].dot(n0) >= cos_half;
          sum += body.face_area(g) * normal_[static_cast<size_t>(g)];
        }
        if (!all || !(sum.norm() > 0)) continue;
        shared_[x] = 1;
        shared_normal_[x] = sum.normalized();
      }
    }
  }

  bool analytic(int f) const { return analytic_[static_cast<size_t>(f)] != 0; }
  const Vec3& face_normal(int f) const { return normal_[static_cast<size_t>(f)]; }
  // Vertex x's corners off analytic faces all have this normal (shared(x)).
  bool shared(int x) const { return shared_[static_cast<size_t>(x)] != 0; }
  const Vec3& shared_normal(int x) const { return shared_normal_[static_cast<size_t>(x)]; }

  // The normal of face f's corner at vertex x, as corner_normals() gives it. `centre`: face f's
  // centre when analytic(f) (face_centre).
  Vec3 normal(int f, int x, const Vec3& centre) const {
    if (analytic(f)) return surface_.normal(v_[static_cast<size_t>(x)], centre);
    if (shared(x)) return shared_normal(x);
    // Area-weighted normals of the faces around x that turn from f by at most the crease
    // angle: a crease keeps its two sides apart, a smooth region shares one normal.
    // A corner where f meets no other face within the crease angle keeps f's normal
    // exactly, so that outline() knows a flat face (a box's) has no contour.
    const Vec3& nf = normal_[static_cast<size_t>(f)];
    Vec3 sum = Vec3::Zero();
    bool alone = true;
    for (int i = start_[static_cast<size_t>(x)]; i < start_[static_cast<size_t>(x) + 1]; ++i) {
      const int g = around_[static_cast<size_t>(i)];
      if (normal_[static_cast<size_t>(g)].dot(nf) >= cos_crease_) {
        sum += body_.face_area(g) * normal_[static_cast<size_t>(g)];
        alone = alone && g == f;
      }
    }
    return !alone && sum.norm() > 0 ? Vec3(sum.normalized()) : nf;
  }

 private:
  const Body& body_;
  const SmoothSurface& surface_;
  const std::vector<Vec3>& v_;
  const std::vector<Face>& faces_;
  double cos_crease_ = 1;
  std::vector<int> start_, around_;
  std::vector<Vec3> normal_;
  std::vector<char> analytic_;
  std::vector<char> shared_;
  std::vector<Vec3> shared_normal_;
};

}  // namespace

std::vector<Vec3> corner_normals(const Body& body, double crease_angle_deg,
                                 const SmoothSurface& surface) {
  const CornerNormals normals(body, crease_angle_deg, surface);
  std::vector<Vec3> out;
  for (size_t f = 0; f < body.faces().size(); ++f) {
    const int face = static_cast<int>(f);
    const Vec3 centre = normals.analytic(face) ? face_centre(body, face) : Vec3::Zero();
    for (const auto& loop : body.faces()[f].loops)
      for (int x : loop) out.push_back(normals.normal(face, x, centre));
  }
  return out;
}

std::vector<OutlineSegment> outline(const Body& body, const Viewpoint& view,
                                    double crease_angle_deg, const SmoothSurface& surface) {
  const CornerNormals normals(body, crease_angle_deg, surface);
  const auto& faces = body.faces();
  const auto& v = body.vertices();
  // The analytic normal of each vertex on a curved face, once: it is the same for every face
  // around the vertex (the same bits) unless the surface's gradient vanishes there (a cone's
  // apex, a cap's centre on the axis), where it depends on the face's centre and is computed
  // per corner. `regular`: 1 cached, 2 per corner, 0 on no curved face.
  std::vector<char> regular;
  std::vector<Vec3> vertex_normal;
  if (surface.is_smooth()) {
    regular.assign(v.size(), 0);
    vertex_normal.assign(v.size(), Vec3::Zero());
    for (size_t f = 0; f < faces.size(); ++f) {
      if (!normals.analytic(static_cast<int>(f))) continue;
      for (const auto& loop : faces[f].loops)
        for (int x : loop) regular[static_cast<size_t>(x)] = 1;
    }
    parallel_chunks(v.size(), kChunk, [&](size_t, size_t begin, size_t end) {
      for (size_t x = begin; x != end; ++x) {
        if (regular[x] == 0) continue;
        const std::optional<Vec3> n = surface.vertex_normal(v[x]);
        regular[x] = n ? 1 : 2;
        if (n) vertex_normal[x] = *n;
      }
    });
  }
  const auto corner_normal = [&](int f, int x) {
    if (!normals.analytic(f)) return normals.normal(f, x, Vec3::Zero());
    if (regular[static_cast<size_t>(x)] == 1) return vertex_normal[static_cast<size_t>(x)];
    return normals.normal(f, x, face_centre(body, f));
  };

  // Singular points of the analytic surface (a cone's apex): the curved faces around the
  // vertex give it different normals, one per face. Every contour generator passes through
  // such a point, so n·r counts as 0 there: the contour reaches it from the one triangle
  // where the sign changes on the opposite side, instead of stopping short at a side.
  std::vector<char> singular(v.size(), 0);
  if (surface.is_smooth()) {
    std::vector<char> seen(v.size(), 0);
    std::vector<Vec3> first(v.size());
    for (size_t f = 0; f < faces.size(); ++f) {
      if (!normals.analytic(static_cast<int>(f))) continue;
      for (const auto& loop : faces[f].loops)
        for (int x : loop) {
          if (regular[static_cast<size_t>(x)] == 1) continue;  // one normal for all its faces
          const Vec3 n = corner_normal(static_cast<int>(f), x);
          const size_t i = static_cast<size_t>(x);
          if (!seen[i]) seen[i] = 1, first[i] = n;
          else if (!(first[i] - n).isZero(1e-9)) singular[i] = 1;
        }
    }
  }

  // n·r at the shared vertices, once each (the same value every triangle there would compute).
  std::vector<double> shared_g(v.size(), 0);
  for (size_t x = 0; x < v.size(); ++x)
    if (normals.shared(static_cast<int>(x)) && !singular[x])
      shared_g[x] = normals.shared_normal(static_cast<int>(x)).dot(view.ray_to(v[x]));
  // And at the vertices with a cached analytic normal.
  std::vector<double> analytic_g;
  if (surface.is_smooth()) {
    analytic_g.assign(v.size(), 0);
    for (size_t x = 0; x < v.size(); ++x)
      if (regular[x] == 1) analytic_g[x] = vertex_normal[x].dot(view.ray_to(v[x]));
  }

  // The triangles in fixed chunks, each chunk's segments in triangle order, the chunks in
  // order: the same list at any thread count.
  // A two-sided body lists the triangles of its front side first; its other side has the same
  // contour (its corner normals are the negated ones), so only the front side is traced.
  const auto& triangles = body.triangles();
  const size_t traced = body.two_sided() ? triangles.size() / 2 : triangles.size();
  std::vector<std::vector<OutlineSegment>> chunk_out((traced + kChunk - 1) / kChunk);
  parallel_chunks(traced, kChunk, [&](size_t c, size_t begin, size_t end) {
    std::vector<OutlineSegment>& out = chunk_out[c];
    for (size_t ti = begin; ti != end; ++ti) {
      const Triangle& t = triangles[ti];
      // Quick rejection: three shared non-analytic corners of one sign (flat or not, no contour).
      if (!normals.analytic(t.face)) {
        int positive = 0;
        bool all_shared = true;
        for (int k = 0; k < 3 && all_shared; ++k) {
          const size_t x = static_cast<size_t>(t.v[k]);
          all_shared = normals.shared(t.v[k]) && !singular[x];
          positive += shared_g[x] >= 0;
        }
        if (all_shared && (positive == 0 || positive == 3)) continue;
      } else {
        // Three cached analytic corners of one sign: the same test as below, without the normals.
        int positive = 0;
        bool cached = true;
        for (int k = 0; k < 3 && cached; ++k) {
          const size_t x = static_cast<size_t>(t.v[k]);
          cached = regular[x] == 1;
          positive += analytic_g[x] >= 0;
        }
        if (cached && (positive == 0 || positive == 3)) continue;
      }
      // A flat-shaded triangle (every corner on the face's own normal) has n·r of one sign in
      // exact arithmetic, the sign facing() decides; rounding must not make a contour there
      // (a box face seen edge-on).
      const Vec3& face_normal = normals.face_normal(t.face);
      Vec3 n[3];
      bool flat = true;
      for (int k = 0; k < 3; ++k) {
        n[k] = corner_normal(t.face, t.v[k]);
        flat = flat && n[k] == face_normal;
      }
      if (flat) continue;
      double g[3];
      const Vec3* corner[3];
      for (int k = 0; k < 3; ++k) {
        corner[k] = &v[static_cast<size_t>(t.v[k])];
        g[k] = singular[static_cast<size_t>(t.v[k])] ? 0.0 : n[k].dot(view.ray_to(*corner[k]));
      }
      // Crossings from the end with the smaller vertex index: the neighbour gets the same point.
      Vec3 ends[2];
      if (internal::contour_segment(corner, g, t.v.data(), ends)) out.push_back({ends[0], ends[1], t.face});
    }
  });
  std::vector<OutlineSegment> out;
  for (auto& chunk : chunk_out) out.insert(out.end(), chunk.begin(), chunk.end());
  return out;
}

}  // namespace hedra
