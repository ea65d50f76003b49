// Outcodes of the course's two basic clippers (docs/algorithms.md §3.1–3.2): the rectangular box
// (6 bits) and the truncated viewing pyramid, with the course's fix for points beyond the
// centre of projection.
#pragma once

#include <cstdint>

#include "hedra/clip/convex_clipper.h"

namespace hedra {

/// Outcode bits, in the course's order T1 … T6.
enum OutcodeBit : std::uint8_t {
  kOutLeft = 1,    // T1: x < x_left     (frustum: f_l < 0)
  kOutRight = 2,   // T2: x > x_right    (frustum: f_r > 0)
  kOutBottom = 4,  // T3: y < y_bottom   (frustum: f_b < 0)
  kOutTop = 8,     // T4: y > y_top      (frustum: f_t > 0)
  kOutNear = 16,   // T5: z > z_near
  kOutFar = 32,    // T6: z < z_far
  kOutSides = 15,  // T1 … T4
};

/// The course's box clipper: x_left ≤ x ≤ x_right, y_bottom ≤ y ≤ y_top, z_far ≤ z ≤ z_near
/// (the viewer looks towards −z, so the near plane has the larger z).
struct ClipBox {
  double x_left = -1, x_right = 1, y_bottom = -1, y_top = 1, z_near = 1, z_far = -1;

  /// The box [min, max]: z_far = min.z, z_near = max.z.
  static ClipBox from_bounds(const Vec3& min, const Vec3& max);
  /// \throw InvalidInput unless every bound is finite and x_left < x_right,
  ///   y_bottom < y_top, z_far < z_near.
  void validate() const;
};

/// The course's truncated viewing pyramid: centre of projection (0, 0, z_cp) on the z axis, the
/// far face x_left … x_right × y_bottom … y_top at z = z_far, cut by the near plane z = z_near,
/// z_far < z_near < z_cp. Its side planes pass through the centre of projection and the far
/// face's edges; the course's test functions are
///   f_r = x − z·α1 − α2, α1 = x_right/(z_far − z_cp), α2 = −α1·z_cp (and f_l with x_left),
///   f_t = y − z·γ1 − γ2, γ1 = y_top/(z_far − z_cp),   γ2 = −γ1·z_cp (and f_b with y_bottom).
struct ViewFrustum {
  double x_left = -1, x_right = 1, y_bottom = -1, y_top = 1, z_near = 0, z_far = -1, z_cp = 4;

  /// \throw InvalidInput unless finite, x_left < x_right, y_bottom < y_top and
  ///   z_far < z_near < z_cp.
  void validate() const;
};

/// Box outcode (T1 … T6). Exact: comparisons of doubles. Cost O(1).
std::uint8_t outcode(const ClipBox& box, const Vec3& p);

/// The course's frustum outcode: T1 … T4 from the signs of f_l, f_r, f_b, f_t, T5 z > z_near,
/// T6 z < z_far, and for points beyond the centre of projection (z > z_cp) the first four bits
/// inverted, as the course prescribes: there the side planes have crossed at the centre, and
/// the inverted bits say on which side the point's image through the centre falls (a point
/// behind the viewer on the left projects to the right). T5 is always set there, so such a
/// point is never visible. The signs are exact: each test function is evaluated as the exact
/// side of its plane (through the centre and the far face's edge), not through rounded α's.
/// Cost O(1).
std::uint8_t outcode(const ViewFrustum& frustum, const Vec3& p);

/// The frustum outcode without the inversion: bit i set when p lies strictly outside the i-th
/// face's half-space. Equal to outcode() for z ≤ z_cp. Cost O(1).
std::uint8_t halfspace_outcode(const ViewFrustum& frustum, const Vec3& p);

/// The course's test functions evaluated literally in double (f_l, f_r, f_b, f_t).
struct FrustumTests {
  double left, right, bottom, top;
};
FrustumTests frustum_tests(const ViewFrustum& frustum, const Vec3& p);

/// Code sums both 0: the segment is fully visible.
inline bool trivially_visible(std::uint8_t a, std::uint8_t b) { return (a | b) == 0; }
/// Logical product non-zero: the segment is fully invisible (valid for half-space codes).
inline bool trivially_invisible(std::uint8_t a, std::uint8_t b) { return (a & b) != 0; }

/// Trivial rejection of segment ab by the frustum. The logical product of the course's codes
/// is only valid when both ends lie on the same side of z = z_cp: for a segment that crosses
/// that plane the inverted bits of one end describe the mirrored pyramid, and their product
/// can reject a segment that does pass through the frustum. Uses the half-space codes, which
/// are valid everywhere (and equal the course's codes where the course's are valid).
bool trivially_invisible(const ViewFrustum& frustum, const Vec3& a, const Vec3& b);

/// The box's six planes as a clipper, in bit order (left, right, bottom, top, near, far).
ConvexClipper box_clipper(const ClipBox& box);
/// The frustum's six planes as a clipper, in bit order; the side planes exactly through the
/// centre of projection and two far corners each.
ConvexClipper frustum_clipper(const ViewFrustum& frustum);

}  // namespace hedra
