#include "hedra/scene/light.h"

#include <cmath>

#include "hedra/core/error.h"

namespace hedra {

Light Light::directional(const Vec3& direction, double intensity) {
  Light l;
  l.type = Type::Directional;
  l.direction = direction;
  l.intensity = intensity;
  l.validate();
  return l;
}

Light Light::point(const Vec3& position, double intensity) {
  Light l;
  l.type = Type::Point;
  l.position = position;
  l.intensity = intensity;
  l.validate();
  return l;
}

Light Light::spot(const Vec3& position, const Vec3& direction, double cone_deg, double falloff,
                  double intensity) {
  Light l;
  l.type = Type::Spot;
  l.position = position;
  l.direction = direction;
  l.cone_deg = cone_deg;
  l.falloff = falloff;
  l.intensity = intensity;
  l.validate();
  return l;
}

Light Light::sun(double latitude, double longitude, const UtcTime& time, double intensity) {
  Light l;
  l.type = Type::Sun;
  l.latitude = latitude;
  l.longitude = longitude;
  l.time = time;
  l.intensity = intensity;
  l.direction = sunlight_direction(latitude, longitude, time);
  l.validate();
  return l;
}

Vec4 Light::homogeneous() const {
  if (at_infinity()) return Vec4(direction.x(), direction.y(), direction.z(), 0);
  return Vec4(-position.x(), -position.y(), -position.z(), -1);
}

void Light::validate() const {
  auto fail = [](const std::string& m) { throw InvalidInput("light: " + m); };
  if (!(intensity >= 0) || !std::isfinite(intensity)) fail("'intensity' must be >= 0");
  if (!color.allFinite() || (color.array() < 0).any()) fail("'color' must be non-negative");
  if (type != Type::Point && (!direction.allFinite() || direction.norm() == 0))
    fail("'direction' must be a non-zero finite vector");
  if ((type == Type::Point || type == Type::Spot) && !position.allFinite())
    fail("'position' must be finite");
  if (type == Type::Spot && !(cone_deg > 0 && cone_deg < 90))
    fail("spot 'cone_deg' must lie strictly between 0 and 90");
  if (type == Type::Spot && !(falloff >= 0)) fail("spot 'falloff' must be >= 0");
}

}  // namespace hedra
