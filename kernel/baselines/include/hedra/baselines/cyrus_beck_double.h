// The plain-double Cyrus–Beck loop, kept as the speed–accuracy baseline of the exact clipper.
#pragma once

#include <optional>
#include <utility>

#include "hedra/core/body.h"

namespace hedra {

/// The course's algorithm exactly as written (docs/algorithms.md §4, steps 3–6), in plain double on
/// body-matrix columns: Wn = N·P1 + d, Dn = N·(P2 − P1), comparisons with 0 in floating point.
/// The "plain double" variant of the speed–accuracy benchmark and a reference in tests;
/// its decisions are wrong near degenerate configurations (see docs/clipping.md).
/// Returns (t_low, t_up) or nullopt. Cost O(columns).
std::optional<std::pair<double, double>> cyrus_beck_double(const BodyMatrix& matrix, const Vec3& p1,
                                                           const Vec3& p2);

}  // namespace hedra
