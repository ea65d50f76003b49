// The hidden-line entry points and the picture plane; the pass itself is in
// hidden_lines.cpp and junction_lines.cpp (private header roberts_internal.h).
#include "hedra/visibility/roberts.h"

#include "hedra/clip/cyrus_beck.h"
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

std::optional<HiddenPart> hidden_part(const OcclusionVolume& volume, const Vec3& p1,
                                      const Vec3& p2) {
  if (!volume.clipper) return std::nullopt;
  const std::optional<SegmentPart> part = clip_segment_open(*volume.clipper, p1, p2);
  if (!part) return std::nullopt;
  return HiddenPart{part->lo.t, part->hi.t};
}

HlrResult hidden_lines(std::span<const Body> bodies, const Camera& camera, const HlrOptions& options) {
  camera.validate();
  return internal::Roberts(bodies, {}, camera, options).run();
}

HlrResult hidden_lines(const Scene& scene, const HlrOptions& options) {
  std::vector<Body> bodies;
  std::vector<std::string> names;
  for (const SceneBody* b : scene.visible_bodies()) {
    bodies.push_back(b->body);
    names.push_back(b->name);
  }
  scene.camera.validate();
  return internal::Roberts(bodies, names, scene.camera, options).run();
}

}  // namespace hedra
