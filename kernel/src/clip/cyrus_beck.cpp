#include "hedra/clip/cyrus_beck.h"

#include <CGAL/Gmpq.h>
#include <CGAL/Mpzf.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>

#include "core/exact_plane.h"
#include "hedra/core/error.h"
#include "hedra/core/tolerance.h"

namespace hedra {
namespace {

void check_point(const Vec3& p) {
  if (p.allFinite() && p.cwiseAbs().maxCoeff() <= kMaxAbsCoordinate) return;
  char buf[160];
  std::snprintf(buf, sizeof buf, "segment end point (%.17g, %.17g, %.17g) %s", p.x(), p.y(), p.z(),
                p.allFinite() ? "is beyond ±1e101" : "is not finite");
  throw InvalidInput(buf);
}

// One side of the visible part while the planes are scanned: a SegmentEnd and the index of
// its plane in the clipper (−1 for an exact end of the segment).
struct Bound {
  SegmentEnd end;
  int plane;
};

Bound bound_at(double t) { return {{t, 0, nullptr}, -1}; }

// Sign of a − b for two bounds of the same segment.
Sign compare_bounds(const Bound& a, const Bound& b, const Vec3& p1, const Vec3& p2) {
  return compare_ends(a.end, b.end, p1, p2);
}

const ExactPlane* plane_of(std::span<const ConvexClipper> pieces, const ClipEnd& end) {
  return end.plane < 0 ? nullptr : &pieces[static_cast<size_t>(end.piece)].plane(end.plane);
}

Bound bound_of(std::span<const ConvexClipper> pieces, const ClipEnd& end, const Vec3& p1,
               const Vec3& p2) {
  if (end.plane < 0) return bound_at(end.t);
  const ExactPlane* f = plane_of(pieces, end);
  const Crossing x = crossing(*f, p1, p2);
  return {{x.t, x.error, f}, end.plane};
}

using Q = CGAL::Mpzf;

// f(p) exactly, from the plane's exact coefficients (as the predicates
// evaluate it).
Q exact_value(const ExactPlane& f, const Vec3& p) {
  const std::array<Q, 4> c = internal::exact_coefficients(f);
  return c[0] * Q(p.x()) + c[1] * Q(p.y()) + c[2] * Q(p.z()) + c[3];
}

// Whether c is num/den (den > 0) rounded to nearest, ties to even: num/den lies strictly
// between the midpoints of c and its neighbours, or on one with c's last bit 0. Exact.
bool rounds_to(const Q& num, const Q& den, double c) {
  const double inf = std::numeric_limits<double>::infinity();
  const double lo = std::nextafter(c, -inf), hi = std::nextafter(c, inf);
  if (!std::isfinite(lo) || !std::isfinite(hi)) return false;
  const Q two_num = Q(2) * num;
  const CGAL::Sign below = CGAL::sign(two_num - (Q(lo) + Q(c)) * den);  // X − (lo + c)/2
  const CGAL::Sign above = CGAL::sign(two_num - (Q(c) + Q(hi)) * den);  // X − (c + hi)/2
  if (below == CGAL::NEGATIVE || above == CGAL::POSITIVE) return false;
  if (below == CGAL::POSITIVE && above == CGAL::NEGATIVE) return true;
  return (std::bit_cast<std::uint64_t>(c) & 1) == 0;  // a tie: c must be the even neighbour
}

// num/den (den > 0) rounded to nearest: the estimate when it is right, else the rational
// quotient truncated toward zero (mpq_get_d) or its neighbour away from zero, one of which is
// the nearest.
double round_quotient(const Q& num, const Q& den, double estimate) {
  if (std::isfinite(estimate) && rounds_to(num, den, estimate)) return estimate;
  const double truncated = (CGAL::Gmpq(num) / CGAL::Gmpq(den)).to_double();
  if (rounds_to(num, den, truncated)) return truncated;
  const double inf = std::numeric_limits<double>::infinity();
  return std::nextafter(truncated, CGAL::sign(num) == CGAL::NEGATIVE ? -inf : inf);
}

}  // namespace

Vec3 crossing_point(const ExactPlane& f, const Vec3& p, const Vec3& q) {
  Q fp = exact_value(f, p), fq = exact_value(f, q);
  Q den = fp - fq;
  HEDRA_ASSERT(CGAL::sign(den) != CGAL::ZERO, "crossing_point: the line does not cross the plane");
  if (CGAL::sign(den) == CGAL::NEGATIVE) {  // keep den > 0
    fp = Q(0) - fp;
    fq = Q(0) - fq;
    den = Q(0) - den;
  }
  // The estimate: P(t) with t = f(p)/(f(p) − f(q)) in double, right almost always.
  const double w = f.value(p), e = f.value(q);
  const double t = w / (w - e);
  Vec3 x;
  for (int i = 0; i < 3; ++i)
    x[i] = round_quotient(fp * Q(q[i]) - fq * Q(p[i]), den, p[i] + (q[i] - p[i]) * t);
  return x;
}

Crossing crossing(const ExactPlane& f, const Vec3& p1, const Vec3& p2) {
  return crossing_from_values(f.value(p1), f.value(p2), f.error_bound(p1.cwiseAbs().maxCoeff()),
                              f.error_bound(p2.cwiseAbs().maxCoeff()));
}

Sign compare_ends(const SegmentEnd& a, const SegmentEnd& b, const Vec3& p1, const Vec3& p2) {
  if (!a.plane && !b.plane)
    return a.t < b.t ? Sign::Negative : (a.t > b.t ? Sign::Positive : Sign::Zero);
  // A crossing lies strictly inside (0, 1): its plane separates the end points strictly.
  if (!a.plane) return a.t == 0 ? Sign::Negative : Sign::Positive;
  if (!b.plane) return b.t == 0 ? Sign::Positive : Sign::Negative;
  if (a.plane == b.plane) return Sign::Zero;
  if (a.t - a.error > b.t + b.error) return Sign::Positive;
  if (a.t + a.error < b.t - b.error) return Sign::Negative;
  return compare_crossings(*a.plane, *b.plane, p1, p2);
}

std::optional<ClipPart> clip_segment(const ConvexClipper& clipper, const Vec3& p1, const Vec3& p2) {
  check_point(p1);
  check_point(p2);
  const double m1 = p1.cwiseAbs().maxCoeff(), m2 = p2.cwiseAbs().maxCoeff();
  // Step 4: t_low = 0, t_up = 1 (exact ends of the segment).
  Bound low = bound_at(0), up = bound_at(1);
  for (int i = 0; i < clipper.plane_count(); ++i) {
    const ExactPlane& f = clipper.plane(i);
    // Step 5: Wn = f(P1) and f(P2) = Wn + Dn, their signs exact.
    const double w = f.value(p1), e = f.value(p2);
    const double bw = f.error_bound(m1), be = f.error_bound(m2);
    const Sign s1 = side_of_plane(f, p1, w, bw), s2 = side_of_plane(f, p2, e, be);
    // Both ends strictly outside this plane: "Dn = 0 and Wn < 0", or "t > 1" / "t < 0".
    if (s1 == Sign::Negative && s2 == Sign::Negative) return std::nullopt;
    // Both ends inside or on the plane (a point, parallel inside, in the face plane, or a
    // crossing outside [0, 1] on the visible side): the plane does not bound.
    if (s1 != Sign::Negative && s2 != Sign::Negative) continue;
    if (s1 == Sign::Negative) {
      // Dn > 0: a lower bound. P2 on the plane gives t = 1 exactly.
      if (s2 == Sign::Zero) {
        low = bound_at(1);
        continue;
      }
      if (low.plane < 0 && low.end.t == 1) continue;  // nothing exceeds an exact 1
      Crossing x = crossing_from_values(w, e, bw, be);
      if (!(x.t == x.t)) x = {0.5, 0.5};  // w = e = 0 in double: t unknown within [0, 1]
      const Bound candidate{{x.t, x.error, &f}, i};
      if (low.plane < 0 || compare_bounds(candidate, low, p1, p2) == Sign::Positive)
        low = candidate;  // ties keep the first plane
    } else {
      // Dn < 0: an upper bound. P1 on the plane gives t = 0 exactly.
      if (s1 == Sign::Zero) {
        up = bound_at(0);
        continue;
      }
      if (up.plane < 0 && up.end.t == 0) continue;
      Crossing x = crossing_from_values(w, e, bw, be);
      if (!(x.t == x.t)) x = {0.5, 0.5};
      const Bound candidate{{x.t, x.error, &f}, i};
      if (up.plane < 0 || compare_bounds(candidate, up, p1, p2) == Sign::Negative) up = candidate;
    }
  }
  // Step 6: visible iff t_low ≤ t_up, decided exactly.
  const Sign order = compare_bounds(low, up, p1, p2);
  if (order == Sign::Positive) return std::nullopt;
  ClipPart part;
  part.start = {low.end.t, low.plane, 0};
  part.end = {up.end.t, up.plane, 0};
  part.point = order == Sign::Zero || p1 == p2;
  // Rounding may invert ends that are equal or within their error bounds of each other.
  if (order == Sign::Zero || part.end.t < part.start.t) part.end.t = part.start.t;
  return part;
}

std::optional<SegmentPart> clip_segment_open(const ConvexClipper& clipper, const Vec3& p1,
                                             const Vec3& p2) {
  return clip_segment_open(std::span<const ExactPlane>(clipper.planes()), p1, p2);
}

std::optional<SegmentPart> intersect_parts(const SegmentPart& a, const SegmentPart& b, const Vec3& p1,
                                           const Vec3& p2) {
  SegmentPart out;
  out.lo = compare_ends(a.lo, b.lo, p1, p2) == Sign::Negative ? b.lo : a.lo;
  out.hi = compare_ends(a.hi, b.hi, p1, p2) == Sign::Negative ? a.hi : b.hi;
  if (compare_ends(out.lo, out.hi, p1, p2) != Sign::Negative) return std::nullopt;
  if (out.lo.plane && out.hi.plane && out.hi.t < out.lo.t) out.hi.t = out.lo.t;  // as clip_segment_open
  return out;
}

std::optional<SegmentPart> clip_segment_open(std::span<const ExactPlane> planes, const Vec3& p1,
                                             const Vec3& p2) {
  const double m1 = p1.cwiseAbs().maxCoeff(), m2 = p2.cwiseAbs().maxCoeff();
  SegmentEnd lo{0, 0, nullptr}, hi{1, 0, nullptr};
  for (const ExactPlane& f : planes) {
    const double w = f.value(p1), e = f.value(p2);
    const double bw = f.error_bound(m1), be = f.error_bound(m2);
    const Sign s1 = side_of_plane(f, p1, w, bw), s2 = side_of_plane(f, p2, e, be);
    if (s1 != Sign::Positive && s2 != Sign::Positive) return std::nullopt;
    if (s1 == Sign::Positive && s2 == Sign::Positive) continue;
    if (s1 == Sign::Zero || s2 == Sign::Zero) continue;  // bounds at t = 0 or 1 exactly
    Crossing x = crossing_from_values(w, e, bw, be);
    if (!(x.t == x.t)) x = {0.5, 0.5};  // both values 0 in double: t within [0, 1]
    const SegmentEnd candidate{x.t, x.error, &f};
    if (s1 == Sign::Negative) {
      if (!lo.plane || compare_ends(candidate, lo, p1, p2) == Sign::Positive) lo = candidate;
    } else if (!hi.plane || compare_ends(candidate, hi, p1, p2) == Sign::Negative) {
      hi = candidate;
    }
  }
  if (compare_ends(lo, hi, p1, p2) != Sign::Negative) return std::nullopt;
  if (lo.plane && hi.plane && hi.t < lo.t) hi.t = lo.t;  // rounding of ends within their bounds
  return SegmentPart{lo, hi};
}

void merge_parts(std::vector<SegmentPart>& parts, const Vec3& p1, const Vec3& p2) {
  if (parts.size() < 2) return;
  std::sort(parts.begin(), parts.end(), [&](const SegmentPart& a, const SegmentPart& b) {
    return compare_ends(a.lo, b.lo, p1, p2) == Sign::Negative;
  });
  size_t last = 0;
  for (size_t i = 1; i < parts.size(); ++i) {
    SegmentPart& back = parts[last];
    if (compare_ends(parts[i].lo, back.hi, p1, p2) != Sign::Positive) {
      if (compare_ends(parts[i].hi, back.hi, p1, p2) == Sign::Positive) back.hi = parts[i].hi;
    } else {
      parts[++last] = parts[i];
    }
  }
  parts.resize(last + 1);
}

Sign compare_ends(std::span<const ConvexClipper> pieces, const ClipEnd& a, const ClipEnd& b,
                  const Vec3& p1, const Vec3& p2) {
  if (a.plane >= 0 && b.plane >= 0 && a.piece == b.piece && a.plane == b.plane) return Sign::Zero;
  return compare_bounds(bound_of(pieces, a, p1, p2), bound_of(pieces, b, p1, p2), p1, p2);
}

std::vector<ClipPart> clip_segment(std::span<const ConvexClipper> pieces, const Vec3& p1,
                                   const Vec3& p2) {
  std::vector<ClipPart> parts;
  for (size_t k = 0; k < pieces.size(); ++k) {
    if (std::optional<ClipPart> part = clip_segment(pieces[k], p1, p2)) {
      part->start.piece = part->end.piece = static_cast<int>(k);
      parts.push_back(*part);
    }
  }
  if (parts.size() < 2) return parts;
  const auto cmp = [&](const ClipEnd& a, const ClipEnd& b) {
    return compare_ends(pieces, a, b, p1, p2);
  };
  // Order by start (exact), then sweep: a part that starts at or before the current end
  // (exactly) continues the current part.
  std::stable_sort(parts.begin(), parts.end(), [&](const ClipPart& a, const ClipPart& b) {
    return cmp(a.start, b.start) == Sign::Negative;
  });
  std::vector<ClipPart> merged;
  for (const ClipPart& part : parts) {
    if (!merged.empty() && cmp(part.start, merged.back().end) != Sign::Positive) {
      ClipPart& back = merged.back();
      if (cmp(part.end, back.end) == Sign::Positive) back.end = part.end;
      back.point = p1 == p2 || cmp(back.start, back.end) == Sign::Zero;
      if (back.end.t < back.start.t) back.end.t = back.start.t;
    } else {
      merged.push_back(part);
    }
  }
  return merged;
}

std::vector<ClipPart> clip_segment_outside(std::span<const ConvexClipper> pieces, const Vec3& p1,
                                           const Vec3& p2) {
  const std::vector<ClipPart> inside = clip_segment(pieces, p1, p2);
  const ClipEnd first{0, -1, 0}, last{1, -1, 0};
  if (p1 == p2) {
    // A point segment is a point: outside whole, or not at all.
    if (inside.empty()) return {ClipPart{first, last, true}};
    return {};
  }
  std::vector<ClipPart> outside;
  ClipEnd from = first;
  for (const ClipPart& part : inside) {
    if (part.point) continue;  // removing a point changes nothing in the closure
    if (compare_ends(pieces, from, part.start, p1, p2) == Sign::Negative)
      outside.push_back({from, part.start, false});
    from = part.end;
  }
  if (compare_ends(pieces, from, last, p1, p2) == Sign::Negative)
    outside.push_back({from, last, false});
  return outside;
}

std::vector<ClipPart> clip_segment_outside(const ConvexClipper& clipper, const Vec3& p1,
                                           const Vec3& p2) {
  return clip_segment_outside(std::span<const ConvexClipper>(&clipper, 1), p1, p2);
}

Vec3 end_point(std::span<const ConvexClipper> pieces, const ClipEnd& end, const Vec3& p1,
               const Vec3& p2) {
  if (end.plane < 0) return end.t == 0 ? p1 : (end.t == 1 ? p2 : point_at(p1, p2, end.t));
  return crossing_point(*plane_of(pieces, end), p1, p2);
}

Vec3 point_at(const Vec3& p1, const Vec3& p2, double t) {
  if (t == 0) return p1;
  if (t == 1) return p2;
  return Vec3(p1.x() + (p2.x() - p1.x()) * t, p1.y() + (p2.y() - p1.y()) * t,
              p1.z() + (p2.z() - p1.z()) * t);
}


}  // namespace hedra
