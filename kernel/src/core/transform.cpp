#include "hedra/core/transform.h"

#include <cmath>
#include <numbers>
#include <string>

#include "hedra/core/error.h"

namespace hedra {
namespace {

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

// Exact cosine and sine for multiples of 90°, so rotating a box by 90° keeps integer
// coordinates integer (std::cos(pi/2) is 6e-17, not 0).
void cos_sin(double degrees, double& c, double& s) {
  double r = std::fmod(degrees, 360.0);
  if (r < 0) r += 360.0;
  if (r == 0.0) { c = 1; s = 0; return; }
  if (r == 90.0) { c = 0; s = 1; return; }
  if (r == 180.0) { c = -1; s = 0; return; }
  if (r == 270.0) { c = 0; s = -1; return; }
  c = std::cos(radians(degrees));
  s = std::sin(radians(degrees));
}

// Conjugates a transform about the origin so that it acts about `centre`.
Transform about(const Vec3& centre, const Transform& at_origin) {
  if (centre.isZero()) return at_origin;
  return Transform::translation(-centre) * at_origin * Transform::translation(centre);
}

void require_finite(double v, const char* what) {
  if (!std::isfinite(v)) throw InvalidInput(std::string(what) + " is not finite");
}

}  // namespace

Transform Transform::translation(const Vec3& d) {
  Mat4 m = Mat4::Identity();
  m.block<1, 3>(3, 0) = d.transpose();
  return Transform(m);
}

Transform Transform::scaling(const Vec3& k, const Vec3& centre) {
  Mat4 m = Mat4::Identity();
  m(0, 0) = k.x();
  m(1, 1) = k.y();
  m(2, 2) = k.z();
  // x' = x·kx + (1 − kx)·xm, written directly rather than as a product of three matrices,
  // so the course's formula (docs/algorithms.md §2) is reproduced without extra rounding.
  for (int i = 0; i < 3; ++i) m(3, i) = (1.0 - k[i]) * centre[i];
  return Transform(m);
}

Transform Transform::rotation_x(double degrees, const Vec3& centre) {
  double c, s;
  cos_sin(degrees, c, s);
  Mat4 m = Mat4::Identity();
  // y' = y cosθ − z sinθ, z' = z cosθ + y sinθ
  m(1, 1) = c;  m(1, 2) = s;
  m(2, 1) = -s; m(2, 2) = c;
  return about(centre, Transform(m));
}

Transform Transform::rotation_y(double degrees, const Vec3& centre) {
  double c, s;
  cos_sin(degrees, c, s);
  Mat4 m = Mat4::Identity();
  // x' = x cosθ + z sinθ, z' = z cosθ − x sinθ
  m(0, 0) = c; m(0, 2) = -s;
  m(2, 0) = s; m(2, 2) = c;
  return about(centre, Transform(m));
}

Transform Transform::rotation_z(double degrees, const Vec3& centre) {
  double c, s;
  cos_sin(degrees, c, s);
  Mat4 m = Mat4::Identity();
  // x' = x cosθ − y sinθ, y' = x sinθ + y cosθ
  m(0, 0) = c;  m(0, 1) = s;
  m(1, 0) = -s; m(1, 1) = c;
  return about(centre, Transform(m));
}

Transform Transform::rotation(const Vec3& axis, double degrees, const Vec3& centre) {
  if (!axis.allFinite()) throw InvalidInput("rotation axis is not finite");
  double n = axis.norm();
  if (n == 0.0) throw InvalidInput("rotation axis is the zero vector");
  Vec3 u = axis / n;
  double c, s;
  cos_sin(degrees, c, s);
  // Rodrigues' formula R (column-vector form); the row convention stores Rᵀ.
  Eigen::Matrix3d k;
  k << 0, -u.z(), u.y(), u.z(), 0, -u.x(), -u.y(), u.x(), 0;
  Eigen::Matrix3d r = c * Eigen::Matrix3d::Identity() + s * k + (1 - c) * u * u.transpose();
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = r.transpose();
  return about(centre, Transform(m));
}

Transform Transform::perspective(double focal_distance) {
  require_finite(focal_distance, "focal distance");
  if (focal_distance == 0.0) throw InvalidInput("focal distance is zero");
  Mat4 m = Mat4::Identity();
  m(2, 3) = -1.0 / focal_distance;
  return Transform(m);
}

Transform Transform::perspective_projection(double focal_distance) {
  Transform t = perspective(focal_distance);
  t.m_(2, 2) = 0.0;
  return t;
}

Transform Transform::inverse() const {
  Eigen::FullPivLU<Mat4> lu(m_);
  if (!lu.isInvertible()) throw InvalidInput("transform is singular and has no inverse");
  return Transform(lu.inverse());
}

bool Transform::is_affine() const {
  return m_(0, 3) == 0.0 && m_(1, 3) == 0.0 && m_(2, 3) == 0.0 && m_(3, 3) == 1.0;
}

Vec4 Transform::apply_homogeneous(const Vec3& p) const {
  return (p.homogeneous().transpose() * m_).transpose();
}

Vec3 Transform::apply(const Vec3& p) const {
  Vec4 h = apply_homogeneous(p);
  if (h.w() == 0.0) throw InvalidInput("point maps to infinity (it lies on the vanishing plane)");
  if (h.w() == 1.0) return h.head<3>();
  return h.head<3>() / h.w();
}

Vec3 Transform::apply_vector(const Vec3& v) const {
  return (v.transpose() * m_.topLeftCorner<3, 3>()).transpose();
}

Plane Transform::apply(const Plane& plane) const {
  return Plane(inverse().matrix() * plane.coefficients).normalized();
}

BodyMatrix Transform::apply(const BodyMatrix& body_matrix) const {
  return inverse().matrix() * body_matrix;
}

}  // namespace hedra
