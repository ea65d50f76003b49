#include "hedra/clip/polyhedron_clipper.h"

#include <CGAL/Interval_nt.h>
#include <CGAL/Mpzf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <optional>

#include "core/filtered_sign.h"
#include "hedra/core/error.h"
#include "hedra/core/tolerance.h"
#include "hedra/mesh/convexity.h"

namespace hedra {
namespace {

constexpr int kLeafSize = 4;

void check_point(const Vec3& p) {
  if (p.allFinite() && p.cwiseAbs().maxCoeff() <= kMaxAbsCoordinate) return;
  char buf[160];
  std::snprintf(buf, sizeof buf, "segment end point (%.17g, %.17g, %.17g) %s", p.x(), p.y(), p.z(),
                p.allFinite() ? "is beyond ±1e101" : "is not finite");
  throw InvalidInput(buf);
}

using internal::filtered_sign;
using internal::to_sign;

// The side of edge a → b that the line p1 → p2 passes after the translation by
// δ = ε·e_x + ε²·e_y + ε³·e_z (ε → 0), when it meets the edge's line exactly
// (orient3d(p1, p2, a, b) = 0). orient3d(p1 + δ, p2 + δ, a, b) = orient3d(p1, p2, a, b)
// − δ·(w × d) with w = b − a, d = p2 − p1, so the sign is the first non-zero of −(w × d)_x,
// −(w × d)_y, −(w × d)_z; all vanish only for an edge parallel to the line (then its
// triangles are parallel to the line and never crossed). Antisymmetric in a, b, as the
// unperturbed sign, so the two triangles of an edge agree.
Sign perturbed_edge_sign(const Vec3& a, const Vec3& b, const Vec3& p1, const Vec3& p2) {
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const Sign s = filtered_sign([&](auto zero) {
      using T = decltype(zero);
      const T wj = T(b[j]) - T(a[j]), wk = T(b[k]) - T(a[k]);
      const T dj = T(p2[j]) - T(p1[j]), dk = T(p2[k]) - T(p1[k]);
      return wk * dj - wj * dk;  // −(w × d)_i
    });
    if (s != Sign::Zero) return s;
  }
  return Sign::Zero;
}

// The planes through the edges of triangle (a, b, c) and an axis its plane does not contain,
// each with the triangle on its inner side: their intersection meets the triangle's plane in
// the triangle, so they clip a line lying in that plane to the line ∩ triangle.
ConvexClipper edge_prism(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  int axes[3] = {0, 1, 2};
  std::sort(axes, axes + 3, [&](int i, int j) { return std::abs(n[i]) > std::abs(n[j]); });
  for (int k : axes) {
    // The exact normal's component k is the orientation of the projection along k.
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    if (orient2d(Vec2(a[i], a[j]), Vec2(b[i], b[j]), Vec2(c[i], c[j])) == Sign::Zero) continue;
    const Vec3 axis = Vec3::Unit(k);
    std::vector<ExactPlane> planes;
    const Vec3* v[3] = {&a, &b, &c};
    for (int e = 0; e < 3; ++e) {
      ExactPlane g = ExactPlane::through_direction(*v[e], *v[(e + 1) % 3], axis);
      if (side_of_plane(g, *v[(e + 2) % 3]) == Sign::Negative) g = g.flipped();
      planes.push_back(g);
    }
    return ConvexClipper::from_planes(std::move(planes));
  }
  throw InternalError("edge_prism: a degenerate triangle");
}

// The exact end of a segment (t = 0 or 1) as a SegmentEnd.
SegmentEnd segment_end(double t) { return {t, 0, nullptr}; }

// A crossing of the line with plane f strictly inside (0, 1) as a SegmentEnd.
SegmentEnd crossing_end(const ExactPlane& f, const Vec3& p1, const Vec3& p2) {
  const Crossing x = crossing(f, p1, p2);
  return {x.t, x.error, &f};
}

// The segment split at its events, each open interval between consecutive events classified.
struct Classification {
  std::deque<ExactPlane> planes;   // stable storage for the events' planes
  std::vector<SegmentEnd> bounds;  // t = 0, the events in order, t = 1
  std::vector<int> triangle;       // a triangle of each bound (−1 for the segment's ends)
  std::vector<char> inside;        // interval (bounds[i], bounds[i + 1]) in the body
  bool start_on = false, end_on = false;  // P1, P2 on the boundary

  bool bound_inside(size_t k) const {
    if (k == 0) return start_on || inside.front();
    if (k + 1 == bounds.size()) return end_on || inside.back();
    return true;  // an event lies on a triangle
  }
  ClipEnd end(size_t k) const {
    if (k == 0) return {0, -1, 0};
    if (k + 1 == bounds.size()) return {1, -1, 0};
    return {bounds[k].t, triangle[k], 0};
  }
};

struct Hit {
  SegmentEnd end;
  int triangle;
  int weight;  // signed crossing of the translated line (+1 leaving, −1 entering), or 0
};

// Steps 1–4 of the header comment for p1 ≠ p2.
Classification classify(const PolyhedronClipper& clipper, const Vec3& p1, const Vec3& p2) {
  Classification out;
  std::vector<int> candidates;
  clipper.ray_candidates(p1, p2, candidates);
  const auto& v = clipper.body().vertices();
  std::vector<Hit> hits;
  std::vector<int> coplanar;
  int beyond = 0;  // crossings of the translated line at t ≥ 1
  for (int tri : candidates) {
    const auto& ix = clipper.triangle(tri);
    const Vec3 &a = v[static_cast<size_t>(ix[0])], &b = v[static_cast<size_t>(ix[1])],
               &c = v[static_cast<size_t>(ix[2])];
    // Positive: outside the triangle's plane (the triangle runs counter-clockwise from outside).
    const Sign o1 = orient3d(a, b, c, p1), o2 = orient3d(a, b, c, p2);
    if (o1 == Sign::Zero && o2 == Sign::Zero) {
      coplanar.push_back(tri);
      continue;
    }
    // The side of each edge the line passes: all equal (or zero) where it meets the closed
    // triangle. Their exact sum is (P2 − P1)·n, so a common sign is the crossing's direction:
    // Positive leaves the body (n points outwards).
    Sign s[3] = {orient3d(p1, p2, a, b), orient3d(p1, p2, b, c), orient3d(p1, p2, c, a)};
    const bool positive = s[0] == Sign::Positive || s[1] == Sign::Positive || s[2] == Sign::Positive;
    const bool negative = s[0] == Sign::Negative || s[1] == Sign::Negative || s[2] == Sign::Negative;
    if (positive == negative) continue;  // misses the triangle (both false: not possible here)
    const Sign sigma = positive ? Sign::Positive : Sign::Negative;
    // Where on the line: o goes from Negative to Positive along the line when sigma > 0.
    enum { kBefore, kAtStart, kBetween, kAtEnd, kAfter } where;
    if (o1 == Sign::Zero) where = kAtStart;
    else if (o2 == Sign::Zero) where = kAtEnd;
    else if (o1 != o2) where = kBetween;
    else where = (o1 == Sign::Negative) == (sigma == Sign::Positive) ? kAfter : kBefore;
    if (where == kBefore) continue;
    // The translated line crosses the triangle when every zero edge sign perturbs to sigma.
    bool crossed = true;
    const Vec3* p[3] = {&a, &b, &c};
    for (int e = 0; e < 3 && crossed; ++e)
      if (s[e] == Sign::Zero) crossed = perturbed_edge_sign(*p[e], *p[(e + 1) % 3], p1, p2) == sigma;
    const int weight = crossed ? static_cast<int>(sigma) : 0;
    switch (where) {
      case kAtStart: out.start_on = true; break;  // counts for no interval of the segment
      case kAtEnd: out.end_on = true; beyond += weight; break;
      case kAfter: beyond += weight; break;
      default:
        out.planes.push_back(ExactPlane::through(a, b, c));
        hits.push_back({crossing_end(out.planes.back(), p1, p2), tri, weight});
    }
  }
  std::sort(hits.begin(), hits.end(), [&](const Hit& x, const Hit& y) {
    return compare_ends(x.end, y.end, p1, p2) == Sign::Negative;
  });
  // Events: equal parameters (a crossing through an edge or vertex) are one event.
  out.bounds.push_back(segment_end(0));
  out.triangle.push_back(-1);
  std::vector<int> weight{0};
  for (const Hit& h : hits) {
    if (out.bounds.size() > 1 && compare_ends(out.bounds.back(), h.end, p1, p2) == Sign::Zero) {
      weight.back() += h.weight;
      continue;
    }
    out.bounds.push_back(h.end);
    out.triangle.push_back(h.triangle);
    weight.push_back(h.weight);
  }
  out.bounds.push_back(segment_end(1));
  out.triangle.push_back(-1);
  // Winding of interval i: the crossings at or after bound i + 1, and beyond P2.
  const size_t gaps = out.bounds.size() - 1;
  out.inside.assign(gaps, 0);
  int winding = beyond;
  for (size_t i = gaps; i-- > 0;) {
    out.inside[i] = winding != 0;
    winding += weight[i];  // bound i's crossings (bound 0: none counted)
  }
  // Intervals on a face: those a coplanar triangle's own interval overlaps.
  for (int tri : coplanar) {
    const auto& ix = clipper.triangle(tri);
    const ConvexClipper prism = edge_prism(v[static_cast<size_t>(ix[0])],
                                           v[static_cast<size_t>(ix[1])],
                                           v[static_cast<size_t>(ix[2])]);
    const std::optional<ClipPart> part = clip_segment(prism, p1, p2);
    if (!part) continue;
    const auto as_end = [&](const ClipEnd& e) {
      return e.plane < 0 ? segment_end(e.t) : crossing_end(prism.plane(e.plane), p1, p2);
    };
    const SegmentEnd lo = as_end(part->start), hi = as_end(part->end);
    if (part->start.plane < 0 && part->start.t == 0) out.start_on = true;
    if (part->end.plane < 0 && part->end.t == 1) out.end_on = true;
    if (part->point) continue;  // a touching point is an event (or a segment end) already
    for (size_t i = 0; i < gaps; ++i)
      if (!out.inside[i] && compare_ends(out.bounds[i], hi, p1, p2) == Sign::Negative &&
          compare_ends(lo, out.bounds[i + 1], p1, p2) == Sign::Negative)
        out.inside[i] = 1;
  }
  return out;
}

// A point other than p, so that the line through both classifies p.
Vec3 other_point(const Vec3& p) { return {p.x() + (std::abs(p.x()) + 1), p.y(), p.z()}; }

bool point_inside(const PolyhedronClipper& clipper, const Vec3& p) {
  return classify(clipper, p, other_point(p)).bound_inside(0);
}

}  // namespace

PolyhedronClipper::PolyhedronClipper(const Body& body) : body_(body) {
  if (body.two_sided())
    throw InvalidInput("an open surface (two-sided) has no interior to clip against");
  const auto& v = body.vertices();
  triangles_.reserve(body.triangles().size());
  std::vector<Vec3> centroids;
  centroids.reserve(body.triangles().size());
  for (const Triangle& t : body.triangles()) {
    triangles_.push_back(t.v);
    centroids.push_back((v[static_cast<size_t>(t.v[0])] + v[static_cast<size_t>(t.v[1])] +
                         v[static_cast<size_t>(t.v[2])]) /
                        3);
  }
  for (const Vec3& p : v) extent_ = std::max(extent_, p.cwiseAbs().maxCoeff());
  order_.resize(triangles_.size());
  for (size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<int>(i);
  nodes_.reserve(2 * triangles_.size() / kLeafSize + 2);
  if (!triangles_.empty()) build(0, static_cast<int>(order_.size()), centroids);
}

int PolyhedronClipper::build(int begin, int end, const std::vector<Vec3>& centroids) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  Node node;
  for (int k = 0; k < 3; ++k) {
    node.lo[k] = std::numeric_limits<double>::infinity();
    node.hi[k] = -std::numeric_limits<double>::infinity();
  }
  Eigen::AlignedBox3d cbox;
  const auto& v = body_.vertices();
  for (int i = begin; i < end; ++i) {
    const int t = order_[static_cast<size_t>(i)];
    for (int corner : triangles_[static_cast<size_t>(t)]) {
      const Vec3& p = v[static_cast<size_t>(corner)];
      for (int k = 0; k < 3; ++k) {
        node.lo[k] = std::min(node.lo[k], p[k]);
        node.hi[k] = std::max(node.hi[k], p[k]);
      }
    }
    cbox.extend(centroids[static_cast<size_t>(t)]);
  }
  if (end - begin <= kLeafSize) {
    node.first = begin;
    node.count = end - begin;
    nodes_[static_cast<size_t>(index)] = node;
    return index;
  }
  // Median split of the centroids along the box's longest axis: depth O(log n).
  int axis;
  cbox.sizes().maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int x, int y) {
                     return centroids[static_cast<size_t>(x)][axis] <
                            centroids[static_cast<size_t>(y)][axis];
                   });
  build(begin, mid, centroids);
  node.first = build(mid, end, centroids);
  node.count = 0;
  nodes_[static_cast<size_t>(index)] = node;
  return index;
}

ExactPlane PolyhedronClipper::plane(int triangle) const {
  const auto& ix = triangles_[static_cast<size_t>(triangle)];
  const auto& v = body_.vertices();
  return ExactPlane::through(v[static_cast<size_t>(ix[0])], v[static_cast<size_t>(ix[1])],
                             v[static_cast<size_t>(ix[2])]);
}

void PolyhedronClipper::ray_candidates(const Vec3& p1, const Vec3& p2,
                                       std::vector<int>& out) const {
  if (nodes_.empty()) return;
  const Vec3 d = p2 - p1;
  // The exact ray's points inside a box are within about u·(|p1| + extent) of the rounded
  // ray's; the slab arithmetic adds a few more roundings of that size. 1e-10 covers them all
  // with a wide margin (culling only: a larger margin only costs time).
  const double margin =
      1e-10 * (extent_ + p1.cwiseAbs().maxCoeff() + p2.cwiseAbs().maxCoeff()) +
      std::numeric_limits<double>::min();
  double inv[3];
  for (int k = 0; k < 3; ++k) inv[k] = d[k] != 0 ? 1 / d[k] : 0;
  const auto hits_box = [&](const Node& n) {
    double t0 = 0, t1 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      const double lo = n.lo[k] - margin, hi = n.hi[k] + margin;
      if (d[k] == 0) {
        if (p1[k] < lo || p1[k] > hi) return false;
        continue;
      }
      double a = (lo - p1[k]) * inv[k], b = (hi - p1[k]) * inv[k];
      if (a > b) std::swap(a, b);
      // Relative slack for the roundings of the slab parameters themselves.
      a -= std::abs(a) * 1e-12;
      b += std::abs(b) * 1e-12;
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      if (t0 > t1) return false;
    }
    return true;
  };
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[static_cast<size_t>(stack[--top])];
    if (!hits_box(n)) continue;
    if (n.count > 0) {
      for (int i = n.first; i < n.first + n.count; ++i) out.push_back(order_[static_cast<size_t>(i)]);
      continue;
    }
    const int self = static_cast<int>(&n - nodes_.data());
    stack[top++] = n.first;   // right child
    stack[top++] = self + 1;  // left child
  }
}

std::vector<ClipPart> clip_segment(const PolyhedronClipper& clipper, const Vec3& p1,
                                   const Vec3& p2) {
  check_point(p1);
  check_point(p2);
  if (p1 == p2) {
    if (!point_inside(clipper, p1)) return {};
    return {ClipPart{{0, -1, 0}, {1, -1, 0}, true}};
  }
  const Classification c = classify(clipper, p1, p2);
  std::vector<ClipPart> parts;
  const size_t gaps = c.inside.size();
  size_t open = 0;
  for (size_t k = 0; k <= gaps; ++k) {
    const bool left = k > 0 && c.inside[k - 1], right = k < gaps && c.inside[k];
    if (!left && right) {
      open = k;
    } else if (left && !right) {
      parts.push_back({c.end(open), c.end(k), false});
    } else if (!left && !right && c.bound_inside(k)) {
      parts.push_back({c.end(k), c.end(k), true});
    }
  }
  return parts;
}

std::vector<ClipPart> clip_segment_outside(const PolyhedronClipper& clipper, const Vec3& p1,
                                           const Vec3& p2) {
  check_point(p1);
  check_point(p2);
  if (p1 == p2) {
    if (point_inside(clipper, p1)) return {};
    return {ClipPart{{0, -1, 0}, {1, -1, 0}, true}};
  }
  const Classification c = classify(clipper, p1, p2);
  std::vector<ClipPart> parts;
  const size_t gaps = c.inside.size();
  for (size_t i = 0; i < gaps; ++i) {
    if (c.inside[i]) continue;
    size_t j = i;
    while (j + 1 < gaps && !c.inside[j + 1]) ++j;
    parts.push_back({c.end(i), c.end(j + 1), false});
    i = j;
  }
  return parts;
}

Vec3 end_point(const PolyhedronClipper& clipper, const ClipEnd& end, const Vec3& p1,
               const Vec3& p2) {
  if (end.plane < 0) return end.t == 0 ? p1 : (end.t == 1 ? p2 : point_at(p1, p2, end.t));
  return crossing_point(clipper.plane(end.plane), p1, p2);
}

// ---- SolidClipper ----

SolidClipper::SolidClipper(std::span<const Body> bodies) {
  for (const Body& body : bodies) {
    if (is_convex(body))
      convex_.emplace_back(body);
    else
      polyhedra_.emplace_back(body);
  }
}

namespace {

// A part of one source with its ends' planes kept alive for exact comparisons.
struct SourcedPart {
  ClipPart part;
  SegmentEnd start, end;
};

}  // namespace

std::vector<ClipPart> SolidClipper::clip(const Vec3& p1, const Vec3& p2) const {
  if (polyhedra_.empty()) return clip_segment(convex_, p1, p2);  // convex pieces, as ever
  std::deque<ExactPlane> planes;  // polyhedron planes, stable while parts are compared
  std::vector<SourcedPart> parts;
  const auto sourced = [&](const ClipEnd& e) -> SegmentEnd {
    if (e.plane < 0) return segment_end(e.t);
    if (e.piece < convex_count()) return crossing_end(convex_[static_cast<size_t>(e.piece)].plane(e.plane), p1, p2);
    planes.push_back(polyhedra_[static_cast<size_t>(e.piece - convex_count())].plane(e.plane));
    return crossing_end(planes.back(), p1, p2);
  };
  const auto add = [&](ClipPart part, int piece) {
    part.start.piece = part.end.piece = piece;
    parts.push_back({part, sourced(part.start), sourced(part.end)});
  };
  for (size_t k = 0; k < convex_.size(); ++k)
    if (std::optional<ClipPart> part = clip_segment(convex_[k], p1, p2))
      add(*part, static_cast<int>(k));
  for (size_t k = 0; k < polyhedra_.size(); ++k)
    for (const ClipPart& part : clip_segment(polyhedra_[k], p1, p2))
      add(part, convex_count() + static_cast<int>(k));
  if (convex_.size() + polyhedra_.size() < 2) {
    std::vector<ClipPart> out;
    for (const SourcedPart& s : parts) out.push_back(s.part);
    return out;
  }
  const auto cmp = [&](const SegmentEnd& a, const SegmentEnd& b) {
    return compare_ends(a, b, p1, p2);
  };
  // As clip_segment of convex pieces: order by start (exact), then a part that starts at or
  // before the current end continues the current part.
  std::stable_sort(parts.begin(), parts.end(), [&](const SourcedPart& a, const SourcedPart& b) {
    return cmp(a.start, b.start) == Sign::Negative;
  });
  std::vector<SourcedPart> merged;
  for (const SourcedPart& s : parts) {
    if (!merged.empty() && cmp(s.start, merged.back().end) != Sign::Positive) {
      SourcedPart& back = merged.back();
      if (cmp(s.end, back.end) == Sign::Positive) {
        back.end = s.end;
        back.part.end = s.part.end;
      }
      back.part.point = p1 == p2 || cmp(back.start, back.end) == Sign::Zero;
      if (back.part.end.t < back.part.start.t) back.part.end.t = back.part.start.t;
    } else {
      merged.push_back(s);
    }
  }
  std::vector<ClipPart> out;
  out.reserve(merged.size());
  for (const SourcedPart& s : merged) out.push_back(s.part);
  return out;
}

std::vector<ClipPart> SolidClipper::clip_outside(const Vec3& p1, const Vec3& p2) const {
  if (convex_.empty() && polyhedra_.size() == 1) return clip_segment_outside(polyhedra_[0], p1, p2);
  if (polyhedra_.empty()) return clip_segment_outside(convex_, p1, p2);
  const std::vector<ClipPart> inside = clip(p1, p2);
  const ClipEnd first{0, -1, 0}, last{1, -1, 0};
  if (p1 == p2) {
    if (inside.empty()) return {ClipPart{first, last, true}};
    return {};
  }
  std::deque<ExactPlane> planes;
  const auto as_end = [&](const ClipEnd& e) -> SegmentEnd {
    if (e.plane < 0) return segment_end(e.t);
    if (e.piece < convex_count()) return crossing_end(convex_[static_cast<size_t>(e.piece)].plane(e.plane), p1, p2);
    planes.push_back(polyhedra_[static_cast<size_t>(e.piece - convex_count())].plane(e.plane));
    return crossing_end(planes.back(), p1, p2);
  };
  std::vector<ClipPart> outside;
  ClipEnd from = first;
  for (const ClipPart& part : inside) {
    if (part.point) continue;  // removing a point changes nothing in the closure
    if (compare_ends(as_end(from), as_end(part.start), p1, p2) == Sign::Negative)
      outside.push_back({from, part.start, false});
    from = part.end;
  }
  if (compare_ends(as_end(from), as_end(last), p1, p2) == Sign::Negative)
    outside.push_back({from, last, false});
  return outside;
}

Vec3 SolidClipper::end_point(const ClipEnd& end, const Vec3& p1, const Vec3& p2) const {
  if (end.plane < 0) return end.t == 0 ? p1 : (end.t == 1 ? p2 : point_at(p1, p2, end.t));
  if (end.piece < convex_count()) return hedra::end_point(convex_, end, p1, p2);
  return hedra::end_point(polyhedra_[static_cast<size_t>(end.piece - convex_count())], end, p1, p2);
}

}  // namespace hedra
