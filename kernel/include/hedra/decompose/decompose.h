// Exact convex decomposition by plane splitting (docs/algorithms.md §5.3).
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/core/error.h"  // DecompositionCancelled, DecompositionFailed

namespace hedra {

struct DecomposeOptions {
  /// More pieces than this is an error (InvalidInput naming the count).
  int max_pieces = 100000;
  /// Called after every round of cuts with (pieces done, pieces still open); returning false
  /// cancels (DecompositionCancelled).
  std::function<bool(int done, int open)> progress;
  /// Worker threads for independent pieces (0: TBB's default). The result does not depend on it.
  int threads = 0;
  /// Verify the result in exact arithmetic: every piece convex and the pieces' exact volumes
  /// summing to the input's exact volume (sets Decomposition::verified).
  bool verify = false;
  /// After cutting, join adjacent pieces whose union is convex (decided exactly), greedily in
  /// canonical order. Fewer pieces; each merged piece is still convex and the cover exact.
  bool merge = false;
};

struct Decomposition {
  std::vector<Body> pieces;  // convex, interior-disjoint, covering the input; canonical order
  int cuts = 0;              // plane cuts made
  int merges = 0;            // pieces joined by the merge pass (DecomposeOptions::merge)
  bool verified = false;     // exact checks passed (only with DecomposeOptions::verify)
  double exact_volume = 0;   // input volume from the exact computation (with verify)
  /// Pieces that could not be represented in double: exact pieces whose rounded corners are
  /// all coplanar (slivers thinner than rounding everywhere; their volume is below rounding),
  /// and CGAL's slivers whose corners coincide after rounding (decompose_cgal). Not in
  /// `pieces`.
  int degenerate_pieces = 0;
};

/// Joins adjacent convex bodies whose union is convex, greedily, until no pair is left: the
/// merge pass of DecomposeOptions::merge, for pieces from any method (TetGen's tetrahedra,
/// CGAL's pieces). Two pieces with faces on one plane from opposite sides join iff each one's
/// vertices lie inside the other's remaining face planes (exact sides; faces of different
/// pieces on one plane within rounding count as one plane). Pieces that are not exactly
/// convex (rounded pieces of another method) come first, unchanged; then the merged ones in
/// canonical order. Cost O(P·F·V) per pass.
std::vector<Body> merge_convex(const std::vector<Body>& pieces, int* merges = nullptr);

/// The course's method, exactly: while a piece has a reflex edge, cut it by the plane of a face
/// at such an edge (the one lying on the most reflex edges, then crossing the fewest faces,
/// then the first in input order), split it into connected components, continue.
///
/// Exactness: points are CGAL Epeck points (cut points are exact intersections of input edges
/// with input planes); each point also carries the input planes it lies on, so a vertex is on
/// its own faces' planes symbolically even when rotated coordinates put it a few ulps off.
/// Input faces whose planes coincide within rounding (kRoundingPlanarity) share one plane.
/// Where that model of the input contradicts itself (features at the guard's scale: a failed
/// cut, a failed verification, a fold the guard hides), the input itself is decomposed with
/// the exact planes of its triangles and exact sides only: a second run, more pieces.
/// A convex input comes back as one piece, unchanged. Deterministic for any thread count.
/// Rounding, once at the end: each piece is the exact piece rounded to double with its faces
/// merged by plane; where rounding breaks a face (slivers of cuts through nearly coplanar
/// faces, e.g. a rotated float32 STL), the convex hull of the piece's rounded corners, within
/// half an ulp per coordinate of the exact piece; a piece whose rounded corners are coplanar
/// is left out and counted in degenerate_pieces. Never fails on a valid body.
/// Cost per cut of a piece with V points, T triangles and C candidate planes: O(min(C, 64)·(V + T))
/// exact sides (16 candidates weighed when C > 64, preferring cuts that halve the piece) plus
/// the split and simplification, O(T log T); pieces keep only their corners, so a prism over an
/// n-point star takes O(n log n) in all (docs/algorithms.md §5.3).
/// \throw InvalidInput when more than options.max_pieces pieces are needed.
/// \throw DecompositionCancelled when the progress callback returns false.
Decomposition decompose(const Body& body, const DecomposeOptions& options = {});


}  // namespace hedra
