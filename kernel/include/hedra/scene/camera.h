// The viewer: a parallel or a perspective camera with an image size.
#pragma once

#include <string>

#include <Eigen/Geometry>

#include "hedra/core/plane.h"

namespace hedra {

/// Fraction of the image kept free on each side when a scene is fitted to it.
constexpr double kViewMargin = 0.05;

struct Camera {
  enum class Projection { Parallel, Perspective };
  Projection projection = Projection::Parallel;
  /// Parallel: direction from the eye towards the scene. The default is the course's viewer
  /// at +∞ on z looking at the origin: direction (0, 0, −1), E = (0, 0, −1, 0).
  Vec3 direction = Vec3(0, 0, -1);
  /// Perspective: eye point, target point and vertical field of view.
  Vec3 eye = Vec3(0, 0, 10);
  Vec3 target = Vec3::Zero();
  double fov_deg = 45;
  Vec3 up = Vec3(0, 1, 0);
  int width = 800;
  int height = 600;

  /// The course's special case: parallel view from +∞ on z (docs/algorithms.md §6.1).
  static Camera course_default() { return Camera(); }
  static Camera parallel(const Vec3& direction, const Vec3& up = Vec3(0, 0, 1));
  static Camera perspective(const Vec3& eye, const Vec3& target, double fov_deg,
                            const Vec3& up = Vec3(0, 0, 1));

  /// Homogeneous viewer vector E of the course: a face with body-matrix column V is a back
  /// face when E·V < 0 and edge-on when E·V = 0. Parallel: E = (direction, 0).
  /// Perspective: E = (−eye, −1), so E·V < 0 exactly when the eye is strictly inside the
  /// face's inner half-space (the face turns its back to the eye).
  Vec4 viewer_vector() const;
  /// Unit viewing direction at point p (from the eye towards p).
  Vec3 view_direction_at(const Vec3& p) const;
  /// Size in world units of one pixel at point p, for a parallel view whose visible height is
  /// `view_height` (world units) or a perspective view (from the distance and the fov).
  double pixel_size_at(const Vec3& p, double view_height) const;

  /// Perspective: the near clipping distance for a scene in `scene_box`, as the renderer uses
  /// it: kRasterNearPlane (tolerance.h) × the distance from the eye to the box's farthest
  /// corner. Geometry nearer than that to the eye plane is clipped away (render, hlr, shadows'
  /// drawing). Cost O(1).
  double near_distance(const Eigen::AlignedBox3d& scene_box) const;
  /// Perspective: the near plane at near_distance(scene_box) in front of the eye, its inner
  /// (positive) side the kept side, its double coefficients the plane itself (they are taken as
  /// exact by side_of_plane and split()). Cost O(1).
  Plane near_plane(const Eigen::AlignedBox3d& scene_box) const;

  /// \throw InvalidInput naming the field ("camera: 'up' is parallel to the view direction").
  void validate() const;
};

}  // namespace hedra
