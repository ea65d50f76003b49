// The hidden-line entry points and the picture plane; the pass itself is in
// hidden_lines.cpp and junction_lines.cpp (private header roberts_internal.h).
#include "hedra/visibility/roberts.h"

#include "hedra/clip/cyrus_beck.h"
#include "hedra/core/error.h"
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

HlrResult hidden_lines(std::span<const Body> bodies, const Camera& camera, const HlrOptions& options) {
  return hidden_lines(bodies, {}, camera, options);
}

HlrResult hidden_lines(std::span<const Body> bodies, std::span<const SmoothSurface> surfaces,
                       const Camera& camera, const HlrOptions& options) {
  camera.validate();
  check_options(options);
  if (!surfaces.empty() && surfaces.size() != bodies.size())
    throw InvalidInput("hidden lines: " + std::to_string(surfaces.size()) + " surfaces for " +
                       std::to_string(bodies.size()) + " bodies");
  return internal::Roberts(bodies, {}, surfaces, camera, options).run();
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
  scene.camera.validate();
  check_options(options);
  return internal::Roberts(bodies, names, surfaces, scene.camera, options).run();
}

}  // namespace hedra
