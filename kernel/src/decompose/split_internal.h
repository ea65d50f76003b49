// Internals of the exact plane splitting (hedra/decompose/split.h, split.cpp) shared with
// the convex decomposition (decompose.cpp): exact pieces as triangles on canonical planes.
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

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
  // Index of `approx` by unit normal (cells of kNormalCell, filled lazily up to `indexed`), so
  // that piece_of() finds a face's plane among the planes met before without scanning them all.
  std::unordered_map<std::uint64_t, std::vector<int>> normal_cells;
  size_t indexed = 0;
};

struct Point {
  P3 p;
  std::vector<int> on;  // sorted ids of canonical planes the point lies on, by construction
  int origin = -1;      // input vertex id, or −1 for a point made by a cut
  Vec3 input = Vec3::Zero();  // the input's double coordinates (origin >= 0)
};

// A triangle on canonical plane `plane`; sign +1: its outward normal is the plane's normal.
struct Tri {
  std::array<int, 3> v;
  int plane;
  int sign;
};

struct Piece {
  std::vector<Point> pts;
  std::vector<Tri> tris;
};

inline std::uint64_t key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

// Side of a point with respect to canonical plane `id`: +1 outside (positive side), −1, or 0
// (split.cpp). Cost O(1) exact.
int side(const Context& ctx, const Point& pt, int id);
// Records that pt lies on canonical plane id (sorted, no repeats).
void add_on(Point& pt, int id);
// Groups the body's faces into canonical planes and builds the exact piece of the whole body.
// Cost O(V + F log F).
Piece piece_of(const Body& body, Context& ctx);
// The connected components of a triangle soup, as pieces. Cost O(T).
std::vector<Piece> components(const std::vector<Point>& pts, const std::vector<Tri>& tris);

struct Sides {
  std::vector<Piece> below, above;
  bool cut = false;  // false when the plane does not pass through the piece's interior
};

// A piece cut by canonical plane `plane`, the caps triangulated exactly. Cost O(T + C log C)
// for T triangles and C cap vertices.
Sides split_piece(const Context& ctx, const Piece& in, int plane);
// A piece back to a Body (coordinates rounded once). Cost O(T log T).
Body body_of(const Piece& piece);

}  // namespace hedra::internal
