#include "hedra/baselines/box_clip.h"

#include <array>
#include <bit>

namespace hedra {
namespace {

// Axis and coordinate of the plane of each outcode bit (T1 … T6).
struct BitPlane {
  int axis;
  double value;
};

std::array<BitPlane, 6> bit_planes(const ClipBox& b) {
  return {
      {{0, b.x_left}, {0, b.x_right}, {1, b.y_bottom}, {1, b.y_top}, {2, b.z_near}, {2, b.z_far}}};
}

}  // namespace

std::optional<std::pair<Vec3, Vec3>> cohen_sutherland(const ClipBox& box, const Vec3& p1,
                                                      const Vec3& p2) {
  const std::array<BitPlane, 6> planes = bit_planes(box);
  Vec3 end[2] = {p1, p2};
  std::uint8_t code[2] = {outcode(box, p1), outcode(box, p2)};
  std::uint8_t moved[2] = {0, 0};  // bits whose plane each end has been moved onto
  for (;;) {
    const std::uint8_t c0 = code[0] & ~moved[0], c1 = code[1] & ~moved[1];
    if (trivially_visible(c0, c1)) return std::make_pair(end[0], end[1]);
    if (trivially_invisible(c0, c1)) return std::nullopt;
    // An end that is outside, and the plane of its lowest set bit.
    const int i = c0 ? 0 : 1;
    const std::uint8_t c = i == 0 ? c0 : c1;
    const int bit = std::countr_zero(static_cast<unsigned>(c));
    const BitPlane& plane = planes[static_cast<size_t>(bit)];
    // The original line meets the plane at t = (value − p1[axis]) / (p2[axis] − p1[axis]). The
    // denominator is not zero: a line parallel to the plane keeps one value of that coordinate
    // at every point (moved ends included), so both codes would carry the bit and the logical
    // product would already have rejected the segment.
    const double t = (plane.value - p1[plane.axis]) / (p2[plane.axis] - p1[plane.axis]);
    Vec3 q = p1 + (p2 - p1) * t;
    q[plane.axis] = plane.value;
    end[i] = q;
    moved[i] |= static_cast<std::uint8_t>(1u << bit);
    code[i] = outcode(box, q);
  }
}

std::optional<std::pair<double, double>> liang_barsky(const ClipBox& box, const Vec3& p1,
                                                      const Vec3& p2) {
  const Vec3 d = p2 - p1;
  // Inside the box iff q_k − α·p_k ≥ 0 for the six faces (left, right, bottom, top, near, far).
  const double p[6] = {-d.x(), d.x(), -d.y(), d.y(), d.z(), -d.z()};
  const double q[6] = {p1.x() - box.x_left, box.x_right - p1.x(), p1.y() - box.y_bottom,
                       box.y_top - p1.y(),  box.z_near - p1.z(),  p1.z() - box.z_far};
  double low = 0, up = 1;
  for (int k = 0; k < 6; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return std::nullopt;  // parallel to the face and outside it
      continue;
    }
    if (p[k] < 0) {
      // Entering at α = q/p: reject if α > up, raise low if α > low. With p < 0,
      // q/p > a  ⇔  q < a·p.
      if (q[k] < up * p[k]) return std::nullopt;
      if (q[k] < low * p[k]) low = q[k] / p[k];
    } else {
      // Leaving at α = q/p: reject if α < low, lower up if α < up (q/p < a ⇔ q < a·p).
      if (q[k] < low * p[k]) return std::nullopt;
      if (q[k] < up * p[k]) up = q[k] / p[k];
    }
  }
  return std::make_pair(low, up);
}

}  // namespace hedra
