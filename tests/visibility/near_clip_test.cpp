// Hidden lines of a perspective scene that reaches behind the eye: the near plane (the
// renderer's, Camera::near_plane) clips it, against a brute-force reference that clips each
// edge to the near half-space and casts rays against the bodies ∩ that half-space.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hedra/core/error.h"
#include "hedra/core/primitives.h"
#include "hedra/core/transform.h"
#include "hedra/visibility/roberts.h"

namespace hedra {
namespace {

// Brute force: X (in front of the near plane) is hidden when the open segment from X to the eye
// passes through the open interior of some body ∩ {near ≥ 0}, over more than 1e-12 of the
// scene's size (slab test with every face plane and the near plane, in double).
class NearReference {
 public:
  NearReference(const std::vector<Body>& bodies, const Vec3& eye, const Plane& near)
      : eye_(eye), near_(near.normalized()) {
    for (const Body& b : bodies) {
      std::vector<Plane> planes{near_};
      for (int f = 0; f < b.face_count(); ++f) planes.push_back(b.plane(f).normalized());
      parts_.push_back(std::move(planes));
    }
  }

  bool hidden(const Vec3& x) const {
    const Vec3 r = eye_ - x;
    for (const auto& planes : parts_) {
      double lo = 0, hi = 1;
      bool empty = false;
      for (const Plane& p : planes) {
        const double f = p.value(x), g = p.normal().dot(r);
        if (g == 0) {
          if (f <= 0) empty = true;
          continue;
        }
        const double s = -f / g;
        if (g > 0) lo = std::max(lo, s);
        else hi = std::min(hi, s);
      }
      if (!empty && (hi - lo) * r.norm() > 1e-12 * 20) return true;
    }
    return false;
  }

  // Visible length of the part of p1p2 in front of the near plane: samples, transitions bisected.
  double visible_length(const Vec3& p1, const Vec3& p2) const {
    double t0 = 0, t1 = 1;
    const double f1 = near_.value(p1), f2 = near_.value(p2);
    if (f1 < 0 && f2 < 0) return 0;
    if (f1 < 0) t0 = f1 / (f1 - f2);
    if (f2 < 0) t1 = f1 / (f1 - f2);
    const auto at = [&](double t) { return Vec3(p1 + (p2 - p1) * t); };
    std::vector<double> ts;
    const int n = 2000;
    for (int k = 0; k <= n; ++k) ts.push_back(t0 + (t1 - t0) * std::clamp(k / double(n), 1e-12, 1 - 1e-12));
    double visible = 0, from = ts[0];
    bool state = !hidden(at(ts[0]));
    for (size_t k = 1; k < ts.size(); ++k) {
      const bool s = !hidden(at(ts[k]));
      if (s == state) continue;
      double lo = ts[k - 1], hi = ts[k];
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (!hidden(at(mid)) == state ? lo : hi) = mid;
      }
      if (state) visible += 0.5 * (lo + hi) - from;
      from = 0.5 * (lo + hi);
      state = s;
    }
    if (state) visible += t1 - from;
    return visible * (p2 - p1).norm();
  }

 private:
  Vec3 eye_;
  Plane near_;
  std::vector<std::vector<Plane>> parts_;
};

// The camera stands among the bodies: two beams pass beside the eye and reach behind it, a
// tilted slab crosses the eye plane below the eye, a wall and a block stand in front.
struct InsideScene {
  std::vector<Body> bodies;
  Camera camera = Camera::perspective({0, 0, 5}, {0, 0, 0}, 90, {0, 1, 0});
  InsideScene() {
    bodies.push_back(box({-3, -3, -1}, {3, 3, 0}));           // wall
    bodies.push_back(box({-1, -1, 0}, {-0.25, -0.25, 1.5}));  // block in front of the wall
    bodies.push_back(box({1.5, -0.5, -0.5}, {2.5, 0.5, 8}));  // beam through the eye plane
    bodies.push_back(box({-2.5, 0.2, 0.5}, {-1.2, 1.1, 7}));  // another one, hiding the block's corner
    bodies.push_back(box({-2, -2.2, 1}, {2, -1.6, 9}).transformed(
        Transform::rotation_x(7, Vec3(0, -1.9, 5))));         // tilted slab under the eye
  }
};

double box_scale(const std::vector<Body>& bodies, const Vec3& eye) {
  double m = eye.cwiseAbs().maxCoeff();
  for (const Body& b : bodies) m = std::max({m, b.bbox().min().cwiseAbs().maxCoeff(), b.bbox().max().cwiseAbs().maxCoeff()});
  return m;
}

TEST(NearClip, ASceneThroughTheEyePlaneMatchesTheBruteForceReference) {
  const InsideScene s;
  Eigen::AlignedBox3d box;
  box.setEmpty();
  for (const Body& b : s.bodies) box.extend(b.bbox());
  const Plane near = s.camera.near_plane(box);
  HlrOptions o;
  o.merge_coincident = false;
  o.junctions = false;
  const HlrResult r = hidden_lines(s.bodies, s.camera, o);  // no error: the scene is clipped
  ASSERT_FALSE(r.visible.empty());
  const double scale = box_scale(s.bodies, s.camera.eye);
  // Every drawn point is in front of the near plane (up to the rounding of clipped points).
  for (const HlrSegment& seg : r.visible) {
    EXPECT_GE(near.value(seg.a), -1e-12 * scale);
    EXPECT_GE(near.value(seg.b), -1e-12 * scale);
  }
  // Each drawn segment lies on one input edge (the cut through the bodies is not drawn); per
  // edge, the drawn length equals the reference's.
  const NearReference ref(s.bodies, s.camera.eye, near);
  std::vector<std::vector<double>> drawn(s.bodies.size());
  for (size_t b = 0; b < s.bodies.size(); ++b) drawn[b].assign(static_cast<size_t>(s.bodies[b].edge_count()), 0);
  for (const HlrSegment& seg : r.visible) {
    ASSERT_GE(seg.body, 0);
    const Body& body = s.bodies[static_cast<size_t>(seg.body)];
    int found = -1;
    for (int e = 0; e < body.edge_count() && found < 0; ++e) {
      const Vec3 p = body.vertices()[static_cast<size_t>(body.edges()[static_cast<size_t>(e)].v0)];
      const Vec3 q = body.vertices()[static_cast<size_t>(body.edges()[static_cast<size_t>(e)].v1)];
      const Vec3 d = (q - p).normalized();
      const auto on = [&](const Vec3& x) {
        const double t = (x - p).dot(d);
        return (x - p - t * d).norm() <= 1e-9 * scale && t >= -1e-9 * scale && t <= (q - p).norm() + 1e-9 * scale;
      };
      if (on(seg.a) && on(seg.b)) found = e;
    }
    ASSERT_GE(found, 0) << "a drawn segment on no edge of body " << seg.body << ": " << seg.a.transpose()
                        << " – " << seg.b.transpose();
    drawn[static_cast<size_t>(seg.body)][static_cast<size_t>(found)] += (seg.b - seg.a).norm();
  }
  int clipped = 0, partly_hidden = 0;
  for (size_t b = 0; b < s.bodies.size(); ++b) {
    const Body& body = s.bodies[b];
    for (int e = 0; e < body.edge_count(); ++e) {
      const Vec3 p = body.vertices()[static_cast<size_t>(body.edges()[static_cast<size_t>(e)].v0)];
      const Vec3 q = body.vertices()[static_cast<size_t>(body.edges()[static_cast<size_t>(e)].v1)];
      const double expected = ref.visible_length(p, q);
      EXPECT_NEAR(drawn[b][static_cast<size_t>(e)], expected, 1e-9 * scale) << "body " << b << " edge " << e;
      clipped += (near.value(p) < 0) != (near.value(q) < 0) && expected > 0;
      partly_hidden += expected > 1e-6 && expected < (q - p).norm() - 1e-6 && near.value(p) > 0 && near.value(q) > 0;
    }
  }
  EXPECT_GE(clipped, 4);        // edges cut by the near plane and still seen
  EXPECT_GE(partly_hidden, 2);  // and the occlusion is real
}

TEST(NearClip, TheEyeInsideABodyIsStillAnError) {
  const std::vector<Body> cube{box({0, 0, 0}, {1, 1, 1})};
  EXPECT_THROW(hidden_lines(cube, Camera::perspective({0.5, 0.5, 0.5}, {0, 0, 0}, 60)), InvalidInput);
}

TEST(NearClip, ASceneWhollyInFrontIsUnchanged) {
  // The near plane changes nothing (same segments, same edge indices) when no vertex reaches it.
  const std::vector<Body> bodies{box({0, 0, 0}, {2, 2, 2}), box({1, 1, 1}, {3, 4, 2.5})};
  const Camera c = Camera::perspective({8, -6, 7}, {1, 1, 1}, 50);
  const HlrResult r = hidden_lines(bodies, c);
  for (const HlrSegment& s : r.visible) EXPECT_TRUE(s.edge >= 0 || s.kind == LineKind::Junction);
  int with_edge = 0;
  for (const HlrSegment& s : r.visible) with_edge += s.edge >= 0;
  EXPECT_GT(with_edge, 0);
}

}  // namespace
}  // namespace hedra
