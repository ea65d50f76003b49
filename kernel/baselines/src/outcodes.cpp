#include "hedra/baselines/outcodes.h"

#include <cmath>

#include "hedra/core/error.h"

namespace hedra {
namespace {

bool all_finite(std::initializer_list<double> values) {
  for (double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

// Exact sign of the course's test function f = c − (z − z_cp)·edge/(z_far − z_cp), c the x or y
// coordinate (f_r: edge = x_right, f_l: x_left, f_t: y_top, f_b: y_bottom). As
// z_far − z_cp < 0, sign(f) = sign(edge·(z − z_cp) − (z_far − z_cp)·c), which is orient2d of
// the centre (0, z_cp), the far edge (edge, z_far) and the point (c, z).
Sign test_sign(double edge, double z_far, double z_cp, double coordinate, double z) {
  return orient2d(Vec2(0, z_cp), Vec2(edge, z_far), Vec2(coordinate, z));
}

}  // namespace

ClipBox ClipBox::from_bounds(const Vec3& min, const Vec3& max) {
  ClipBox b;
  b.x_left = min.x();
  b.x_right = max.x();
  b.y_bottom = min.y();
  b.y_top = max.y();
  b.z_far = min.z();
  b.z_near = max.z();
  return b;
}

void ClipBox::validate() const {
  if (!all_finite({x_left, x_right, y_bottom, y_top, z_near, z_far}))
    throw InvalidInput("clip box with a bound that is not finite");
  if (!(x_left < x_right) || !(y_bottom < y_top) || !(z_far < z_near))
    throw InvalidInput("clip box needs x_left < x_right, y_bottom < y_top and z_far < z_near");
}

void ViewFrustum::validate() const {
  if (!all_finite({x_left, x_right, y_bottom, y_top, z_near, z_far, z_cp}))
    throw InvalidInput("view frustum with a parameter that is not finite");
  if (!(x_left < x_right) || !(y_bottom < y_top))
    throw InvalidInput("view frustum needs x_left < x_right and y_bottom < y_top");
  if (!(z_far < z_near) || !(z_near < z_cp))
    throw InvalidInput("view frustum needs z_far < z_near < z_cp");
}

std::uint8_t outcode(const ClipBox& box, const Vec3& p) {
  std::uint8_t code = 0;
  if (p.x() < box.x_left) code |= kOutLeft;
  if (p.x() > box.x_right) code |= kOutRight;
  if (p.y() < box.y_bottom) code |= kOutBottom;
  if (p.y() > box.y_top) code |= kOutTop;
  if (p.z() > box.z_near) code |= kOutNear;
  if (p.z() < box.z_far) code |= kOutFar;
  return code;
}

std::uint8_t halfspace_outcode(const ViewFrustum& f, const Vec3& p) {
  std::uint8_t code = 0;
  if (test_sign(f.x_left, f.z_far, f.z_cp, p.x(), p.z()) == Sign::Negative) code |= kOutLeft;
  if (test_sign(f.x_right, f.z_far, f.z_cp, p.x(), p.z()) == Sign::Positive) code |= kOutRight;
  if (test_sign(f.y_bottom, f.z_far, f.z_cp, p.y(), p.z()) == Sign::Negative) code |= kOutBottom;
  if (test_sign(f.y_top, f.z_far, f.z_cp, p.y(), p.z()) == Sign::Positive) code |= kOutTop;
  if (p.z() > f.z_near) code |= kOutNear;
  if (p.z() < f.z_far) code |= kOutFar;
  return code;
}

std::uint8_t outcode(const ViewFrustum& f, const Vec3& p) {
  std::uint8_t code = halfspace_outcode(f, p);
  // The course's fix (docs/algorithms.md §3.2): beyond the centre of projection the first four bits
  // are inverted.
  if (p.z() > f.z_cp) code ^= kOutSides;
  return code;
}

FrustumTests frustum_tests(const ViewFrustum& f, const Vec3& p) {
  const double depth = f.z_far - f.z_cp;
  const double a1 = f.x_right / depth, a2 = -a1 * f.z_cp;
  const double b1 = f.x_left / depth, b2 = -b1 * f.z_cp;
  const double g1 = f.y_top / depth, g2 = -g1 * f.z_cp;
  const double d1 = f.y_bottom / depth, d2 = -d1 * f.z_cp;
  return {p.x() - p.z() * b1 - b2, p.x() - p.z() * a1 - a2, p.y() - p.z() * d1 - d2,
          p.y() - p.z() * g1 - g2};
}

bool trivially_invisible(const ViewFrustum& frustum, const Vec3& a, const Vec3& b) {
  return (halfspace_outcode(frustum, a) & halfspace_outcode(frustum, b)) != 0;
}

ConvexClipper box_clipper(const ClipBox& box) {
  box.validate();
  return ConvexClipper::from_planes({
      ExactPlane::from_coefficients(Plane(1, 0, 0, -box.x_left)),
      ExactPlane::from_coefficients(Plane(-1, 0, 0, box.x_right)),
      ExactPlane::from_coefficients(Plane(0, 1, 0, -box.y_bottom)),
      ExactPlane::from_coefficients(Plane(0, -1, 0, box.y_top)),
      ExactPlane::from_coefficients(Plane(0, 0, -1, box.z_near)),
      ExactPlane::from_coefficients(Plane(0, 0, 1, -box.z_far)),
  });
}

ConvexClipper frustum_clipper(const ViewFrustum& f) {
  f.validate();
  const Vec3 centre(0, 0, f.z_cp);
  const Vec3 lb(f.x_left, f.y_bottom, f.z_far), rb(f.x_right, f.y_bottom, f.z_far);
  const Vec3 rt(f.x_right, f.y_top, f.z_far), lt(f.x_left, f.y_top, f.z_far);
  // Each triple runs counter-clockwise seen from outside, so orient3d is Negative inside.
  return ConvexClipper::from_planes({
      ExactPlane::through(centre, lt, lb),
      ExactPlane::through(centre, rb, rt),
      ExactPlane::through(centre, lb, rb),
      ExactPlane::through(centre, rt, lt),
      ExactPlane::from_coefficients(Plane(0, 0, -1, f.z_near)),
      ExactPlane::from_coefficients(Plane(0, 0, 1, -f.z_far)),
  });
}

}  // namespace hedra
