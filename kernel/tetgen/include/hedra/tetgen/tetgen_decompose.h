// Decomposition into tetrahedra through TetGen (libtet). TetGen is licensed AGPL-3.0: this
// lives in its own target, hedra::tetgen (like libigl's copyleft::tetgen), and a program
// linked with it is covered by the AGPL-3.0.
#pragma once

#include "hedra/decompose/decompose.h"

namespace hedra::tetgen {

/// Constrained Delaunay tetrahedralization of the body's boundary (TetGen switches "pQ": a
/// piecewise linear complex, no quality refinement), one convex piece per tetrahedron.
/// \throw InvalidInput when TetGen rejects the input (it reports self-intersections).
Decomposition decompose(const Body& body);

}  // namespace hedra::tetgen
