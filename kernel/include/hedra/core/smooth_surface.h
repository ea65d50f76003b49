// The analytic surface a curved primitive approximates. The polyhedron stays the model for
// every geometric decision; this only gives shading the true surface normals, so a
// tessellated sphere looks round (docs/algorithms.md §8: "normals: gradient of an analytic
// surface") while real edges — a cylinder's rim, a box's edges — stay sharp.
#pragma once

#include <optional>
#include <vector>

#include "hedra/core/plane.h"
#include "hedra/core/transform.h"

namespace hedra {

/// A sphere, a cylinder or a cone as built by hedra/core/primitives.h (cylinder and cone about
/// the z axis), carried by an affine placement. Default: no surface (every face is flat).
/// Value type.
class SmoothSurface {
 public:
  enum class Kind { None, Sphere, Cylinder, Cone };

  SmoothSurface() = default;
  static SmoothSurface sphere(const Vec3& centre, double radius);
  /// Side of the cylinder of radius r about the z axis between z0 and z1 (caps stay flat).
  static SmoothSurface cylinder(double radius, double z0, double z1);
  /// Side of the cone with base circle of radius r at z0 and apex (0, 0, z1) (base stays flat).
  static SmoothSurface cone(double radius, double z0, double z1);

  /// The same surface moved with its body (Body::transformed). A perspective transform gives
  /// Kind::None: its image is no longer one of these surfaces, so the faces shade flat.
  SmoothSurface transformed(const Transform& t) const;

  Kind kind() const { return kind_; }

  /// Every number that defines the surface (19 doubles), for serialising it exactly (Python
  /// pickling); from_state() rebuilds it bit for bit. \throw InvalidInput on a bad state.
  std::vector<double> state() const;
  static SmoothSurface from_state(const std::vector<double>& state);
  bool is_smooth() const { return kind_ != Kind::None; }

  /// Whether a face of the body whose outward unit normal is `outward` lies on the curved
  /// part (a sphere face, a cylinder or cone side) rather than on a flat cap or base. Caps
  /// have normals along the local z axis, sides within a small angle of perpendicular to it
  /// (cylinder) or of the cone's slope; the test takes the middle ground between the two.
  /// Cost O(1).
  bool curved_face(const Vec3& outward) const;

  /// Outward unit normal of the analytic surface at the point of the polyhedron `p`
  /// (a vertex of a curved face; `face_centre` is that face's centroid, used where the
  /// gradient vanishes: at the apex of a cone, on the axis of a cylinder). Cost O(1).
  Vec3 normal(const Vec3& p, const Vec3& face_centre) const;

  /// Whether normal(p, c) depends on the face centre c (p at a sphere's centre, on a cylinder's
  /// or cone's axis). Where it does not, every face around p gets the same normal, bit for bit.
  /// Cost O(1).
  bool normal_needs_face(const Vec3& p) const;

  /// normal(p, c), the same bits, where it does not depend on c; std::nullopt where
  /// normal_needs_face(p). One transform of p instead of the three of both calls (the normal
  /// of every vertex of a tessellated body, for outlines). Cost O(1).
  std::optional<Vec3> vertex_normal(const Vec3& p) const;

 private:
  // Local (primitive) normal at local point q; `face_centre` (world) is taken to the local
  // frame only where the gradient vanishes.
  Vec3 local_normal(const Vec3& q, const Vec3& face_centre) const;
  // Whether local_normal(q, c) depends on c.
  bool local_needs_face(const Vec3& q) const;

  Kind kind_ = Kind::None;
  Vec3 centre_ = Vec3::Zero();  // sphere
  double radius_ = 0, z0_ = 0, z1_ = 0;
  // Placement, column-vector form: world = linear_ · local + offset_. Normals map to the
  // world with inverse_ᵀ (inverse_ = linear_⁻¹) and back with linear_ᵀ.
  Eigen::Matrix3d linear_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d inverse_ = Eigen::Matrix3d::Identity();
  Vec3 offset_ = Vec3::Zero();
};

}  // namespace hedra
