// Exact convex decomposition by plane splitting (docs/algorithms.md §5.3).
#pragma once

#include <array>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "hedra/core/body.h"
#include "hedra/core/error.h"  // DecompositionCancelled, DecompositionFailed
#include "hedra/core/predicates.h"

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
  /// Also return each piece as exact planes (Decomposition::exact_pieces), for consumers that
  /// clip against the pieces (hidden lines, shadows, clipping). Costs a few exact tests per
  /// triangle of each piece.
  bool exact_pieces = false;
  /// Decompose the exact solid a Boolean's result keeps (Body::exact_solid()) rather than its
  /// rounding, where the Boolean rounded a corner of its body and the solid's faces are exactly
  /// planar (Decomposition::from_exact_solid; else the body, as any other).
  /// Its pieces and exact_pieces are then those of the exact result, and `planes` and
  /// `piece_planes` the solid's face planes, with the rounded body's vertices on them by
  /// construction (the solid's corners they round) and its faces on them (the solid's faces
  /// they round): hidden lines and shadows decide incidence with the rounded body's edges
  /// through them, as with the guarded run's model.
  /// A body with no solid whose faces are planar only within rounding (Body::faces_off_plane():
  /// a rotated part read from OFF, OBJ or PLY) has its plane solid stand in as a moved body's
  /// exact image does (below, and past a cut budget of 8·V + 4096): each face on one exact
  /// plane — faces coplanar within the rounding guard, with one orientation, share one, through
  /// three input vertices (core/exact_solid.h) —
  /// and each vertex off one of its planes moved to where its planes meet exactly (three of
  /// them, concurrent with the rest; the foot on the line of two, or on the plane of one), by
  /// at most 16 guards (kRoundingPlanarity × scale each). Where a vertex's planes do not meet in
  /// one point (a torus's quadrilaterals, four planes at a vertex) there is none, and the body
  /// is cut in the guarded model as before. Cost of making it O(V + T) exact constructions.
  bool from_exact_solid = true;
  /// With from_exact_solid: cut a moved body from its exact image (a body with exactly planar
  /// faces moved by an affine map), or a file's rotated part from its plane solid, whenever it
  /// has one, not only past the guarded run's cut budget. Every piece is then exactly convex, so its consumers clip against the exact piece
  /// (Decomposition::exact_pieces), never a rounded one; the guarded run's exact pieces of a
  /// rotated body fold by an ulp across its quadrilaterals and mostly have none. Costs 1.3–4×
  /// the guarded run on the benchmark's rotated shapes (milliseconds). Hidden lines, shadows and
  /// `clip`'s midpoint method set it (the first two occlude by a file's rotated part's
  /// triangles, Occluders::Auto, without decomposing it).
  bool prefer_exact_solid = false;
};

/// The exact planes the decomposition cut and bounded its pieces with, for consumers that must
/// decide incidence with a piece's faces exactly although the pieces are rounded (hidden lines,
/// shadows: an edge or face of the input lying on a piece's face; docs/design.md, "Exact
/// inside, rounded only at the edge"). Every face of an exact piece lies on one canonical
/// plane: the plane of an input face (or, in the exact-planes run, of an input triangle)
/// through three input vertices; input faces coplanar within rounding share one. Where the
/// pieces are those of the body's exact solid (Decomposition::from_exact_solid), the planes are
/// the solid's face planes, exactly coplanar faces sharing one: through three input vertices
/// where three corners of the face are doubles, else given by exact coefficients (`exact`);
/// the body's vertices are the solid's corners rounded, on their faces' planes by
/// construction. Value type.
struct InputPlanes {
  /// Per canonical plane: three input vertices it passes through, ordered so that
  /// orient3d(s[0], s[1], s[2], p) is Positive for p strictly on its positive side (outside the
  /// input faces that have sign +1 on it). Zero for a plane given by `exact`.
  std::vector<std::array<Vec3, 3>> support;
  /// Per canonical plane (empty, or as many as `support`): the plane's exact coefficients
  /// (ExactPlane::by_exact(), positive side Positive) where no three input vertices support
  /// it (a face of a moved body's exact image, or of a Boolean's solid, through corners that
  /// are not doubles); a default plane elsewhere.
  std::vector<ExactPlane> exact;
  /// Per canonical plane: unit-normal double plane (same orientation), and the rounding guard
  /// (0 in the exact-planes run): the model's rule for input vertices (see on()).
  std::vector<Plane> approx;
  double guard = 0;
  /// Per input vertex: the canonical planes it lies on by construction (its faces'), sorted.
  std::vector<std::vector<int>> vertex_planes;
  /// Per input face: (canonical plane, sign) of its triangles, sorted (one pair in the guarded
  /// run); sign +1 when the face's outward normal is the plane's positive side.
  std::vector<std::vector<std::pair<int, int>>> face_planes;
  /// Whether input vertex v (coordinates p) lies on canonical plane c in the decomposition's
  /// model of the input, the rule every cut was decided with: by construction, or exactly
  /// (side()), or within the rounding guard of the plane (input vertices only: a rotated
  /// body's coplanar faces). Cost O(log k) + one exact predicate.
  bool on(int c, int v, const Vec3& p) const;
  /// Exact side of point p (orient3d on the support triple, or the sign of the exact
  /// coefficients at p): Positive on the positive side.
  Sign side(int c, const Vec3& p) const;
  /// Exact side moving along direction d goes to (orient_direction on the support triple, or
  /// the sign of the exact normal's product with d).
  Sign side_along(int c, const Vec3& d) const;
  bool empty() const { return support.empty(); }
};

/// A convex piece as exact planes: the piece is the intersection of the inner (Positive)
/// half-spaces of `faces`, exactly, whatever rounding did to its double corners. Each face is
/// the supporting plane of one face of the exact piece: the input plane through three input
/// vertices (ExactPlane::through) where the face lies on it exactly, else the plane of three
/// of the exact piece's corners with multiprecision coefficients (ExactPlane::by_exact(): a
/// face through vertices only within rounding of an input plane, a rotated float32 part's).
/// `edges` lists each pair of faces (j < k) meeting at an edge of the exact piece, once: what
/// an occlusion volume needs for its silhouette (occlusion_volume(const ExactConvex&, …),
/// hedra/visibility/occlusion.h), with no corner rounded. Value type.
struct ExactConvex {
  std::vector<ExactPlane> faces;
  std::vector<std::pair<int, int>> edges;
  /// Per face: the canonical plane (Decomposition::planes) it lies on exactly, or −1 (a face
  /// through vertices only within rounding of one). Where an input vertex lies on a face in
  /// the model (InputPlanes::on), so it does on the exact piece: what lets hidden lines end a
  /// hidden part exactly at a vertex whose rounded coordinates are an ulp off the face.
  std::vector<int> canonical;
};

struct Decomposition {
  std::vector<Body> pieces;  // convex, interior-disjoint, covering the input; canonical order
  /// Per piece: (canonical plane, sign) of every face of the exact piece, sorted; sign +1 when
  /// the piece lies on the plane's negative side. Exact whatever rounding did to `pieces`
  /// (the convex-hull fallback included). Empty for a convex input (its one piece is the body
  /// itself) and for the floating method.
  std::vector<std::vector<std::pair<int, int>>> piece_planes;
  InputPlanes planes;
  /// Per piece of `pieces`: the exact piece as planes (ExactConvex), for the consumers that
  /// clip against it (hidden lines, shadows, clipping): nothing they decide depends on the
  /// rounded corners. Only with DecomposeOptions::exact_pieces; empty where piece_planes is; a piece with no faces where the exact piece
  /// is not exactly convex (the guarded run decides convexity with input vertices within the
  /// rounding guard of a plane counted on it, so a piece can fold by an ulp there): its
  /// consumers keep the rounded piece.
  std::vector<ExactConvex> exact_pieces;
  int cuts = 0;              // plane cuts made
  int merges = 0;            // pieces joined by the merge pass (DecomposeOptions::merge)
  bool verified = false;     // exact checks passed (only with DecomposeOptions::verify)
  double exact_volume = 0;   // input volume from the exact computation (with verify)
  /// Pieces that could not be represented in double: exact pieces whose rounded corners are
  /// all coplanar (slivers thinner than rounding everywhere; their volume is below rounding),
  /// and CGAL's slivers whose corners coincide after rounding (decompose_cgal). Not in
  /// `pieces`.
  int degenerate_pieces = 0;
  /// The pieces are those of the body's exact solid, or of its plane solid
  /// (DecomposeOptions::from_exact_solid).
  bool from_exact_solid = false;
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
/// A Boolean's result is cut from its exact solid, a moved body from its exact image, and a
/// file's rotated part (faces planar only within rounding) from its plane solid, where those
/// stand (DecomposeOptions::from_exact_solid, prefer_exact_solid).
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
