// Midpoint subdivision clipping with precision ε (docs/algorithms.md §3.4), against the course's
// box and frustum through their outcodes, and against any convex clipper through exact sides.
//
// The course's procedure: trivially visible → keep; trivially invisible → drop; otherwise, for
// each end in turn, if it is visible it is an end of the result, else bisect
// Pm = (P1 + P2)/2, keeping the half that is not trivially invisible, until |P1 − P2| ≤ ε; then
// swap the ends. The course leaves open the case where neither half is trivially invisible
// and the midpoint is not visible (a segment passing a corner outside, or a visible part on
// either side). hedra first looks for any visible point, by subdividing and dropping halves
// that are trivially invisible, down to pieces of length ε; from that point every bisection
// towards an end has one visible and one invisible end, so keeping the half with a change of
// visibility is always right. Result, with P the exact visible part:
//  - both returned ends are visible points (decided exactly), each within ε of the end of P it
//    stands for (plus the rounding of the midpoints, ~u·|P| per bisection);
//  - a visible part shorter than about ε can be missed (nullopt).
#pragma once

#include <optional>

#include "hedra/clip/convex_clipper.h"
#include "hedra/baselines/outcodes.h"

namespace hedra {

/// The visible part found by midpoint subdivision: its end points and their parameters on
/// P(t) = P1 + (P2 − P1)·t (each midpoint halves a parameter interval, exactly).
struct MidpointClip {
  Vec3 start, end;
  double t_start = 0, t_end = 1;
  int bisections = 0;  // midpoints evaluated (the cost)
};

/// Against the box, through its 6-bit outcodes. \throw InvalidInput unless eps > 0 and
/// finite, or for an invalid box. Cost O(log(|P2 − P1| / ε)) outcodes.
std::optional<MidpointClip> midpoint_clip(const ClipBox& box, const Vec3& p1, const Vec3& p2,
                                          double eps);

/// Against the frustum: visibility from the course's outcode (0 iff inside, exact); trivial
/// rejection from the half-space codes (see trivially_invisible(ViewFrustum, …)).
std::optional<MidpointClip> midpoint_clip(const ViewFrustum& frustum, const Vec3& p1,
                                          const Vec3& p2, double eps);

/// Against any convex clipper: a point is visible when no plane is Negative at it; a part is
/// trivially invisible when one plane is Negative at both its ends (exact sides).
/// Cost O(planes · log(|P2 − P1| / ε)).
std::optional<MidpointClip> midpoint_clip(const ConvexClipper& clipper, const Vec3& p1,
                                          const Vec3& p2, double eps);

}  // namespace hedra
