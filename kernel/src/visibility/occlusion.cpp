#include "hedra/visibility/occlusion.h"

#include "hedra/core/error.h"

namespace hedra {

Viewpoint Viewpoint::at(const Vec3& point) {
  if (!point.allFinite()) throw InvalidInput("viewpoint: the point is not finite");
  Viewpoint v;
  v.at_infinity = false;
  v.point = point;
  return v;
}

Viewpoint Viewpoint::towards(const Vec3& direction) {
  if (!direction.allFinite() || direction.isZero())
    throw InvalidInput("viewpoint: the direction is zero or not finite");
  Viewpoint v;
  v.at_infinity = true;
  v.direction = direction;
  return v;
}

Viewpoint Viewpoint::of(const Camera& camera) {
  return camera.projection == Camera::Projection::Parallel ? towards(camera.direction)
                                                           : at(camera.eye);
}

Viewpoint Viewpoint::of(const Light& light) {
  switch (light.type) {
    case Light::Type::Point:
    case Light::Type::Spot:
      return at(light.position);
    case Light::Type::Directional:
    case Light::Type::Sun:
      return towards(light.direction);
  }
  return towards(light.direction);
}

ExactPlane exact_face_plane(const Body& body, int face) {
  const auto& s = body.support(face);
  const auto& v = body.vertices();
  ExactPlane plane = ExactPlane::through(v[s[0]], v[s[1]], v[s[2]]);
  // Orient it as the body's plane: the support triple's orientation rule lives in Body, so
  // compare at a vertex strictly off the plane (a closed body has one).
  for (const Vec3& p : v) {
    const Sign want = body.face_side(face, p);
    if (want == Sign::Zero) continue;
    return side_of_plane(plane, p) == want ? plane : plane.flipped();
  }
  throw InvalidInput("exact_face_plane: the body is flat");
}

Facing facing(const Body& body, int face, const Viewpoint& view) {
  Sign s;
  if (view.at_infinity) {
    s = direction_sign(exact_face_plane(body, face), view.direction);
    // Moving along d into the inner side: the ray enters through this face.
    return s == Sign::Positive ? Facing::Front : (s == Sign::Zero ? Facing::EdgeOn : Facing::Back);
  }
  s = body.face_side(face, view.point);
  return s == Sign::Negative ? Facing::Front : (s == Sign::Zero ? Facing::EdgeOn : Facing::Back);
}

OcclusionVolume occlusion_volume(const Body& body, const Viewpoint& view) {
  OcclusionVolume out;
  const int n = body.face_count();
  std::vector<char> front(n, 0);
  std::vector<ExactPlane> planes;
  for (int f = 0; f < n; ++f) {
    if (facing(body, f, view) != Facing::Front) continue;
    front[f] = 1;
    out.front_faces.push_back(f);
    planes.push_back(exact_face_plane(body, f));
  }
  if (out.front_faces.empty()) return out;
  const auto& v = body.vertices();
  for (const Edge& e : body.edges()) {
    if (front[e.left_face] == front[e.right_face]) continue;
    out.silhouette.emplace_back(e.v0, e.v1);
    const Vec3 &a = v[e.v0], &b = v[e.v1];
    // A viewpoint on the edge's line sees the body edge-on there: that plane is degenerate
    // and the front face's own plane already bounds the volume.
    ExactPlane plane;
    try {
      plane = view.at_infinity ? ExactPlane::through_direction(a, b, view.direction)
                               : ExactPlane::through(a, b, view.point);
    } catch (const InvalidInput&) {
      continue;
    }
    // The body lies on the plane's inner side: orient it by a vertex strictly off it.
    bool oriented = false;
    for (const Vec3& p : v) {
      const Sign s = side_of_plane(plane, p);
      if (s == Sign::Zero) continue;
      planes.push_back(s == Sign::Positive ? plane : plane.flipped());
      oriented = true;
      break;
    }
    if (!oriented) throw InvalidInput("occlusion_volume: the body is flat");
  }
  out.clipper = ConvexClipper::from_planes(std::move(planes));
  return out;
}

bool hides(const OcclusionVolume& volume, const Vec3& p) {
  if (!volume.clipper) return false;
  for (const ExactPlane& f : volume.clipper->planes())
    if (side_of_plane(f, p) != Sign::Positive) return false;
  return true;
}

}  // namespace hedra
