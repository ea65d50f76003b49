// The hidden-line entry points and the picture plane; the pass itself is in
// hidden_lines.cpp and junction_lines.cpp (private header roberts_internal.h).
#include "hedra/visibility/roberts.h"

#include <algorithm>
#include <array>
#include <map>
#include <numeric>

#include "hedra/clip/cyrus_beck.h"
#include "hedra/core/error.h"
#include "hedra/core/face_geometry.h"
#include "hedra/core/predicates.h"
#include "hedra/core/tolerance.h"
#include "hedra/decompose/split.h"
#include "visibility/roberts_internal.h"

namespace hedra {

// ---- Picture plane ----

PictureProjection::PictureProjection(const Camera& camera) {
  perspective_ = camera.projection == Camera::Projection::Perspective;
  eye_ = camera.eye;
  axis_ = (perspective_ ? Vec3(camera.target - camera.eye) : camera.direction).normalized();
  right_ = axis_.cross(camera.up).normalized();
  up_ = right_.cross(axis_);
}

Vec2 PictureProjection::project(const Vec3& p) const {
  if (!perspective_) return {p.dot(right_), p.dot(up_)};
  const Vec3 q = p - eye_;
  const double d = q.dot(axis_);
  return {q.dot(right_) / d, q.dot(up_) / d};
}

double PictureProjection::depth(const Vec3& p) const {
  return perspective_ ? (p - eye_).dot(axis_) : p.dot(axis_);
}

double HlrResult::length(LineKind kind, bool visible_parts) const {
  double sum = 0;
  for (const HlrSegment& s : visible_parts ? visible : hidden)
    if (s.kind == kind) sum += (s.b - s.a).norm();
  return sum;
}

double HlrResult::picture_length(LineKind kind) const {
  double sum = 0;
  for (const HlrSegment& s : visible)
    if (s.kind == kind) sum += (s.b2 - s.a2).norm();
  return sum;
}

namespace {

void check_options(const HlrOptions& options) {
  if (!(options.crease_angle >= 0 && options.crease_angle <= 180))
    throw InvalidInput("crease angle " + std::to_string(options.crease_angle) +
                       " is outside 0..180 degrees");
}

}  // namespace

std::optional<HiddenPart> hidden_part(const OcclusionVolume& volume, const Vec3& p1,
                                      const Vec3& p2) {
  if (!volume.clipper) return std::nullopt;
  const std::optional<SegmentPart> part = clip_segment_open(*volume.clipper, p1, p2);
  if (!part) return std::nullopt;
  return HiddenPart{part->lo.t, part->hi.t};
}

namespace {

std::string body_name(std::span<const std::string> names, size_t b) {
  return names.empty() ? "body " + std::to_string(b) : "body '" + names[b] + "'";
}

// A convex polygon `loop` of a two-sided face (an open surface's) clipped by the near plane:
// each corner's side decided exactly (corners on the plane kept), each crossing interpolated
// from the edge's end points in lexicographic order, so that the faces sharing an edge get the
// same point and the edge stays one edge of the surface. The crossings are rounded: the
// polygon is planar within kRoundingPlanarity of the face's scale. Repeated consecutive points
// are dropped; fewer than 3 left: none in front. Cost O(corners).
std::vector<Vec3> polygon_in_front(const std::vector<Vec3>& v, const std::vector<int>& loop, const Plane& near) {
  const size_t n = loop.size();
  std::vector<Vec3> kept;
  for (size_t i = 0; i < n; ++i) {
    const Vec3& p = v[static_cast<size_t>(loop[i])];
    const Vec3& q = v[static_cast<size_t>(loop[(i + 1) % n])];
    const Sign sp = side_of_plane(near, p), sq = side_of_plane(near, q);
    if (sp != Sign::Negative) kept.push_back(p);
    if ((sp == Sign::Positive && sq == Sign::Negative) || (sp == Sign::Negative && sq == Sign::Positive)) {
      const bool forward = std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3);
      const Vec3& a = forward ? p : q;
      const Vec3& b = forward ? q : p;
      const double da = near.value(a), db = near.value(b);
      kept.push_back(a + (da / (da - db)) * (b - a));
    }
  }
  std::vector<Vec3> polygon;
  for (const Vec3& p : kept)
    if (polygon.empty() || p != polygon.back()) polygon.push_back(p);
  while (polygon.size() > 1 && polygon.front() == polygon.back()) polygon.pop_back();
  if (polygon.size() < 3) polygon.clear();
  return polygon;
}

// The part of a two-sided body strictly in front of the near plane: each face of its front side
// clipped by polygon_in_front() (a polygon that rounding leaves not strictly convex: its fan of
// triangles, those with area), as one two-sided surface whose corners of equal coordinates are
// one vertex (neighbours share their crossings), so that the surface keeps its edges. None when
// no part in front has area. Where the pieces do not join into one surface, each is its own
// two-sided face. Cost O(n log n) for n corners.
std::vector<Body> face_in_front(const Body& body, const Plane& near) {
  const std::vector<Vec3>& v = body.vertices();
  const double planarity = kRoundingPlanarity * body.scale();
  std::vector<Vec3> points;
  std::map<std::array<double, 3>, int> index;
  std::vector<std::vector<int>> loops;
  std::vector<std::vector<Vec3>> polygons;
  const auto add = [&](const std::vector<Vec3>& polygon) {
    std::vector<int> loop;
    for (const Vec3& p : polygon) {
      const auto [it, added] = index.emplace(std::array<double, 3>{p.x(), p.y(), p.z()}, static_cast<int>(points.size()));
      if (added) points.push_back(p);
      loop.push_back(it->second);
    }
    loops.push_back(std::move(loop));
    polygons.push_back(polygon);
  };
  for (int f = 0; f < body.face_count() / 2; ++f) {
    const std::vector<Vec3> polygon = polygon_in_front(v, body.faces()[static_cast<size_t>(f)].loops[0], near);
    if (polygon.empty()) continue;
    std::vector<int> all(polygon.size());
    std::iota(all.begin(), all.end(), 0);
    if (convex_face_defect(polygon, all, planarity).empty()) {
      add(polygon);
      continue;
    }
    for (size_t i = 1; i + 1 < polygon.size(); ++i) {
      const std::vector<Vec3> t{polygon[0], polygon[i], polygon[i + 1]};
      if (convex_face_defect(t, {0, 1, 2}, 0).empty()) add(t);  // else no area: nothing there
    }
  }
  if (loops.empty()) return {};
  try {
    return {Body::two_sided_surface(points, loops, planarity)};
  } catch (const InvalidInput&) {
  }
  std::vector<Body> out;
  for (const std::vector<Vec3>& polygon : polygons) out.push_back(Body::two_sided_polygon(polygon, planarity));
  return out;
}

// The drawing of the bodies ∩ the near half-space of a perspective camera (camera.h's
// near_plane, the renderer's): bodies that reach the near plane are split by it exactly
// (hedra/decompose/split.h) and only their parts in front are drawn and hide; the cut itself
// (the edges of the caps, junction lines on them) is not a line of the scene and is not drawn.
// Parallel views and scenes wholly in front go straight to the Roberts pass.
// Cost: O(V) exact side tests, plus O(n log n) per split body of n triangles.
HlrResult clipped_hidden_lines(std::span<const Body> bodies, std::span<const std::string> names,
                               std::span<const SmoothSurface> surfaces, const Camera& camera,
                               const HlrOptions& options, const Eigen::AlignedBox3d& box) {
  camera.validate();
  check_options(options);
  if (!surfaces.empty() && surfaces.size() != bodies.size())
    throw InvalidInput("hidden lines: " + std::to_string(surfaces.size()) + " surfaces for " +
                       std::to_string(bodies.size()) + " bodies");
  if (camera.projection != Camera::Projection::Perspective)
    return internal::Roberts(bodies, names, surfaces, camera, options).run();
  // The eye inside or on a body is still an error: nothing of the scene could be seen.
  for (size_t b = 0; b < bodies.size(); ++b) {
    const Body& body = bodies[b];
    if (!body.bbox().contains(camera.eye)) continue;
    const Location where = body.classify(camera.eye);
    if (where != Location::Outside)
      throw InvalidInput(body_name(names, b) + ": the perspective eye lies " +
                         (where == Location::Inside ? "inside" : "on") + " the body");
  }
  const Plane near = camera.near_plane(box);
  std::vector<char> cut(bodies.size(), 0);
  bool any = false;
  for (size_t b = 0; b < bodies.size(); ++b) {
    for (const Vec3& v : bodies[b].vertices())
      if (side_of_plane(near, v) != Sign::Positive) {
        cut[b] = 1;
        any = true;
        break;
      }
  }
  if (!any) return internal::Roberts(bodies, names, surfaces, camera, options).run();

  std::vector<Body> kept;
  std::vector<std::string> kept_names;
  std::vector<SmoothSurface> kept_surfaces;  // the analytic surface does not depend on the cut
  std::vector<int> origin;
  for (size_t b = 0; b < bodies.size(); ++b) {
    std::vector<Body> parts;
    if (cut[b])
      parts = bodies[b].two_sided() ? face_in_front(bodies[b], near) : split(bodies[b], near).above;
    else
      parts.push_back(bodies[b]);
    for (Body& p : parts) {
      kept.push_back(std::move(p));
      if (!names.empty()) kept_names.push_back(names[b]);
      if (!surfaces.empty()) kept_surfaces.push_back(surfaces[b]);
      origin.push_back(static_cast<int>(b));
    }
  }
  // Messages of the pass name the input body (a split body's parts keep its name).
  HlrResult result = internal::Roberts(kept, kept_names, kept_surfaces, camera, options).run();
  // Drop the cut: segments with both ends on the near plane. Their points are rounded
  // intersections with that plane (a few ulps of the coordinates off it), so this is a
  // tolerance on constructed points, not a decision about the input.
  double m = camera.eye.cwiseAbs().maxCoeff();
  if (!box.isEmpty()) m = std::max({m, box.min().cwiseAbs().maxCoeff(), box.max().cwiseAbs().maxCoeff()});
  const double tol = 1e-12 * std::max(m, 1e-300);
  const auto on_near = [&](const Vec3& p) { return std::abs(near.value(p)) <= tol; };
  for (std::vector<HlrSegment>* list : {&result.visible, &result.hidden}) {
    std::erase_if(*list, [&](const HlrSegment& s) { return on_near(s.a) && on_near(s.b); });
    for (HlrSegment& s : *list) {
      const int b = s.body;
      s.body = origin[static_cast<size_t>(b)];
      if (s.other_body >= 0) s.other_body = origin[static_cast<size_t>(s.other_body)];
      if (cut[static_cast<size_t>(s.body)]) s.edge = -1;  // an edge of the split body, not of the input
    }
  }
  result.stats.bodies = static_cast<int>(bodies.size());
  return result;
}

}  // namespace

HlrResult hidden_lines(std::span<const Body> bodies, const Camera& camera, const HlrOptions& options) {
  return hidden_lines(bodies, {}, camera, options);
}

HlrResult hidden_lines(std::span<const Body> bodies, std::span<const SmoothSurface> surfaces,
                       const Camera& camera, const HlrOptions& options) {
  Eigen::AlignedBox3d box;
  box.setEmpty();
  for (const Body& b : bodies) box.extend(b.bbox());
  return clipped_hidden_lines(bodies, {}, surfaces, camera, options, box);
}

HlrResult hidden_lines(const Scene& scene, const HlrOptions& options) {
  std::vector<Body> bodies;
  std::vector<std::string> names;
  std::vector<SmoothSurface> surfaces;
  for (const SceneBody* b : scene.visible_bodies()) {
    bodies.push_back(b->body);
    names.push_back(b->name);
    surfaces.push_back(b->surface);
  }
  return clipped_hidden_lines(bodies, names, surfaces, scene.camera, options, scene.bbox());
}

}  // namespace hedra
