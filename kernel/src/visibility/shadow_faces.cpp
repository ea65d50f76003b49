// Shadows: faces in their own 2D frames and their convex parts (shadows_internal.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <unordered_map>

#include "hedra/core/face_geometry.h"
#include "hedra/core/tolerance.h"
#include "visibility/shadows_internal.h"

namespace hedra::internal {
namespace {

// Convex parts of a face: the outer loop itself when it is convex and has no holes, else the
// face's triangles merged greedily while the union stays convex (Hertel–Mehlhorn): always the
// first pair in list order (then the first shared edge of the first polygon) whose union is
// convex, until none is left. Computed without rescanning every pair after each merge: a
// pair's test depends only on its two polygons, so after a merge only the merged polygon and
// its neighbours listed before it can have a new merge; the smallest polygon that may still
// have one is taken next (an ordered work set), which finds the same pairs in the same order
// as the plain rescan. Shared edges from a directed-edge map, and the union of two convex
// polygons sharing one edge is convex iff its angles at that edge's two ends are (the other
// corners keep their neighbours). Cost O(T + M·d) for T triangles, M merges and d the largest
// number of neighbours of a part (was O(T³) with the rescans: minutes for a 4000-point star).
void convex_parts(const Body& body, int f, ShadowFace& fd) {
  const Face& face = body.faces()[static_cast<size_t>(f)];
  const auto& v = body.vertices();
  // The turn at b between a and c as seen in the face's 2D frame (counter-clockwise there; the
  // frame's orientation is the face's reversed when flip): exact, on the dropped coordinates.
  auto turn = [&](int a, int b, int c) {
    const Vec2 pa = drop(v[static_cast<size_t>(a)], fd.axis), pb = drop(v[static_cast<size_t>(b)], fd.axis),
               pc = drop(v[static_cast<size_t>(c)], fd.axis);
    return fd.flip ? orient2d(pc, pb, pa) : orient2d(pa, pb, pc);
  };
  // Exact convexity of a loop of vertex ids, counter-clockwise in that frame (collinear
  // vertices allowed), without building its 2D ring (a mesh has a million triangular faces).
  auto convex_loop = [&](const std::vector<int>& ids) {
    const size_t m = ids.size();
    for (size_t i = 0; i < m; ++i)
      if (turn(ids[(i + m - 1) % m], ids[i], ids[(i + 1) % m]) == Sign::Negative) return false;
    return true;
  };
  if (face.loops.size() == 1 && convex_loop(face.loops[0])) {
    fd.convex = true;
    return;
  }
  fd.convex = false;
  std::vector<std::vector<int>> polys;
  for (const Triangle& t : body.triangles())
    if (t.face == f) polys.push_back({t.v[0], t.v[1], t.v[2]});
  const size_t n = polys.size();
  std::vector<char> alive(n, 1), convex(n, 0);
  for (size_t k = 0; k < n; ++k) convex[k] = convex_loop(polys[k]);
  auto edge_key = [](int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  };
  std::unordered_map<std::uint64_t, size_t> owner;  // directed edge -> polygon
  for (size_t k = 0; k < n; ++k)
    for (size_t i = 0; i < 3; ++i) owner[edge_key(polys[k][i], polys[k][(i + 1) % 3])] = k;
  auto neighbour = [&](int u, int w) -> long {  // the polygon with edge w -> u
    auto it = owner.find(edge_key(w, u));
    return it == owner.end() ? -1 : static_cast<long>(it->second);
  };
  // The union of A and B across A's edge i (B has the reverse edge), in the original order.
  auto join = [&](const std::vector<int>& A, size_t i, const std::vector<int>& B) {
    const int u = A[i], w = A[(i + 1) % A.size()];
    size_t j = 0;
    while (!(B[j] == w && B[(j + 1) % B.size()] == u)) ++j;
    std::vector<int> m;
    for (size_t s = 0; s < A.size(); ++s) m.push_back(A[(i + 1 + s) % A.size()]);  // w … u
    for (size_t s = 2; s < B.size(); ++s) m.push_back(B[(j + s) % B.size()]);       // after u … before w
    return m;
  };
  auto shared_edges = [&](size_t a, size_t b) {
    const size_t small = polys[a].size() <= polys[b].size() ? a : b, other = small == a ? b : a;
    const auto& P = polys[small];
    int count = 0;
    for (size_t i = 0; i < P.size(); ++i) count += neighbour(P[i], P[(i + 1) % P.size()]) == static_cast<long>(other);
    return count;
  };
  // Whether joining A (polygon a) and B across A's edge i gives a convex polygon; the joined
  // ring when it does. Exactly convex_loop of the joined ring.
  auto try_join = [&](size_t a, size_t i, size_t b, std::vector<int>& m) {
    const auto &A = polys[a], &B = polys[b];
    if (convex[a] && convex[b] && shared_edges(a, b) == 1) {
      const int u = A[i], w = A[(i + 1) % A.size()];
      size_t j = 0;
      while (!(B[j] == w && B[(j + 1) % B.size()] == u)) ++j;
      const int before_u = A[(i + A.size() - 1) % A.size()], after_u = B[(j + 2) % B.size()];
      const int before_w = B[(j + B.size() - 1) % B.size()], after_w = A[(i + 2) % A.size()];
      if (turn(before_u, u, after_u) == Sign::Negative || turn(before_w, w, after_w) == Sign::Negative) return false;
      m = join(A, i, B);
      return true;
    }
    m = join(A, i, B);
    return convex_loop(m);
  };
  std::set<size_t> unknown;  // polygons that may still have a merge with a later one
  for (size_t k = 0; k < n; ++k) unknown.insert(k);
  while (!unknown.empty()) {
    const size_t a = *unknown.begin();
    // The first later polygon (in list order) with a convex union, through A's first such edge.
    std::vector<std::pair<size_t, size_t>> later;  // (later polygon, edge of A), in scan order
    for (size_t i = 0; i < polys[a].size(); ++i) {
      const long b = neighbour(polys[a][i], polys[a][(i + 1) % polys[a].size()]);
      if (b > static_cast<long>(a)) later.emplace_back(static_cast<size_t>(b), i);
    }
    std::sort(later.begin(), later.end());
    bool merged = false;
    for (const auto& [b, i] : later) {
      {
        std::vector<int> m;
        if (!try_join(a, i, b, m)) continue;
        // The shared edge goes; B's other edges now belong to A.
        const int u = polys[a][i], w = polys[a][(i + 1) % polys[a].size()];
        owner.erase(edge_key(u, w));
        owner.erase(edge_key(w, u));
        for (size_t k = 0; k < polys[b].size(); ++k) {
          auto it = owner.find(edge_key(polys[b][k], polys[b][(k + 1) % polys[b].size()]));
          if (it != owner.end() && it->second == b) it->second = a;
        }
        polys[a] = std::move(m);
        polys[b].clear();
        alive[b] = 0;
        unknown.erase(b);
        convex[a] = 1;
        merged = true;
      }
      if (merged) break;
    }
    if (!merged) {
      unknown.erase(a);
      continue;
    }
    // The merged polygon changed: it stays to be checked, and so do its earlier neighbours.
    for (size_t i = 0; i < polys[a].size(); ++i) {
      const long c = neighbour(polys[a][i], polys[a][(i + 1) % polys[a].size()]);
      if (c >= 0 && c < static_cast<long>(a)) unknown.insert(static_cast<size_t>(c));
    }
  }
  for (size_t k = 0; k < n; ++k) {
    if (!alive[k]) continue;
    Polygon3 p;
    for (int id : polys[k]) p.push_back(v[static_cast<size_t>(id)]);
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
  Eigen::AlignedBox3d box;
  fd.corners.reserve(face.loops[0].size());
  for (int id : face.loops[0]) {
    fd.corners.push_back(body.vertices()[static_cast<size_t>(id)]);
    box.extend(fd.corners.back());
  }
  fd.centre = box.center();
  fd.radius = 0.5 * box.diagonal().norm();
  // Exactly planar (the body's constructor decided it): polygon clipping then decides its
  // vertices as they are.
  fd.planar = !body.face_off_plane(f);
  if (!fd.planar && face.loops.size() == 1) {
    // Off its plane and convex: its triangles (convex_polygon_split, as a convex body's
    // occluder, exactly_planar_convex, takes them), each on its own plane.
    const auto& c = fd.corners;
    fd.split = convex_polygon_split(c);
    if (!fd.split.empty()) {
      fd.convex = false;
      for (const auto& k : fd.split) {
        const std::array<Vec3, 3> t{c[static_cast<size_t>(k[0])], c[static_cast<size_t>(k[1])], c[static_cast<size_t>(k[2])]};
        fd.parts.push_back({t[0], t[1], t[2]});
        fd.part_planes.push_back(triangle_plane(t));
      }
      return fd;
    }
  }
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

namespace {

// A ring with its rounding debris removed (kShadowDebris), on one pass with a stack and then
// around the seam: a vertex within `snap` (max-norm) of the one before it is dropped, and so is
// a spike, a vertex q where the ring goes out and comes back along the same line (both
// neighbours on the same side of q, the nearer within snap of the line through q and the
// farther: a slit of no width between two pieces whose edges are an ulp apart). False when
// what is left is not a ring (under 3 vertices) or thinner than snap (2 · |area| / perimeter).
// O(n).
bool without_debris(const Ring2& ring, double snap, Ring2& out) {
  const auto close = [snap](const Vec2& a, const Vec2& b) {
    return (a - b).cwiseAbs().maxCoeff() <= snap;
  };
  const auto spike = [snap](const Vec2& a, const Vec2& q, const Vec2& b) {
    const Vec2 u = a - q, w = b - q;
    const double height_times_longer = std::abs(u.x() * w.y() - u.y() * w.x());
    return u.dot(w) > 0 && height_times_longer <= snap * std::max(u.norm(), w.norm());
  };
  out.clear();
  out.reserve(ring.size());
  for (const Vec2& v : ring) {
    out.push_back(v);
    for (;;) {
      const size_t n = out.size();
      if (n >= 2 && close(out[n - 2], out[n - 1])) {
        out.pop_back();
      } else if (n >= 3 && spike(out[n - 3], out[n - 2], out[n - 1])) {
        out.erase(out.end() - 2);
      } else {
        break;
      }
    }
  }
  for (bool changed = true; changed && out.size() >= 3;) {  // around the seam
    const size_t n = out.size();
    changed = true;
    if (close(out[n - 1], out[0]) || spike(out[n - 2], out[n - 1], out[0]))
      out.pop_back();
    else if (spike(out[n - 1], out[0], out[1]))
      out.erase(out.begin());
    else
      changed = false;
  }
  if (out.size() < 3) return false;
  double perimeter = 0;
  for (size_t k = 0; k < out.size(); ++k) perimeter += (out[(k + 1) % out.size()] - out[k]).norm();
  return 2 * std::abs(ring_area(out)) > snap * perimeter;
}

}  // namespace

void lift_polygon(const ShadowFace& fd, const PolygonWithHoles2& p, double scale,
                  std::vector<ShadowPolygon>& out) {
  const double snap = kShadowDebris * scale;
  Ring2 ring;
  if (!without_debris(p.outer, snap, ring)) return;
  PolygonWithHoles2 kept;
  kept.outer = ring;
  for (const Ring2& h : p.holes)
    if (without_debris(h, snap, ring)) kept.holes.push_back(ring);
  ShadowPolygon s;
  s.outer = fd.lift(kept.outer);
  for (const Ring2& h : kept.holes) s.holes.push_back(fd.lift(h));
  s.area = polygon_area(kept) * fd.area_factor;
  out.push_back(std::move(s));
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
