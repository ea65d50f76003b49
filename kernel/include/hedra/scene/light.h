// Light sources: directional, point, spot, and the sun (a directional light computed from a
// place and a UTC time).
#pragma once

#include "hedra/core/plane.h"
#include "hedra/scene/sun.h"

namespace hedra {

struct Light {
  enum class Type { Directional, Point, Spot, Sun };
  Type type = Type::Directional;
  Vec3 direction = Vec3(0, 0, -1);  // the way the light travels (directional, spot, sun)
  Vec3 position = Vec3::Zero();     // point, spot
  double intensity = 1;
  Vec3 color = Vec3(1, 1, 1);
  double cone_deg = 30;  // spot: half-angle of the cone
  double falloff = 1;    // spot: exponent of cos(angle) inside the cone
  // Sun inputs (kept for reports and write-back).
  double latitude = 0, longitude = 0;
  UtcTime time;

  static Light directional(const Vec3& direction, double intensity = 1);
  static Light point(const Vec3& position, double intensity = 1);
  static Light spot(const Vec3& position, const Vec3& direction, double cone_deg,
                    double falloff = 1, double intensity = 1);
  /// \throw InvalidInput when the sun is below the horizon (naming the place and time).
  static Light sun(double latitude, double longitude, const UtcTime& time, double intensity = 1);

  bool at_infinity() const { return type == Type::Directional || type == Type::Sun; }
  /// Homogeneous light vector L of the course (docs/algorithms.md §7.1): a face with body-matrix
  /// column V faces away from the light (self-shadow) when L·V < 0, grazes it when L·V = 0.
  /// At infinity L = (direction, 0); at a point L = (−position, −1) (as Camera::viewer_vector).
  Vec4 homogeneous() const;
  /// \throw InvalidInput naming the problem.
  void validate() const;
};

}  // namespace hedra
