// Internal: the exact coefficients of an ExactPlane (hedra/core/predicates.h), for code that
// computes with them in multiprecision (pencil planes, the exact faces of decomposition pieces,
// junction lines in homogeneous arithmetic, Cyrus–Beck's exact crossings).
#pragma once

#include <CGAL/Mpzf.h>

#include <array>
#include <utility>

#include "hedra/core/predicates.h"

namespace hedra::internal {

/// f(p) = c[0]·x + c[1]·y + c[2]·z + c[3], exactly; `interval[i]` encloses c[i] / 2^s for one
/// power of two s (the plane's double form, n and k, is that scaled function rounded), for the
/// interval stage of the filtered predicates.
struct ExactCoefficients {
  std::array<CGAL::Mpzf, 4> c;
  std::array<std::pair<double, double>, 4> interval{};
};

/// The exact affine function of any ExactPlane (its defining form, negation applied):
/// f(p) = c[0]·x + c[1]·y + c[2]·z + c[3]. Cost O(1) multiprecision operations.
std::array<CGAL::Mpzf, 4> exact_coefficients(const ExactPlane& f);

/// An ExactPlane from four exact coefficients (ExactPlane::from_exact).
/// \throw InvalidInput if the normal is zero or the offset too large for the normal.
ExactPlane plane_from_exact(const std::array<CGAL::Mpzf, 4>& c);

}  // namespace hedra::internal
