#include "hedra/scene/lod.h"

#include <cmath>
#include <cstdio>

#include "hedra/core/error.h"

namespace hedra {

double parallel_view_height(const Camera& camera, const Eigen::AlignedBox3d& box) {
  // Picture-plane axes: right = direction × up, true up = right × direction.
  const Vec3 d = camera.direction.normalized();
  const Vec3 right = d.cross(camera.up).normalized();
  const Vec3 up = right.cross(d);
  double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
  for (int i = 0; i < 8; ++i) {
    Vec3 c = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i));
    umin = std::min(umin, c.dot(right));
    umax = std::max(umax, c.dot(right));
    vmin = std::min(vmin, c.dot(up));
    vmax = std::max(vmax, c.dot(up));
  }
  const double aspect = static_cast<double>(camera.width) / camera.height;
  const double height = std::max(vmax - vmin, (umax - umin) / aspect);
  return height / (1 - 2 * kViewMargin);
}

double chordal_tolerance_for_pixels(double pixel_tolerance, const Vec3& centre, double radius,
                                    const Camera& camera, double view_height, std::string* note) {
  if (!(pixel_tolerance > 0) || !std::isfinite(pixel_tolerance))
    throw InvalidInput("'pixel_tolerance' must be positive");
  char buf[200];
  if (camera.projection == Camera::Projection::Parallel) {
    const double pixel = camera.pixel_size_at(centre, view_height);
    const double tol = pixel_tolerance * pixel;
    std::snprintf(buf, sizeof buf,
                  "pixel_tolerance %g px x pixel size %.4g (parallel view, %d px high) = chordal "
                  "tolerance %.4g",
                  pixel_tolerance, pixel, camera.height, tol);
    if (note) *note = buf;
    return tol;
  }
  const Vec3 axis = (camera.target - camera.eye).normalized();
  const double depth = (centre - camera.eye).dot(axis) - radius;  // nearest depth of the body
  if (!(depth > 0))
    throw InvalidInput("pixel_tolerance: the body reaches the eye plane of the perspective camera");
  const Vec3 nearest = camera.eye + depth * axis;
  const double pixel = camera.pixel_size_at(nearest, 0);
  const double tol = pixel_tolerance * pixel;
  std::snprintf(buf, sizeof buf,
                "pixel_tolerance %g px x pixel size %.4g at depth %.4g (perspective, fov %g deg, "
                "%d px high) = chordal tolerance %.4g",
                pixel_tolerance, pixel, depth, camera.fov_deg, camera.height, tol);
  if (note) *note = buf;
  return tol;
}

}  // namespace hedra
