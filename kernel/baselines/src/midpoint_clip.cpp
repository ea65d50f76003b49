#include "hedra/baselines/midpoint_clip.h"

#include <cmath>
#include <vector>

#include "hedra/core/error.h"

namespace hedra {
namespace {

struct Node {
  Vec3 p;
  double t;
};

Node midpoint(const Node& a, const Node& b) { return {(a.p + b.p) * 0.5, 0.5 * (a.t + b.t)}; }

// Same point as an end: no further progress is possible in double.
bool stalled(const Node& m, const Node& a, const Node& b) { return m.p == a.p || m.p == b.p; }

// Region: bool visible(const Vec3&), bool trivially_invisible(const Vec3&, const Vec3&).
template <class Region>
std::optional<MidpointClip> subdivide(const Region& region, const Vec3& p1, const Vec3& p2,
                                      double eps) {
  if (!(eps > 0) || !std::isfinite(eps))
    throw InvalidInput("midpoint subdivision needs a precision eps > 0");
  if (!p1.allFinite() || !p2.allFinite())
    throw InvalidInput("segment end point with a coordinate that is not finite");
  MidpointClip result;
  const Node first{p1, 0}, last{p2, 1};
  const bool v1 = region.visible(p1), v2 = region.visible(p2);
  if (v1 && v2) {  // trivially visible (a convex region contains the whole segment)
    result.start = p1;
    result.end = p2;
    return result;
  }
  if (region.trivially_invisible(p1, p2)) return std::nullopt;

  // Stage 1: a visible point, by subdivision; halves that are trivially invisible, or
  // shorter than ε, are dropped. Depth first from P1's side.
  std::optional<Node> seen;
  if (v1) seen = first;
  if (v2) seen = last;
  std::vector<std::pair<Node, Node>> stack{{first, last}};
  while (!seen && !stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    if ((b.p - a.p).norm() <= eps) continue;
    const Node m = midpoint(a, b);
    ++result.bisections;
    if (stalled(m, a, b)) continue;
    if (region.visible(m.p)) {
      seen = m;
      break;
    }
    if (!region.trivially_invisible(m.p, b.p)) stack.push_back({m, b});
    if (!region.trivially_invisible(a.p, m.p)) stack.push_back({a, m});
  }
  if (!seen) return std::nullopt;

  // Stage 2: from the visible point towards each end; the bracket keeps one invisible end
  // (`out`) and one visible end (`in`), so the end of the visible part stays inside it.
  const auto find_end = [&](Node out, Node in) {
    while ((in.p - out.p).norm() > eps) {
      const Node m = midpoint(out, in);
      ++result.bisections;
      if (stalled(m, out, in)) break;
      if (region.visible(m.p))
        in = m;
      else
        out = m;
    }
    return in;
  };
  const Node start = v1 ? first : find_end(first, *seen);
  const Node end = v2 ? last : find_end(last, *seen);
  result.start = start.p;
  result.t_start = start.t;
  result.end = end.p;
  result.t_end = end.t;
  return result;
}

struct BoxRegion {
  const ClipBox& box;
  bool visible(const Vec3& p) const { return outcode(box, p) == 0; }
  bool trivially_invisible(const Vec3& a, const Vec3& b) const {
    return hedra::trivially_invisible(outcode(box, a), outcode(box, b));
  }
};

struct FrustumRegion {
  const ViewFrustum& frustum;
  bool visible(const Vec3& p) const { return outcode(frustum, p) == 0; }
  bool trivially_invisible(const Vec3& a, const Vec3& b) const {
    return hedra::trivially_invisible(frustum, a, b);
  }
};

struct ClipperRegion {
  const ConvexClipper& clipper;
  bool visible(const Vec3& p) const { return clipper.contains(p); }
  bool trivially_invisible(const Vec3& a, const Vec3& b) const {
    for (const ExactPlane& f : clipper.planes())
      if (side_of_plane(f, a) == Sign::Negative && side_of_plane(f, b) == Sign::Negative)
        return true;
    return false;
  }
};

}  // namespace

std::optional<MidpointClip> midpoint_clip(const ClipBox& box, const Vec3& p1, const Vec3& p2,
                                          double eps) {
  box.validate();
  return subdivide(BoxRegion{box}, p1, p2, eps);
}

std::optional<MidpointClip> midpoint_clip(const ViewFrustum& frustum, const Vec3& p1,
                                          const Vec3& p2, double eps) {
  frustum.validate();
  return subdivide(FrustumRegion{frustum}, p1, p2, eps);
}

std::optional<MidpointClip> midpoint_clip(const ConvexClipper& clipper, const Vec3& p1,
                                          const Vec3& p2, double eps) {
  return subdivide(ClipperRegion{clipper}, p1, p2, eps);
}

}  // namespace hedra
