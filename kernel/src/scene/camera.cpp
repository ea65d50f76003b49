#include "hedra/scene/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hedra/core/error.h"
#include "hedra/core/tolerance.h"

namespace hedra {

Camera Camera::parallel(const Vec3& direction, const Vec3& up) {
  Camera c;
  c.projection = Projection::Parallel;
  c.direction = direction;
  c.up = up;
  c.validate();
  return c;
}

Camera Camera::perspective(const Vec3& eye, const Vec3& target, double fov_deg, const Vec3& up) {
  Camera c;
  c.projection = Projection::Perspective;
  c.eye = eye;
  c.target = target;
  c.fov_deg = fov_deg;
  c.up = up;
  c.validate();
  return c;
}

Vec4 Camera::viewer_vector() const {
  if (projection == Projection::Parallel) return Vec4(direction.x(), direction.y(), direction.z(), 0);
  return Vec4(-eye.x(), -eye.y(), -eye.z(), -1);
}

Vec3 Camera::view_direction_at(const Vec3& p) const {
  if (projection == Projection::Parallel) return direction.normalized();
  return (p - eye).normalized();
}

double Camera::pixel_size_at(const Vec3& p, double view_height) const {
  if (projection == Projection::Parallel) return view_height / height;
  const Vec3 axis = (target - eye).normalized();
  const double depth = std::max((p - eye).dot(axis), 1e-9 * (target - eye).norm());
  return 2 * depth * std::tan(fov_deg * std::numbers::pi / 360) / height;
}

double Camera::near_distance(const Eigen::AlignedBox3d& scene_box) const {
  Eigen::AlignedBox3d box = scene_box;
  if (box.isEmpty()) box = Eigen::AlignedBox3d(Vec3::Zero(), Vec3::Zero());
  double far = 0;
  for (int i = 0; i < 8; ++i)
    far = std::max(far, (box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)) - eye).norm());
  return kRasterNearPlane * std::max(far, 1e-300);
}

Plane Camera::near_plane(const Eigen::AlignedBox3d& scene_box) const {
  const Vec3 f = (target - eye).normalized();
  return Plane(f.x(), f.y(), f.z(), -(f.dot(eye) + near_distance(scene_box)));
}

void Camera::validate() const {
  auto fail = [](const std::string& m) { throw InvalidInput("camera: " + m); };
  if (width < 1 || height < 1 || width > 65536 || height > 65536)
    fail("image size must be between 1 and 65536 pixels");
  if (!up.allFinite() || up.norm() == 0) fail("'up' must be a non-zero finite vector");
  Vec3 view;
  if (projection == Projection::Parallel) {
    if (!direction.allFinite() || direction.norm() == 0)
      fail("'direction' must be a non-zero finite vector");
    view = direction;
  } else {
    if (!eye.allFinite() || !target.allFinite()) fail("'eye' and 'target' must be finite");
    if (eye == target) fail("'eye' and 'target' coincide");
    if (!(fov_deg > 0 && fov_deg < 180)) fail("'fov_deg' must lie strictly between 0 and 180");
    view = target - eye;
  }
  if (view.normalized().cross(up.normalized()).norm() < 1e-9)
    fail("'up' is parallel to the view direction");
}

}  // namespace hedra
