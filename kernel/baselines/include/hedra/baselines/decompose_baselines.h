// Decompositions kept only to be compared against the exact one (bench/, docs/decomposition.md).
#pragma once

#include "hedra/decompose/decompose.h"

namespace hedra {

/// The same algorithm in plain floating point: a point is on a plane when its double distance
/// is within epsilon · body.scale(), cut points are rounded. No symbolic incidence. Kept for
/// the speed–accuracy comparison: it is allowed to fail, and reports how.
/// \throw DecompositionFailed, DecompositionCancelled, InvalidInput (max pieces).
Decomposition decompose_float(const Body& body, double epsilon,
                              const DecomposeOptions& options = {});

/// CGAL's convex_decomposition_3 on a Nef polyhedron (exact kernel), for comparison: the
/// time includes building the Nef polyhedron from the body. Pieces rounded to double; slivers
/// that collapse when rounded are counted in degenerate_pieces.
Decomposition decompose_cgal(const Body& body);

}  // namespace hedra
