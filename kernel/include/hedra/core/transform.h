// Homogeneous 4×4 transformations in the course's row-vector convention (docs/algorithms.md §2).
//
// Convention. The course writes points as rows (x, y, z, 1) multiplied on the right:
//   (x', y', z', w') = (x, y, z, 1) · M.
// matrix() returns exactly that M (translation in row 4, the perspective term −1/C in
// row 3, column 4). Eigen is column-major and column-vector minded; the mapping is
//   p'ᵀ = Mᵀ · pᵀ      (apply() does p.homogeneous().transpose() * M),
// so a course matrix is never transposed when stored, only when used with column vectors.
// Composition follows the row convention: (A * B) applies A first, then B
// (p · A · B). A plane is a column (a, b, c, d)ᵀ with p · V = value; it transforms as
// V' = M⁻¹ · V, and a body matrix as [VT] = [T]⁻¹ · [V] (docs/algorithms.md §2), so that
// p' · V' = p · V: a transformed interior point stays positive.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "hedra/core/plane.h"

namespace hedra {

using Mat4 = Eigen::Matrix4d;
using BodyMatrix = Eigen::Matrix<double, 4, Eigen::Dynamic>;

class Transform {
 public:
  Transform() : m_(Mat4::Identity()) {}
  /// Wraps a matrix given in the course's row-vector convention.
  explicit Transform(const Mat4& row_convention_matrix) : m_(row_convention_matrix) {}

  // Builders. Angles in degrees, counter-clockwise when looking from the positive axis
  // towards the origin (x' = x cosθ − y sinθ for OZ, as in docs/algorithms.md §2).
  static Transform identity() { return Transform(); }
  static Transform translation(const Vec3& d);
  /// Scaling by (kx, ky, kz) about `centre`: x' = x·kx + (1 − kx)·xm. Negative factors
  /// reflect (kx = −1: mirror in the plane x = xm; all −1: symmetry through the centre).
  static Transform scaling(const Vec3& k, const Vec3& centre = Vec3::Zero());
  static Transform scaling(double k, const Vec3& centre = Vec3::Zero()) {
    return scaling(Vec3(k, k, k), centre);
  }
  static Transform rotation_x(double degrees, const Vec3& centre = Vec3::Zero());
  static Transform rotation_y(double degrees, const Vec3& centre = Vec3::Zero());
  static Transform rotation_z(double degrees, const Vec3& centre = Vec3::Zero());
  /// Rotation about the axis through `centre` with direction `axis` (right-handed).
  /// \throw InvalidInput if axis is zero or not finite.
  static Transform rotation(const Vec3& axis, double degrees, const Vec3& centre = Vec3::Zero());
  /// One-point perspective transformation, centre of projection at (0, 0, C): identity with
  /// −1/C in row 3, column 4. Keeps a depth z' = z / (1 − z/C) for hidden-surface work.
  /// \throw InvalidInput if C is zero or not finite.
  static Transform perspective(double focal_distance);
  /// One-point perspective projection onto z = 0: column 3 zeroed and −1/C in row 3,
  /// column 4, so (x, y, z) ↦ (x, y, 0) / (1 − z/C).
  static Transform perspective_projection(double focal_distance);

  const Mat4& matrix() const { return m_; }
  /// Composition: (*this) first, then `next`.
  Transform operator*(const Transform& next) const { return Transform(m_ * next.m_); }
  Transform then(const Transform& next) const { return *this * next; }
  /// \throw InvalidInput if the matrix is singular (a projection has no inverse).
  Transform inverse() const;
  /// True when the last column is (0, 0, 0, 1): no perspective term.
  bool is_affine() const;
  /// Determinant of the upper-left 3×3 block: negative for reflections.
  double linear_determinant() const { return m_.topLeftCorner<3, 3>().determinant(); }

  /// Homogeneous image of a point (no division).
  Vec4 apply_homogeneous(const Vec3& p) const;
  /// Image of a point, divided by w. \throw InvalidInput when w = 0 (a point on the
  /// vanishing plane of a perspective).
  Vec3 apply(const Vec3& p) const;
  /// Image of a direction (w = 0), no translation; for affine transforms only.
  Vec3 apply_vector(const Vec3& v) const;
  /// Plane image: V' = M⁻¹ · V, renormalized to a unit normal (orientation kept).
  Plane apply(const Plane& plane) const;
  /// Body matrix image: [VT] = [T]⁻¹ · [V], columns not renormalized (as in the course).
  BodyMatrix apply(const BodyMatrix& body_matrix) const;

 private:
  Mat4 m_;  // row-vector convention: p' = p · m_
};

}  // namespace hedra
