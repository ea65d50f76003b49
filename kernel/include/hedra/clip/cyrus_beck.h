// Cyrus–Beck clipping of segments against convex clippers (docs/algorithms.md §4), exterior
// clipping (erasing), and clipping against a non-convex clipper given by convex pieces.
//
// Exactness. Every decision is exact: the side of each end point with respect to each plane
// (side_of_plane on ExactPlane), which plane bounds the visible part from below and from above
// (compare_crossings), and whether anything is visible, a single point, or a proper part. Only
// the parameters t are rounded. For a crossing of plane F by P(t) = P1 + (P2 − P1)·t, with
// w = F.value(P1), e = F.value(P2), δw = F.error_bound(max|P1_i|), δe likewise for P2,
// t is computed as w·(1/(w − e)) and
//     |t − t_exact| ≤ (δw + δe) / |w − e| + 3u            (u = 2^-53),
// which crossing() returns. For a plane with a unit normal, |w − e| = L·|cos θ| (L the
// segment's length, θ the angle between the segment and the normal) and δ ≈ 4u·(|n·P| + |k|),
// so the end point moves along the segment by at most about (δw + δe)/|cos θ| + 3u·L: small
// except for segments nearly parallel to a face, as for any construction of an intersection.
#pragma once

#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "hedra/clip/convex_clipper.h"

namespace hedra {

/// One end of a clipped part of the segment P(t) = P1 + (P2 − P1)·t.
struct ClipEnd {
  double t = 0;    // exactly 0 or 1 when plane < 0, else the crossing rounded (bound above)
  int plane = -1;  // plane of `piece` whose crossing is this end; −1: an end of the segment
  int piece = 0;   // convex piece of the clipper that `plane` belongs to
};

/// A closed part [start, end] of a segment, start.t ≤ end.t.
struct ClipPart {
  ClipEnd start, end;
  bool point = false;  // exact: the part is a single point (the segment only touches)
};

/// A crossing parameter and its error bound (see the header comment).
struct Crossing {
  double t = 0;
  double error = 0;
};

/// Factors of the crossing bound: the relative part covers the roundings of computing the bound
/// itself, the absolute part the 3 roundings of t (≤ 3u for t in [0, 1]) and the roundings of
/// t ± error in the comparisons that use it.
constexpr double kCrossingInflation = 1 + 8 * (0.5 * std::numeric_limits<double>::epsilon());
constexpr double kCrossingAbsolute = 6 * (0.5 * std::numeric_limits<double>::epsilon());

/// The crossing from the plane values w = f.value(p1), e = f.value(p2) and their bounds,
/// clamped to [0, 1]. Inline, so that the batch clipper computes the identical bits.
inline Crossing crossing_from_values(double w, double e, double bound_w, double bound_e) {
  const double r = 1.0 / (w - e);
  double t = w * r;
  t = t > 1 ? 1.0 : t;
  t = t < 0 ? 0.0 : t;
  return {t, (bound_w + bound_e) * std::abs(r) * kCrossingInflation + kCrossingAbsolute};
}

/// Parameter of the point where segment p1p2 crosses plane f, t = w·(1/(w − e)) clamped to
/// [0, 1], with its error bound. Meaningful when f(p1) and f(p2) have opposite exact signs.
/// Cost O(1).
Crossing crossing(const ExactPlane& f, const Vec3& p1, const Vec3& p2);

/// Cyrus–Beck (docs/algorithms.md §4): the part of segment p1p2 inside the closed convex clipper,
/// or nullopt. The course's step 5 with exact signs: Wn = f(P1), Dn = f(P2) − f(P1), so
/// "Dn = 0, Wn < 0" and "t > 1" / "t < 0" are "both ends strictly outside one plane"; a plane that
/// both ends are on or inside does not bound; the others give t = −Wn/Dn, lower bounds where
/// Dn > 0 and upper bounds where Dn < 0, of which the exact maximum and minimum count.
/// Degenerate inputs are exact: a point segment (inside or not), a segment parallel to a face
/// (inside, outside, or in its plane: kept, since the clipper is closed), through a vertex or
/// along an edge (kept, or a single point when it only touches).
/// \throw InvalidInput if a coordinate is not finite or exceeds kMaxAbsCoordinate.
/// Cost O(planes), plus exact arithmetic only for near-degenerate configurations.
std::optional<ClipPart> clip_segment(const ConvexClipper& clipper, const Vec3& p1, const Vec3& p2);

/// Exterior clipping (erasing): the closure of the parts of p1p2 outside the clipper, in order:
/// none, one or two parts. A segment that only touches the clipper comes back whole; one lying
/// in a face plane inside the face is inside, so nothing comes back.
/// \throw InvalidInput as clip_segment. Cost O(planes).
std::vector<ClipPart> clip_segment_outside(const ConvexClipper& clipper, const Vec3& p1,
                                           const Vec3& p2);

/// Non-convex clipper given as convex pieces (their union; they may touch or overlap): the
/// per-piece parts merged in order along the segment. Parts that touch or overlap become one
/// part, decided exactly, so a segment crossing a face shared by two pieces gives one part (no
/// gap, no duplicate) whenever the pieces' shared face planes coincide exactly, as they do for
/// an exact decomposition. Single points stay only where they touch no other part.
/// \throw InvalidInput as clip_segment. Cost O(P·planes + k log k) for k per-piece parts.
std::vector<ClipPart> clip_segment(std::span<const ConvexClipper> pieces, const Vec3& p1,
                                   const Vec3& p2);

/// Exterior clipping against the union of the pieces: the closure of the segment minus their
/// union, as the gaps between the merged inside parts (single points removed).
std::vector<ClipPart> clip_segment_outside(std::span<const ConvexClipper> pieces, const Vec3& p1,
                                           const Vec3& p2);

/// The point X where the line through p and q crosses plane f, each coordinate the exact value
/// X_i = (f(p)·q_i − f(q)·p_i) / (f(p) − f(q)) rounded to nearest (ties to even) once: never
/// built from a rounded parameter, so the crossing of a segment far longer than its distance
/// from the ends (−1e70 … 1e70 against a unit cube) is still the exact point rounded.
/// \pre f(p) ≠ f(q) exactly. Cost O(1): exact products of doubles (CGAL::Mpzf); a rational
/// division only when the double estimate is not the correctly rounded value.
Vec3 crossing_point(const ExactPlane& f, const Vec3& p, const Vec3& q);

/// The point of an end of a part of segment p1p2: P1 or P2 itself for an end of the segment,
/// else the exact crossing of the segment with the end's plane rounded once per coordinate
/// (crossing_point), not P(t) of the rounded t: so the returned part is the exact part
/// rounded, however long the segment (−1e70 … 1e70 against the unit cube gives −1 … 1).
/// Cost O(1), exact arithmetic for a crossing.
Vec3 end_point(std::span<const ConvexClipper> pieces, const ClipEnd& end, const Vec3& p1,
               const Vec3& p2);
/// end_point for the parts of one convex clipper (piece 0).
inline Vec3 end_point(const ConvexClipper& clipper, const ClipEnd& end, const Vec3& p1,
                      const Vec3& p2) {
  return end_point(std::span<const ConvexClipper>(&clipper, 1), end, p1, p2);
}

/// Exact order of two ends of parts of the same segment (pieces as in the parts):
/// sign of a.t_exact − b.t_exact. Cost O(1).
Sign compare_ends(std::span<const ConvexClipper> pieces, const ClipEnd& a, const ClipEnd& b,
                  const Vec3& p1, const Vec3& p2);

// ---- The open clipper (occlusion volumes: a point on the boundary is not hidden) ----

/// An end of a part of segment p1p2 given by the plane it lies on: an exact end of the segment
/// (plane == nullptr, t exactly 0 or 1) or the crossing of *plane, t rounded with its error
/// bound (crossing()). The plane belongs to the clipper the part came from.
struct SegmentEnd {
  double t = 0;
  double error = 0;
  const ExactPlane* plane = nullptr;
};

/// A part [lo, hi] of a segment, lo before hi (exactly).
struct SegmentPart {
  SegmentEnd lo, hi;
};

/// Exact order of two ends of parts of the same segment p1p2: the sign of a.t − b.t for the
/// exact parameters. A crossing end lies strictly inside (0, 1). Cost O(1), exact arithmetic
/// only when the rounded parameters are within their error bounds of each other.
Sign compare_ends(const SegmentEnd& a, const SegmentEnd& b, const Vec3& p1, const Vec3& p2);

/// Cyrus–Beck for the open clipper: the part of segment p1p2 strictly inside every plane
/// (an open interval of t), or nullopt. A plane that both ends are on or outside empties it (a
/// segment in a bounding plane is not inside); a plane with one end on it and the other inside
/// bounds at that exact end. No check of the coordinates (callers pass body vertices).
/// Cost O(planes), exact arithmetic only for near-degenerate configurations.
std::optional<SegmentPart> clip_segment_open(const ConvexClipper& clipper, const Vec3& p1,
                                             const Vec3& p2);
/// The same for planes held by the caller (the ends point into `planes`; no plane: the whole
/// segment).
std::optional<SegmentPart> clip_segment_open(std::span<const ExactPlane> planes, const Vec3& p1,
                                             const Vec3& p2);
/// The part of p1p2 in both parts (the intersection of two open intervals), or nullopt.
/// Cost O(1) exact comparisons.
std::optional<SegmentPart> intersect_parts(const SegmentPart& a, const SegmentPart& b, const Vec3& p1,
                                           const Vec3& p2);

/// Sorts parts of one segment by their start and joins those that overlap or touch, exactly.
/// In place. Cost O(k log k) comparisons.
void merge_parts(std::vector<SegmentPart>& parts, const Vec3& p1, const Vec3& p2);

/// P(t) = P1 + (P2 − P1)·t in double, exactly P1 at t = 0 and P2 at t = 1. For a part's end
/// use end_point: a rounded t loses the point on long segments.
Vec3 point_at(const Vec3& p1, const Vec3& p2, double t);


}  // namespace hedra
