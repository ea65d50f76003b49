#include "hedra/core/smooth_surface.h"

#include <cmath>

#include <Eigen/LU>

#include "hedra/core/error.h"

namespace hedra {

SmoothSurface SmoothSurface::sphere(const Vec3& centre, double radius) {
  SmoothSurface s;
  s.kind_ = Kind::Sphere;
  s.centre_ = centre;
  s.radius_ = radius;
  return s;
}

SmoothSurface SmoothSurface::cylinder(double radius, double z0, double z1) {
  SmoothSurface s;
  s.kind_ = Kind::Cylinder;
  s.radius_ = radius;
  s.z0_ = z0;
  s.z1_ = z1;
  return s;
}

SmoothSurface SmoothSurface::cone(double radius, double z0, double z1) {
  SmoothSurface s;
  s.kind_ = Kind::Cone;
  s.radius_ = radius;
  s.z0_ = z0;
  s.z1_ = z1;
  return s;
}

SmoothSurface SmoothSurface::transformed(const Transform& t) const {
  if (kind_ == Kind::None) return *this;
  if (!t.is_affine()) return SmoothSurface();
  // Row convention p' = p·M: in column form p' = Mᵀ₃ₓ₃·p + (row 4).
  const Eigen::Matrix3d step = t.matrix().topLeftCorner<3, 3>().transpose();
  if (step.determinant() == 0) return SmoothSurface();
  SmoothSurface s = *this;
  s.linear_ = step * linear_;
  s.offset_ = step * offset_ + t.matrix().row(3).head<3>().transpose();
  s.inverse_ = s.linear_.inverse();
  return s;
}

std::vector<double> SmoothSurface::state() const {
  std::vector<double> out{static_cast<double>(kind_), centre_.x(), centre_.y(), centre_.z(),
                          radius_, z0_, z1_};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.push_back(linear_(r, c));
  for (int i = 0; i < 3; ++i) out.push_back(offset_(i));
  return out;
}

SmoothSurface SmoothSurface::from_state(const std::vector<double>& state) {
  if (state.size() != 19 || !(state[0] >= 0 && state[0] <= 3) || state[0] != std::floor(state[0]))
    throw InvalidInput("smooth surface: unknown state");
  SmoothSurface s;
  s.kind_ = static_cast<Kind>(static_cast<int>(state[0]));
  s.centre_ = Vec3(state[1], state[2], state[3]);
  s.radius_ = state[4];
  s.z0_ = state[5];
  s.z1_ = state[6];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) s.linear_(r, c) = state[static_cast<size_t>(7 + 3 * r + c)];
  for (int i = 0; i < 3; ++i) s.offset_(i) = state[static_cast<size_t>(16 + i)];
  // transformed() sets inverse_ the same way (and the identity inverts exactly), so the
  // rebuilt surface is the same bit for bit.
  s.inverse_ = s.linear_.inverse();
  return s;
}

bool SmoothSurface::curved_face(const Vec3& outward) const {
  switch (kind_) {
    case Kind::None:
      return false;
    case Kind::Sphere:
      return true;
    case Kind::Cylinder:
    case Kind::Cone: {
      // Back to the primitive's frame: n_local ∝ linearᵀ · n_world.
      const Vec3 local = (linear_.transpose() * outward).normalized();
      if (kind_ == Kind::Cylinder) return std::abs(local.z()) < 0.5;  // caps: ±1, sides: 0
      const double up = z1_ > z0_ ? 1.0 : -1.0;                       // towards the apex
      return local.z() * up > -0.5;  // base: −1, sides: sin of the slope > 0
    }
  }
  return false;
}

Vec3 SmoothSurface::local_normal(const Vec3& q, const Vec3& face_centre) const {
  const auto local_centre = [&] { return Vec3(inverse_ * (face_centre - offset_)); };
  switch (kind_) {
    case Kind::Sphere: {
      const Vec3 d = q - centre_;
      return d.norm() > 0 ? Vec3(d.normalized()) : Vec3((local_centre() - centre_).normalized());
    }
    case Kind::Cylinder:
    case Kind::Cone: {
      // The normal depends only on the angle about the axis; on the axis (a cone's apex) the
      // face's own angle stands in for it.
      Eigen::Vector2d radial(q.x(), q.y());
      if (radial.norm() <= 1e-12 * radius_) {
        const Vec3 c = local_centre();
        radial = Eigen::Vector2d(c.x(), c.y());
      }
      radial.normalize();
      const double slope = kind_ == Kind::Cylinder ? 0.0 : radius_ / (z1_ - z0_);
      return Vec3(radial.x(), radial.y(), slope).normalized();
    }
    case Kind::None:
      break;
  }
  return Vec3::Zero();
}

bool SmoothSurface::local_needs_face(const Vec3& q) const {
  switch (kind_) {
    case Kind::Sphere: return !((q - centre_).norm() > 0);
    case Kind::Cylinder:
    case Kind::Cone: return Eigen::Vector2d(q.x(), q.y()).norm() <= 1e-12 * radius_;
    case Kind::None: break;
  }
  return false;
}

bool SmoothSurface::normal_needs_face(const Vec3& p) const { return local_needs_face(inverse_ * (p - offset_)); }

Vec3 SmoothSurface::normal(const Vec3& p, const Vec3& face_centre) const {
  const Vec3 q = inverse_ * (p - offset_);
  // Gradients map with the inverse transpose of the placement's linear part.
  return (inverse_.transpose() * local_normal(q, face_centre)).normalized();
}

std::optional<Vec3> SmoothSurface::vertex_normal(const Vec3& p) const {
  const Vec3 q = inverse_ * (p - offset_);
  if (local_needs_face(q)) return std::nullopt;
  return Vec3((inverse_.transpose() * local_normal(q, Vec3::Zero())).normalized());
}

}  // namespace hedra
