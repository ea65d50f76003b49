#include "hedra/visibility/occlusion.h"

#include <algorithm>
#include <cmath>

#include "hedra/core/error.h"
#include "hedra/core/face_geometry.h"
#include "hedra/core/parallel.h"
#include "hedra/core/predicates.h"
#include "hedra/mesh/convexity.h"

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
  // face_side(f, p) = −orient3d(v[s0], v[s1], v[s2], p) = f(p) of ExactPlane::through.
  return ExactPlane::through(v[static_cast<size_t>(s[0])], v[static_cast<size_t>(s[1])],
                             v[static_cast<size_t>(s[2])]);
}

namespace {

Facing facing_from_inner(Sign view_side_inner) {
  return view_side_inner == Sign::Negative
             ? Facing::Front
             : (view_side_inner == Sign::Zero ? Facing::EdgeOn : Facing::Back);
}

// c = a + d when the sum is exact in every coordinate (TwoSum's error term is zero).
bool exact_sum(const Vec3& a, const Vec3& d, Vec3& c) {
  for (int i = 0; i < 3; ++i) {
    const double s = a[i] + d[i], bv = s - a[i];
    if ((a[i] - (s - bv)) + (d[i] - bv) != 0 || !std::isfinite(s)) return false;
    c[i] = s;
  }
  return true;
}

// The plane through silhouette edge ab and the viewpoint (parallel to its direction), or
// nullopt when the viewpoint lies on the edge's line (the front face's plane bounds there).
std::optional<ExactPlane> silhouette_plane(const Vec3& a, const Vec3& b, const Viewpoint& view) {
  try {
    Vec3 c;
    if (!view.at_infinity) return ExactPlane::through(a, b, view.point);
    // The same plane as through_direction (c − a = d exactly), by the three-point form.
    if (exact_sum(a, view.direction, c)) return ExactPlane::through(a, b, c);
    return ExactPlane::through_direction(a, b, view.direction);
  } catch (const InvalidInput&) {
    return std::nullopt;
  }
}

}  // namespace

Facing facing(const Body& body, int face, const Viewpoint& view) {
  const auto& s = body.support(face);
  const auto& v = body.vertices();
  const Vec3 &a = v[static_cast<size_t>(s[0])], &b = v[static_cast<size_t>(s[1])],
             &c = v[static_cast<size_t>(s[2])];
  // orient3d of the support triple is Positive on the outer side (Body::face_side = −it).
  if (view.at_infinity) {
    // Moving along d into the inner side: the ray enters through this face.
    return facing_from_inner(orient_direction(a, b, c, view.direction));
  }
  return facing_from_inner(-orient3d(a, b, c, view.point));
}

Facing facing(const ExactPlane& face_plane, const Viewpoint& view) {
  if (view.at_infinity) return facing_from_inner(-direction_sign(face_plane, view.direction));
  return facing_from_inner(side_of_plane(face_plane, view.point));
}

OcclusionVolume occlusion_volume(const Body& body, const Viewpoint& view) {
  std::vector<Facing> f(static_cast<size_t>(body.face_count()));
  for (int i = 0; i < body.face_count(); ++i) f[static_cast<size_t>(i)] = facing(body, i, view);
  return occlusion_volume(body, f, view);
}

namespace {

// occlusion_volume, or with `front_planes` false silhouette_volume.
OcclusionVolume volume_of(const Body& body, std::span<const Facing> facing, const Viewpoint& view,
                          std::span<const ExactPlane> face_planes, bool front_planes) {
  OcclusionVolume out;
  const auto& v = body.vertices();
  // Sized exactly: reserving a plane per face and edge (160 bytes each) was 36 MB for a
  // 74 000-face sphere, of which a sixth is used, mapped afresh by malloc on every call: most
  // of the page faults of hidden lines, and half their time on a machine where faults are dear.
  const auto is_front = [&](int f) { return facing[static_cast<size_t>(f)] == Facing::Front; };
  size_t fronts = 0, silhouette = 0;
  for (int f = 0; f < body.face_count(); ++f) fronts += is_front(f);
  if (fronts == 0) return out;
  for (const Edge& e : body.edges()) silhouette += is_front(e.left_face) != is_front(e.right_face);
  std::vector<ExactPlane> planes;
  planes.reserve((front_planes ? fronts : 0) + silhouette);
  out.front_faces.reserve(fronts);
  out.silhouette.reserve(silhouette);
  // Front faces: their planes, inner side Positive already.
  for (int f = 0; f < body.face_count(); ++f) {
    if (!is_front(f)) continue;
    out.front_faces.push_back(f);
    if (front_planes)
      planes.push_back(face_planes.empty() ? exact_face_plane(body, f) : face_planes[static_cast<size_t>(f)]);
  }
  // Silhouette edges: between a front face and one that is not.
  for (const Edge& e : body.edges()) {
    if (is_front(e.left_face) == is_front(e.right_face)) continue;
    out.silhouette.emplace_back(e.v0, e.v1);
    const std::optional<ExactPlane> plane =
        silhouette_plane(v[static_cast<size_t>(e.v0)], v[static_cast<size_t>(e.v1)], view);
    if (!plane) continue;
    // The body lies on the inner side. The plane supports the convex body along the edge, so
    // every vertex off it has the same exact sign and any one of them orients the plane: first
    // the vertices of the edge's two faces (O(face size); the front face's vertices off the
    // edge's line are off the plane unless the face is nearly edge-on), then, only when all
    // of those lie on it, the vertex farthest from the plane in double (only the choice of
    // vertex), then an exact scan (data at the limits of double). O(1) per edge of a mesh
    // instead of O(V).
    Sign side = Sign::Zero;
    for (const int f : {e.left_face, e.right_face}) {
      for (const int x : body.faces()[static_cast<size_t>(f)].loops[0])
        if (x != e.v0 && x != e.v1 && (side = side_of_plane(*plane, v[static_cast<size_t>(x)])) != Sign::Zero)
          break;
      if (side != Sign::Zero) break;
    }
    if (side == Sign::Zero) {
      size_t far = 0;
      double best = -1;
      for (size_t i = 0; i < v.size(); ++i) {
        const double d = std::abs(plane->value(v[i]));
        if (d > best) best = d, far = i;
      }
      side = side_of_plane(*plane, v[far]);
    }
    if (side == Sign::Zero)
      for (const Vec3& p : v)
        if ((side = side_of_plane(*plane, p)) != Sign::Zero) break;
    if (side == Sign::Zero) throw InvalidInput("occlusion volume: the body is flat");
    planes.push_back(side == Sign::Positive ? *plane : plane->flipped());
  }
  if (!planes.empty()) out.clipper = ConvexClipper::from_planes(std::move(planes));
  return out;
}

}  // namespace

OcclusionVolume occlusion_volume(const Body& body, std::span<const Facing> facing,
                                 const Viewpoint& view, std::span<const ExactPlane> face_planes) {
  return volume_of(body, facing, view, face_planes, true);
}

OcclusionVolume occlusion_volume(const ExactConvex& piece, const Viewpoint& view) {
  OcclusionVolume out;
  const size_t n = piece.faces.size();
  std::vector<Facing> turned(n);
  std::vector<char> front(n);
  for (size_t f = 0; f < n; ++f) {
    turned[f] = facing(piece.faces[f], view);
    front[f] = turned[f] == Facing::Front;
    if (front[f]) out.front_faces.push_back(static_cast<int>(f));
  }
  if (out.front_faces.empty()) return out;
  std::vector<ExactPlane> planes;
  planes.reserve(out.front_faces.size() + piece.edges.size());
  for (const int f : out.front_faces) planes.push_back(piece.faces[static_cast<size_t>(f)]);
  // The viewpoint as E: a point, or the point at infinity the rays come from (−direction), so
  // that f(E) < 0 exactly for a front face f.
  const Vec3 e = view.at_infinity ? Vec3(-view.direction) : view.point;
  for (const auto& [j, k] : piece.edges) {
    if (front[static_cast<size_t>(j)] == front[static_cast<size_t>(k)]) continue;
    const ExactPlane& f = piece.faces[static_cast<size_t>(front[static_cast<size_t>(j)] ? j : k)];
    const int other = front[static_cast<size_t>(j)] ? k : j;
    const ExactPlane& g = piece.faces[static_cast<size_t>(other)];
    // The other face edge-on (g(E) = 0): the pencil is a positive multiple of g, so g itself,
    // which keeps its exact form (a plane through input points: clippers set an axis-aligned
    // one's crossing coordinate exactly).
    if (turned[static_cast<size_t>(other)] == Facing::EdgeOn)
      planes.push_back(g);
    else
      planes.push_back(ExactPlane::pencil(f, g, e, view.at_infinity));
  }
  out.clipper = ConvexClipper::from_planes(std::move(planes));
  return out;
}

OcclusionVolume silhouette_volume(const Body& body, std::span<const Facing> facing, const Viewpoint& view) {
  return volume_of(body, facing, view, {}, false);
}

OcclusionVolume triangle_occlusion_volume(const std::array<Vec3, 3>& t, const ExactPlane& plane,
                                          const Viewpoint& view) {
  OcclusionVolume out;
  out.front_faces.push_back(0);
  std::vector<ExactPlane> planes;
  planes.reserve(4);
  planes.push_back(plane);
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    out.silhouette.emplace_back(i, j);
    const std::optional<ExactPlane> edge_plane = silhouette_plane(t[static_cast<size_t>(i)], t[static_cast<size_t>(j)], view);
    if (!edge_plane) continue;
    // The third corner is off the plane: on it, the viewpoint would lie in the triangle's plane.
    const Sign side = side_of_plane(*edge_plane, t[static_cast<size_t>(k)]);
    if (side == Sign::Zero) throw InvalidInput("occlusion volume: the body is flat");
    planes.push_back(side == Sign::Positive ? *edge_plane : edge_plane->flipped());
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

namespace hedra {

std::vector<FaceTriangle> face_triangles_of(const Body& body, const std::vector<char>& wanted) {
  const auto& v = body.vertices();
  std::vector<FaceTriangle> out;
  out.reserve(body.triangles().size());
  for (const Triangle& t : body.triangles()) {
    if (!wanted.empty() && !wanted[static_cast<size_t>(t.face)]) continue;
    const std::array<Vec3, 3> c{v[static_cast<size_t>(t.v[0])], v[static_cast<size_t>(t.v[1])],
                                v[static_cast<size_t>(t.v[2])]};
    if (!collinear(c[0], c[1], c[2])) out.push_back({t.face, c});
  }
  return out;
}

std::vector<FaceTriangle> front_triangles_of(const Body& body, std::span<const Facing> faces,
                                             const Viewpoint& view) {
  const std::vector<int>& off_plane = body.faces_off_plane();
  std::vector<char> wanted(faces.size());
  for (size_t f = 0; f < wanted.size(); ++f) wanted[f] = faces[f] == Facing::Front;
  for (int f : off_plane) wanted[static_cast<size_t>(f)] = 1;
  std::vector<FaceTriangle> out = face_triangles_of(body, wanted);
  if (off_plane.empty()) return out;
  std::erase_if(out, [&](const FaceTriangle& t) {
    return body.face_off_plane(t.face) && facing(triangle_plane(t.corners), view) != Facing::Front;
  });
  return out;
}

std::optional<Body> exactly_planar_convex(const Body& body) {
  if (body.faces_off_plane().empty() || body.two_sided()) return std::nullopt;
  std::vector<std::vector<std::array<int, 3>>> splits(body.faces().size());
  for (int f : body.faces_off_plane()) {
    const Face& face = body.faces()[static_cast<size_t>(f)];
    if (face.loops.size() != 1) return std::nullopt;
    std::vector<Vec3> corners;
    corners.reserve(face.loops[0].size());
    for (int i : face.loops[0]) corners.push_back(body.vertices()[static_cast<size_t>(i)]);
    splits[static_cast<size_t>(f)] = convex_polygon_split(corners);
  }
  return exactly_planar_convex(body, splits);
}

std::optional<Body> exactly_planar_convex(const Body& body,
                                          std::span<const std::vector<std::array<int, 3>>> splits) {
  if (body.faces_off_plane().empty() || body.two_sided()) return std::nullopt;
  std::vector<Face> faces;
  faces.reserve(body.faces().size() + body.faces_off_plane().size());
  for (int f = 0; f < body.face_count(); ++f) {
    const Face& face = body.faces()[static_cast<size_t>(f)];
    if (!body.face_off_plane(f)) {
      faces.push_back(face);
      continue;
    }
    const std::vector<std::array<int, 3>>& split = splits[static_cast<size_t>(f)];
    if (face.loops.size() != 1 || split.empty()) return std::nullopt;
    const auto& q = face.loops[0];
    for (const auto& t : split)
      faces.push_back(Face{q[static_cast<size_t>(t[0])], q[static_cast<size_t>(t[1])], q[static_cast<size_t>(t[2])]});
  }
  Body split(body.vertices(), std::move(faces));
  if (certify_convexity(split) != ConvexityCertificate::Convex) return std::nullopt;
  return split;
}

ExactPlane triangle_plane(const std::array<Vec3, 3>& t) {
  size_t first = 0;
  for (size_t i = 1; i < 3; ++i)
    if (std::lexicographical_compare(t[i].data(), t[i].data() + 3, t[first].data(), t[first].data() + 3)) first = i;
  return ExactPlane::through(t[first], t[(first + 1) % 3], t[(first + 2) % 3]);
}

}  // namespace hedra
