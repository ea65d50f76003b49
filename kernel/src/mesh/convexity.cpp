#include "hedra/mesh/convexity.h"

#include <cmath>
#include <numbers>

#include "hedra/core/face_geometry.h"
#include "hedra/core/predicates.h"
#include "hedra/core/tolerance.h"
#include "hedra/core/transform.h"

namespace hedra {
namespace {

std::vector<char> on_face_mask(size_t vertex_count, const Face& face) {
  std::vector<char> on(vertex_count, 0);
  for (const auto& loop : face.loops)
    for (int v : loop) on[v] = 1;
  return on;
}

}  // namespace

ConvexityReport convexity(const Body& body) {
  ConvexityReport report;
  const auto& vertices = body.vertices();
  for (int f = 0; f < body.face_count(); ++f) {
    std::vector<char> on = on_face_mask(vertices.size(), body.faces()[f]);
    for (size_t v = 0; v < vertices.size(); ++v) {
      if (on[v]) continue;
      if (body.face_side(f, vertices[v]) == Sign::Negative) {
        report.nonconvex_faces.push_back(f);
        break;
      }
    }
  }
  report.convex = report.nonconvex_faces.empty();
  return report;
}

bool is_convex(const Body& body) { return convexity(body).convex; }

ConvexityReport convexity(const std::vector<Vec3>& vertices, const std::vector<Face>& faces) {
  ConvexityReport report;
  bool any_off_plane = false;
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto& loop = faces[f].loops.at(0);
    Vec3 normal = newell_normal(vertices, loop);
    if (normal.isZero()) continue;  // a collinear face carries no plane
    std::array<int, 3> s = support_triple(vertices, loop, normal);
    if (s[2] < 0) continue;
    std::vector<char> on = on_face_mask(vertices.size(), faces[f]);
    int positive = 0, negative = 0;
    for (size_t v = 0; v < vertices.size(); ++v) {
      if (on[v]) continue;
      // orient3d is Positive on the outer side (loops run counter-clockwise from outside).
      Sign side = orient3d(vertices[s[0]], vertices[s[1]], vertices[s[2]], vertices[v]);
      if (side == Sign::Positive) ++positive;
      if (side == Sign::Negative) ++negative;
    }
    if (positive || negative) any_off_plane = true;
    if (positive) report.nonconvex_faces.push_back(static_cast<int>(f));
  }
  report.flat = !any_off_plane;
  report.convex = !report.flat && report.nonconvex_faces.empty();
  return report;
}

ConvexityReport convexity_by_rotation(const std::vector<Vec3>& vertices,
                                      const std::vector<Face>& faces, double zero_tolerance) {
  double scale = 0;
  for (const Vec3& p : vertices) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  if (zero_tolerance < 0) zero_tolerance = kRotationConvexityZero;
  const double zero = zero_tolerance * std::max(scale, 1e-300);

  ConvexityReport report;
  bool any_off_plane = false;
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto& loop = faces[f].loops.at(0);
    // Step 1: the first vertex of the face to the origin.
    const Vec3 p0 = vertices[loop[0]];
    Transform t = Transform::translation(-p0);
    // Step 2: rotate so that the edge p0 → p1 lies on the positive x axis: first about OZ to
    // bring it into the XOZ plane, then about OY to lay it on OX.
    Vec3 e = vertices[loop[1]] - p0;
    double az = std::atan2(e.y(), e.x()) * 180 / std::numbers::pi;
    t = t * Transform::rotation_z(-az);
    e = t.apply(vertices[loop[1]]);
    double ay = std::atan2(e.z(), e.x()) * 180 / std::numbers::pi;
    t = t * Transform::rotation_y(ay);
    // Step 3: rotate about OX so that the face lies in z = 0, choosing the vertex of the face
    // farthest from the x axis to fix the angle; its y becomes positive, so the face's
    // outward normal (counter-clockwise loop) becomes +z when the loop turns left there.
    Vec3 best = Vec3::Zero();
    for (int v : loop) {
      Vec3 q = t.apply(vertices[v]);
      if (q.y() * q.y() + q.z() * q.z() > best.y() * best.y() + best.z() * best.z()) best = q;
    }
    double ax = std::atan2(best.z(), best.y()) * 180 / std::numbers::pi;
    t = t * Transform::rotation_x(-ax);
    // The outward normal of the face after the rotations: +z or −z.
    Vec3 normal = t.apply_vector(newell_normal(vertices, faces[f].loops));
    const double outward_sign = normal.z() >= 0 ? 1.0 : -1.0;

    // Step 4: signs of z of the vertices not on the face.
    std::vector<char> on = on_face_mask(vertices.size(), faces[f]);
    int outer = 0, inner = 0;
    for (size_t v = 0; v < vertices.size(); ++v) {
      if (on[v]) continue;
      double z = t.apply(vertices[v]).z() * outward_sign;
      if (z > zero) ++outer;
      if (z < -zero) ++inner;
    }
    if (outer || inner) any_off_plane = true;
    if (outer) report.nonconvex_faces.push_back(static_cast<int>(f));
  }
  report.flat = !any_off_plane;
  report.convex = !report.flat && report.nonconvex_faces.empty();
  return report;
}

ConvexityReport convexity_by_rotation(const Body& body) {
  return convexity_by_rotation(body.vertices(), body.faces());
}

}  // namespace hedra
