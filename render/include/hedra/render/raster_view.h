// A projection of world space onto a raster of W × H pixels: the eye's camera, or a light's
// view for a shadow map. Raster coordinates (sx, sy) run right and down, pixel (i, j) covers
// [i, i + 1) × [j, j + 1), its centre is (i + ½, j + ½).
//
// Depth. Every view has a depth key k, smaller = nearer, that is an affine function of
// (sx, sy) over any plane, so the z-buffer interpolates it exactly (docs/algorithms.md §9,
// Δz = −A/C along a scan line):
//  - parallel: k = distance along the view direction from a reference point;
//  - perspective: k = −1/w with w the distance along the view axis from the eye (the depth
//    the course's perspective transform keeps, z' = z/(1 − z/C), up to an affine change).
// Homogeneous raster coordinates (X, Y, W) with sx = X/W, sy = Y/W serve the clipping of
// polygons against the view volume (near plane included) before the division.
#pragma once

#include <Eigen/Geometry>

#include "hedra/scene/camera.h"
#include "hedra/core/plane.h"

namespace hedra {

class RasterView {
 public:
  RasterView() = default;

  /// The scene camera on a width × height raster. Perspective: the camera's eye, target, up
  /// and vertical field of view. Parallel: the camera's direction and up, the scene box
  /// fitted with the kViewMargin margin (the framing lod.h's pixel tolerances assume).
  /// The near plane is kRasterNearPlane (tolerance.h) × the distance from the eye to the
  /// farthest corner of the box.
  /// \throw InvalidInput from Camera::validate.
  static RasterView of_camera(const Camera& camera, int width, int height,
                              const Eigen::AlignedBox3d& scene_box);

  /// A parallel view along `forward` (unit) with raster axes `right`, `down` (unit,
  /// orthogonal), `scale_x`, `scale_y` raster units per world unit, the world point `origin`
  /// at raster point (cx, cy) and depth key 0.
  static RasterView parallel(const Vec3& origin, const Vec3& forward, const Vec3& right,
                             const Vec3& down, double scale_x, double scale_y, double cx,
                             double cy, int width, int height);
  /// A perspective view from `eye` along `forward` (unit) with raster axes `right`, `down`
  /// (unit, orthogonal): a point at depth w and lateral offsets (a, b) maps to
  /// (cx + scale_x·a/w, cy + scale_y·b/w). `near` > 0 is the near clipping distance.
  static RasterView perspective(const Vec3& eye, const Vec3& forward, const Vec3& right,
                                const Vec3& down, double scale_x, double scale_y, double cx,
                                double cy, int width, int height, double near);

  bool is_perspective() const { return perspective_; }
  int width() const { return width_; }
  int height() const { return height_; }
  double near() const { return near_; }
  const Vec3& eye() const { return eye_; }
  const Vec3& forward() const { return forward_; }
  /// Raster units per world unit along x at depth 1 (perspective) or anywhere (parallel).
  double scale_x() const { return scale_x_; }
  double scale_y() const { return scale_y_; }

  /// Homogeneous raster coordinates (X, Y, W) of p: sx = X/W, sy = Y/W; W is the depth w
  /// (perspective) or 1 (parallel). Cost O(1).
  Vec3 homogeneous(const Vec3& p) const;
  /// Raster coordinates of p (p must lie in front of the eye in perspective).
  Eigen::Vector2d project(const Vec3& p) const;
  /// Depth key of p (smaller = nearer).
  double key(const Vec3& p) const;
  /// Depth w of p: the distance along the view axis (from the eye, or from the reference
  /// point of a parallel view).
  double depth(const Vec3& p) const { return (p - eye_).dot(forward_); }
  /// The depth key over a plane as an affine function of the raster point:
  /// k(sx, sy) = c[0]·sx + c[1]·sy + c[2]. \pre the plane does not contain the eye
  /// (perspective) nor the view direction (parallel): a face seen from the front.
  Vec3 key_plane(const Plane& plane) const;
  /// The world point on the ray through raster point (sx, sy) whose depth key is k.
  Vec3 point_at(double sx, double sy, double k) const;
  /// Unit direction of the ray through raster point (sx, sy), away from the eye.
  Vec3 ray_direction(double sx, double sy) const;

 private:
  bool perspective_ = false;
  Vec3 eye_ = Vec3::Zero();  // perspective: the eye; parallel: the reference point
  Vec3 forward_ = Vec3(0, 0, -1), right_ = Vec3(1, 0, 0), down_ = Vec3(0, -1, 0);
  double scale_x_ = 1, scale_y_ = 1, cx_ = 0, cy_ = 0;
  int width_ = 1, height_ = 1;
  double near_ = 0;
};

}  // namespace hedra
