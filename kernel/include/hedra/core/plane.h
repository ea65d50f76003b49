// A plane a·x + b·y + c·z + d = 0 with the inner-normal convention.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hedra {

using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;

/// Plane (a, b, c, d) of a face: interior points of the body give a·x + b·y + c·z + d > 0,
/// so (a, b, c) is the inner normal. Faces of a Body store unit-length normals, so value()
/// is the signed distance. value() is a floating-point construction; exact side decisions go
/// through hedra/core/predicates.h.
struct Plane {
  Vec4 coefficients = Vec4::Zero();  // (a, b, c, d): a column of the body matrix

  Plane() = default;
  explicit Plane(const Vec4& abcd) : coefficients(abcd) {}
  Plane(double a, double b, double c, double d) : coefficients(a, b, c, d) {}
  /// The plane through `point` with inner normal `normal`.
  static Plane through(const Vec3& point, const Vec3& normal) {
    return Plane(normal.x(), normal.y(), normal.z(), -normal.dot(point));
  }

  Vec3 normal() const { return coefficients.head<3>(); }
  double offset() const { return coefficients[3]; }
  double value(const Vec3& p) const { return coefficients.head<3>().dot(p) + coefficients[3]; }
  /// Same plane scaled so the normal has unit length (the orientation is kept).
  Plane normalized() const { return Plane(coefficients / coefficients.head<3>().norm()); }
  Plane flipped() const { return Plane(-coefficients); }
};

}  // namespace hedra
