// Internals of the exact plane splitting (hedra/decompose/split.h, split.cpp) shared with
// the convex decomposition (decompose.cpp): exact pieces as triangles on canonical planes.
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <vector>

#include "core/exact_solid.h"
#include "core/normal_index.h"
#include "hedra/core/body.h"

namespace hedra::internal {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using P3 = EK::Point_3;
using PL = EK::Plane_3;

// Canonical planes, oriented outwards for input faces: a point strictly outside a face is on
// the plane's positive side.
struct Context {
  std::vector<PL> planes;
  std::vector<Plane> approx;  // unit-normal double planes, same orientation (for the guard)
  // The three input vertices each plane was built through (zero for a plane given by
  // coefficients: split()'s cutting plane); InputPlanes::support.
  std::vector<std::array<Vec3, 3>> support;
  double guard = 0;           // rounding guard for input vertices (see side())
  // Exact planes only (the fallback of decompose()): every canonical plane is the exact plane
  // of input triangles, shared only by triangles exactly on it; no guard, so every side is
  // the exact predicate on the double input. The polyhedron decided on is then the input
  // itself, so no decision can contradict another.
  bool exact_planes = false;
  // The floating-point variant: sides from double evaluation with a tolerance, cut points
  // computed in double; no symbolic incidence. Kept for the speed–accuracy comparison.
  bool floating = false;
  double epsilon = 0;  // absolute, in world units
  // Pieces are simplified after every cut (simplify()); off in the fallback runs of decompose().
  bool simplify = true;
  // Index of `approx` by unit normal (filled lazily), so that piece_of() finds a face's plane
  // among the planes met before without scanning them all.
  NormalIndex normals;
  // A work budget for a run that has an alternative (decompose(): a moved body's exact
  // image): the exact cut points split() may make in all, 0 for no limit. Past it split()
  // throws CutBudgetExceeded; cut_points counts them (only where there is a budget: one
  // shared atomic in the parallel cuts' hot loop).
  size_t cut_budget = 0;
  mutable std::atomic<size_t> cut_points{0};
  // The exact planes of triangles off their canonical plane (Tri::own): made while reading the
  // body and by caps (cuts run in parallel, hence the lock); a deque keeps their addresses.
  mutable std::mutex own_mutex;
  mutable std::deque<PL> own_planes;
  const PL* keep_own_plane(const P3& a, const P3& b, const P3& c) const {
    std::lock_guard<std::mutex> lock(own_mutex);
    return &own_planes.emplace_back(a, b, c);
  }
};

/// Thrown by split() when a run has made Context::cut_budget exact cut points.
struct CutBudgetExceeded {};

struct Point {
  P3 p;
  std::vector<int> on;  // sorted ids of canonical planes the point lies on, by construction
  // The ids in `on` that hold only within the rounding guard (an input vertex a few ulps off a
  // plane its face shares with coplanar-within-rounding faces), not exactly: a face with such a
  // vertex is never re-triangulated (simplify), since that would change the exact volume.
  std::vector<int> loose;
  int origin = -1;      // input vertex id, or −1 for a point made by a cut
  // Construction depth: 0 for input vertices and cut points that are doubles, else the
  // number of segment intersections in the chain that made it (split.cpp, cut_point_of).
  // Caps and simplify() spend work on folded faces only where points are deep.
  int depth = 0;
  Vec3 input = Vec3::Zero();  // the input's double coordinates (origin >= 0)
};

// A triangle on canonical plane `plane`; sign +1: its outward normal is the plane's normal.
// `own`: where the triangle is coplanar with its canonical plane only within the rounding
// guard (a face of a rotated body; a cap through a guarded input vertex, where the cap holds
// points made by chains of cuts), the exact plane of the triangle it is a part of, shared by
// all its parts: the parts of a triangle lie exactly on that triangle's plane. simplify()
// re-triangulates the parts of one such triangle together without changing the exact volume;
// without that, the points made on the diagonals of such faces were cut again and again, and
// their coordinates grew without bound. Null otherwise, which does not mean the triangle lies
// exactly on its canonical plane (a cap through a guarded vertex may not; its vertices' `loose`
// lists say so).
struct Tri {
  std::array<int, 3> v;
  int plane;
  int sign;
  const PL* own = nullptr;  // in Context::own_planes
};

struct Piece {
  std::vector<Point> pts;
  std::vector<Tri> tris;
};

// A lazy exact number rounded to a double, the same whatever was evaluated before. CGAL's
// to_double reads a lazy number's interval, which is tight only once the exact value has been
// computed: by an earlier decision, or by another thread on a point its piece shares with ours
// (the pieces of a round run in parallel and share their cut points). Reading the loose
// interval made the rounded pieces, and so the drawings made with them, change in the last
// bit from run to run. So the exact value is computed first, unless the interval is a point.
inline double rounded(const EK::FT& x) {
  const std::pair<double, double> i = CGAL::to_interval(x);
  if (i.first == i.second) return i.first;
  CGAL::exact(x);
  return CGAL::to_double(x);
}
inline Vec3 rounded(const P3& p) { return Vec3(rounded(p.x()), rounded(p.y()), rounded(p.z())); }

inline std::uint64_t key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

// Side of a point with respect to canonical plane `id`: +1 outside (positive side), −1, or 0
// (split.cpp). Cost O(1) exact.
int side(const Context& ctx, const Point& pt, int id);
// Records that pt lies on canonical plane id (sorted, no repeats).
void add_on(Point& pt, int id);
// Inserts id into a sorted id list (no repeats).
void add_on_sorted(std::vector<int>& ids, int id);
// Groups the body's faces into canonical planes and builds the exact piece of the whole body.
// Cost O(V + F log F).
Piece piece_of(const Body& body, Context& ctx);
// The exact piece of an exact solid (a Boolean's result, Body::exact_solid()) for a run with
// Context::exact_planes: its exact corners are the points (made, not input vertices: origin
// −1), each face one canonical plane through three of its corners, shared by faces exactly on
// it (either orientation). nullopt when a face is not exactly planar (operands rotated in
// double: the solid inherits their faces' ulp folds); the caller then decomposes the rounded
// body with the rounding guard instead. `scale`: the body's, for the normal index.
// `face_plane`, where given: per face of the solid's triangles (ExactSolid::Tri::face), its
// (canonical plane, sign) ((−1, 0) for a face no triangle names).
// Cost O(T) exact orientation tests.
std::optional<Piece> piece_of(const ExactSolid& solid, double scale, Context& ctx,
                              std::vector<std::pair<int, int>>* face_plane = nullptr);
// The connected components of a triangle soup, as pieces. Cost O(T).
std::vector<Piece> components(const std::vector<Point>& pts, const std::vector<Tri>& tris);

struct Sides {
  std::vector<Piece> below, above;
  bool cut = false;  // false when the plane does not pass through the piece's interior
};

// A piece cut by canonical plane `plane`, the caps triangulated exactly. Cost O(T + C log C)
// for T triangles and C cap vertices.
Sides split_piece(const Context& ctx, const Piece& in, int plane);
// Drops the vertices of a closed piece that are not corners — inside a face (every triangle
// around it on one face) or on a straight edge between two faces on non-parallel planes —
// and re-triangulates the faces that held them from their corners (constrained
// triangulation). Cuts leave such vertices behind (cut points of crossed triangles, a cap's
// points on straight runs); without this they pile up in the descendants and every later cut
// pays for them. Decided symbolically (which faces meet at a vertex); only faces whose
// vertices all lie exactly on their plane are re-triangulated — a face is the triangles on one
// canonical plane and side, or the parts of one triangle off it (Tri::own, exactly on their own
// plane) — so the exact volume and every exact side are unchanged. Leaves the piece as it is where a face is not a simple set of
// loops. Cost O(T log T) plus the triangulation of the changed faces.
void simplify(const Context& ctx, Piece& piece);
// A piece back to a Body (coordinates rounded once). Cost O(T log T).
Body body_of(const Piece& piece);

}  // namespace hedra::internal
