#include "hedra/render/raster_view.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hedra/core/error.h"
#include "hedra/scene/lod.h"
#include "hedra/core/tolerance.h"

namespace hedra {

RasterView RasterView::parallel(const Vec3& origin, const Vec3& forward, const Vec3& right,
                                const Vec3& down, double scale_x, double scale_y, double cx,
                                double cy, int width, int height) {
  RasterView v;
  v.perspective_ = false;
  v.eye_ = origin;
  v.forward_ = forward;
  v.right_ = right;
  v.down_ = down;
  v.scale_x_ = scale_x;
  v.scale_y_ = scale_y;
  v.cx_ = cx;
  v.cy_ = cy;
  v.width_ = width;
  v.height_ = height;
  return v;
}

RasterView RasterView::perspective(const Vec3& eye, const Vec3& forward, const Vec3& right,
                                   const Vec3& down, double scale_x, double scale_y, double cx,
                                   double cy, int width, int height, double near) {
  RasterView v = parallel(eye, forward, right, down, scale_x, scale_y, cx, cy, width, height);
  v.perspective_ = true;
  v.near_ = near;
  return v;
}

RasterView RasterView::of_camera(const Camera& camera, int width, int height,
                                 const Eigen::AlignedBox3d& scene_box) {
  Camera c = camera;
  c.width = width;
  c.height = height;
  c.validate();
  Eigen::AlignedBox3d box = scene_box;
  if (box.isEmpty()) box = Eigen::AlignedBox3d(Vec3::Zero(), Vec3::Zero());
  if (c.projection == Camera::Projection::Perspective) {
    const Vec3 f = (c.target - c.eye).normalized();
    const Vec3 right = f.cross(c.up).normalized();
    const Vec3 down = -right.cross(f);
    const double s = 0.5 * height / std::tan(c.fov_deg * std::numbers::pi / 360);
    const double near = c.near_distance(box);  // the same near plane as hlr's (camera.h)
    return perspective(c.eye, f, right, down, s, s, 0.5 * width, 0.5 * height, width, height, near);
  }
  // Parallel: the box fitted as lod.h's parallel_view_height frames it.
  const Vec3 f = c.direction.normalized();
  const Vec3 right = f.cross(c.up).normalized();
  const Vec3 up = right.cross(f);
  double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
  double wmin = INFINITY, wmax = -INFINITY;
  for (int i = 0; i < 8; ++i) {
    const Vec3 p = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i));
    umin = std::min(umin, p.dot(right)), umax = std::max(umax, p.dot(right));
    vmin = std::min(vmin, p.dot(up)), vmax = std::max(vmax, p.dot(up));
    wmin = std::min(wmin, p.dot(f)), wmax = std::max(wmax, p.dot(f));
  }
  double view_height = parallel_view_height(c, box);
  if (!(view_height > 0)) view_height = 1;  // a single point: any scale shows it
  const double s = height / view_height;
  const Vec3 origin = 0.5 * (umin + umax) * right + 0.5 * (vmin + vmax) * up + 0.5 * (wmin + wmax) * f;
  return parallel(origin, f, right, -up, s, s, 0.5 * width, 0.5 * height, width, height);
}

Vec3 RasterView::homogeneous(const Vec3& p) const {
  const Vec3 d = p - eye_;
  const double a = scale_x_ * d.dot(right_), b = scale_y_ * d.dot(down_);
  if (!perspective_) return Vec3(cx_ + a, cy_ + b, 1);
  const double w = d.dot(forward_);
  return Vec3(cx_ * w + a, cy_ * w + b, w);
}

Eigen::Vector2d RasterView::project(const Vec3& p) const {
  const Vec3 h = homogeneous(p);
  return Eigen::Vector2d(h.x() / h.z(), h.y() / h.z());
}

double RasterView::key(const Vec3& p) const {
  const double w = depth(p);
  return perspective_ ? -1 / w : w;
}

Vec3 RasterView::key_plane(const Plane& plane) const {
  const Vec3 n = plane.normal();
  const double nr = n.dot(right_) / scale_x_, nd = n.dot(down_) / scale_y_, nf = n.dot(forward_);
  const double at_eye = plane.value(eye_);
  if (perspective_) {
    // w = −at_eye / (n·dir) with dir = f + (sx − cx)/sx·r + (sy − cy)/sy·d; k = −1/w.
    return Vec3(nr / at_eye, nd / at_eye, (nf - nr * cx_ - nd * cy_) / at_eye);
  }
  // k = −(n·o + d)/(n·f) with o the ray's point at depth 0.
  return Vec3(-nr / nf, -nd / nf, -(at_eye - nr * cx_ - nd * cy_) / nf);
}

Vec3 RasterView::point_at(double sx, double sy, double k) const {
  const Vec3 lateral = ((sx - cx_) / scale_x_) * right_ + ((sy - cy_) / scale_y_) * down_;
  if (perspective_) return eye_ + (-1 / k) * (forward_ + lateral);
  return eye_ + lateral + k * forward_;
}

Vec3 RasterView::ray_direction(double sx, double sy) const {
  if (!perspective_) return forward_;
  return (forward_ + ((sx - cx_) / scale_x_) * right_ + ((sy - cy_) / scale_y_) * down_).normalized();
}

}  // namespace hedra
