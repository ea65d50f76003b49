// Internal: the sign of a polynomial in doubles, interval arithmetic first, exact after.
#pragma once

#include <CGAL/Interval_nt.h>
#include <CGAL/Mpzf.h>

#include "hedra/core/predicates.h"

namespace hedra::internal {

inline Sign to_sign(CGAL::Sign s) { return static_cast<Sign>(static_cast<int>(s)); }

/// Sign of `expr(T(0))` for T = interval (under upward rounding) and, when the interval
/// contains zero without being zero, for T = CGAL::Mpzf, exactly (the expression must be a
/// polynomial in doubles). Cost: one interval evaluation, rarely one exact one.
template <class Expr>
Sign filtered_sign(const Expr& expr) {
  using Interval = CGAL::Interval_nt_advanced;
  {
    CGAL::Protect_FPU_rounding<true> guard;
    const Interval v = expr(Interval(0));
    if (v.inf() > 0) return Sign::Positive;
    if (v.sup() < 0) return Sign::Negative;
    if (v.inf() == 0 && v.sup() == 0) return Sign::Zero;
  }
  return to_sign(CGAL::sign(expr(CGAL::Mpzf(0))));
}

}  // namespace hedra::internal
