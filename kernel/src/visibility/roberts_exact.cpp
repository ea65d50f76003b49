// The exact parts of Roberts hidden-line removal (roberts_exact.h): the course's (t, a) oracle
// (docs/algorithms.md §6.2), the rational path for segments lying in an edge-on internal cut plane,
// and junction lines. Numbers are CGAL::Mpzf (exact sums and products of doubles); points are
// homogeneous (X, W) with W > 0, so a crossing of an input edge with an input plane is exact
// without a division, and parameters are fractions compared by cross-multiplication.
#include "visibility/roberts_exact.h"

#include <CGAL/Gmpq.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Mpzf.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <cmath>
#include <memory>
#include <optional>
#include <unordered_map>

#include "core/exact_plane.h"
#include "hedra/core/error.h"

namespace hedra::detail {
namespace {

using Q = CGAL::Mpzf;

int sgn(const Q& x) { return static_cast<int>(x.sign()); }

// Enclosing intervals of the four homogeneous numbers of a plane or a point (filter).
using Bounds = std::array<std::pair<double, double>, 4>;

// A plane f(X, W) = n·X + k·W, inner side positive, exactly the ExactPlane's affine function.
struct HPlane {
  std::array<Q, 3> n{Q(0), Q(0), Q(0)};
  Q k{0};
  Bounds bounds{};  // of n and k, for the interval filter of signs
};

// A point (X, W), W > 0.
struct HPoint {
  std::array<Q, 3> x{Q(0), Q(0), Q(0)};
  Q w{1};
};

HPlane hplane(const ExactPlane& f) {
  HPlane h;
  const std::array<Q, 4> c = internal::exact_coefficients(f);
  for (int i = 0; i < 3; ++i) h.n[static_cast<size_t>(i)] = c[static_cast<size_t>(i)];
  h.k = c[3];
  for (int i = 0; i < 3; ++i) h.bounds[static_cast<size_t>(i)] = CGAL::to_interval(h.n[static_cast<size_t>(i)]);
  h.bounds[3] = CGAL::to_interval(h.k);
  return h;
}

HPoint hpoint(const Vec3& p) {
  HPoint h;
  for (int i = 0; i < 3; ++i) h.x[i] = Q(p[i]);
  h.w = Q(1);
  return h;
}

// W·f(point): the sign of f at the point, since W > 0.
Q eval(const HPlane& f, const HPoint& p) {
  return f.n[0] * p.x[0] + f.n[1] * p.x[1] + f.n[2] * p.x[2] + f.k * p.w;
}

Q eval_direction(const HPlane& f, const Vec3& d) {
  return f.n[0] * Q(d.x()) + f.n[1] * Q(d.y()) + f.n[2] * Q(d.z());
}

// g·V_j of the course: the value of plane j at the viewer vector g pointing to the viewer,
// (−direction, 0) or (eye, 1).
Q viewer_value(const HPlane& f, const Viewpoint& view) {
  if (view.at_infinity) return Q(0) - eval_direction(f, view.direction);
  return eval(f, hpoint(view.point));
}

Bounds bounds_of(const HPoint& p) {
  return {CGAL::to_interval(p.x[0]), CGAL::to_interval(p.x[1]), CGAL::to_interval(p.x[2]),
          CGAL::to_interval(p.w)};
}

// sgn(eval(f, p)), decided by interval arithmetic when it can (almost always) and exactly
// otherwise: the same sign either way.
int sign_at(const HPlane& f, const HPoint& p, const Bounds& pb) {
  {
    CGAL::Protect_FPU_rounding<true> guard;
    using I = CGAL::Interval_nt_advanced;
    I v = I(f.bounds[0]) * I(pb[0]);
    for (size_t i = 1; i < 4; ++i) v += I(f.bounds[i]) * I(pb[i]);
    if (v.inf() > 0) return 1;
    if (v.sup() < 0) return -1;
  }
  return sgn(eval(f, p));
}

// A parameter num/den on a segment, den > 0.
struct Frac {
  Q num{0}, den{1};
};

Frac frac(Q num, Q den) {
  if (sgn(den) < 0) {
    num = Q(0) - num;
    den = Q(0) - den;
  }
  return {std::move(num), std::move(den)};
}

int cmp(const Frac& a, const Frac& b) { return sgn(a.num * b.den - b.num * a.den); }

double to_double(const Q& num, const Q& den) {
  // Through Gmpq: correctly rounded, and no overflow of the parts on their own.
  return CGAL::to_double(CGAL::Gmpq(num) / CGAL::Gmpq(den));
}

double to_double(const Frac& f) { return to_double(f.num, f.den); }

struct Interval {
  Frac lo, hi;
};

// The open part of segment P1P2 strictly inside the convex set of `planes`: clip_segment_open
// (hedra/clip/cyrus_beck.h) for end points that are exact homogeneous points (junction ends,
// facet crossings) rather than doubles, so every value here is exact. Values: v1 = F1/W1, v2 = F2/W2; a crossing at t = F1·W2 / (F1·W2 − F2·W1).
std::optional<Interval> clip_open_exact(std::span<const HPlane> planes, const HPoint& p1,
                                        const HPoint& p2) {
  Frac lo{Q(0), Q(1)}, hi{Q(1), Q(1)};
  const Bounds b1 = bounds_of(p1), b2 = bounds_of(p2);
  for (const HPlane& f : planes) {
    // Signs first (filtered); the exact values only for a plane the segment crosses.
    const int s1 = sign_at(f, p1, b1), s2 = sign_at(f, p2, b2);
    if (s1 <= 0 && s2 <= 0) return std::nullopt;  // outside, or on the plane: nothing strictly in
    if (s1 > 0 && s2 > 0) continue;
    const Q f1 = eval(f, p1), f2 = eval(f, p2);
    const Q a = f1 * p2.w, b = f2 * p1.w;
    const Frac t = frac(a, a - b);
    if (s1 <= 0) {
      if (cmp(t, lo) > 0) lo = t;
    } else if (cmp(t, hi) < 0) {
      hi = t;
    }
  }
  if (cmp(lo, hi) >= 0) return std::nullopt;
  return Interval{lo, hi};
}

// The course's brute force on constraints α + β·t + γ·a > 0 (with t ≥ 0, t ≤ 1, a ≥ 0 added):
// intersect every pair of boundary lines, keep the intersections satisfying every constraint
// (closed), and return (min t, max t) when they span a region of positive area.
struct Constraint {
  Q alpha, beta, gamma;
};

std::optional<Interval> brute_force(std::vector<Constraint> lines) {
  lines.push_back({Q(0), Q(1), Q(0)});   // t ≥ 0
  lines.push_back({Q(1), Q(-1), Q(0)});  // 1 − t ≥ 0
  lines.push_back({Q(0), Q(0), Q(1)});   // a ≥ 0
  // A constraint without t and a is a constant: it either always holds or empties the region.
  std::vector<Constraint> kept;
  for (Constraint& c : lines) {
    if (sgn(c.beta) == 0 && sgn(c.gamma) == 0) {
      if (sgn(c.alpha) <= 0) return std::nullopt;
      continue;
    }
    kept.push_back(std::move(c));
  }
  struct Vertex {
    Q t, a, d;  // (t, a) = (T/D, A/D), D > 0
  };
  std::vector<Vertex> feasible;
  const size_t n = kept.size();
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      const Constraint &ci = kept[i], &cj = kept[j];
      Q d = ci.beta * cj.gamma - cj.beta * ci.gamma;
      if (sgn(d) == 0) continue;  // parallel boundary lines
      Q t = cj.alpha * ci.gamma - ci.alpha * cj.gamma;
      Q a = cj.beta * ci.alpha - ci.beta * cj.alpha;
      if (sgn(d) < 0) {
        d = Q(0) - d;
        t = Q(0) - t;
        a = Q(0) - a;
      }
      bool ok = true;
      for (size_t k = 0; k < n && ok; ++k) {
        const Constraint& c = kept[k];
        ok = sgn(c.alpha * d + c.beta * t + c.gamma * a) >= 0;
      }
      if (ok) feasible.push_back({std::move(t), std::move(a), std::move(d)});
    }
  }
  if (feasible.size() < 3) return std::nullopt;
  // Positive area: three feasible vertices not on one line.
  const Vertex& v0 = feasible[0];
  const Vertex* v1 = nullptr;
  bool area = false;
  for (const Vertex& v : feasible) {
    if (!v1) {
      if (sgn(v.t * v0.d - v0.t * v.d) != 0 || sgn(v.a * v0.d - v0.a * v.d) != 0) v1 = &v;
      continue;
    }
    const Q det = v0.t * (v1->a * v.d - v.a * v1->d) - v0.a * (v1->t * v.d - v.t * v1->d) +
                  v0.d * (v1->t * v.a - v.t * v1->a);
    if (sgn(det) != 0) {
      area = true;
      break;
    }
  }
  if (!area) return std::nullopt;
  Frac lo{feasible[0].t, feasible[0].d}, hi = lo;
  for (const Vertex& v : feasible) {
    const Frac f{v.t, v.d};
    if (cmp(f, lo) < 0) lo = f;
    if (cmp(f, hi) > 0) hi = f;
  }
  return Interval{lo, hi};
}

// The (t, a) system of a convex set (planes) for segment P1P2, scaled by W1·W2 > 0:
// h_j(P(t)) = v1 + t·(v2 − v1) with v = F/W, and the viewer term a·g·V_j.
std::optional<Interval> hidden_brute_force(std::span<const HPlane> planes, const Viewpoint& view,
                                           const HPoint& p1, const HPoint& p2) {
  std::vector<Constraint> lines;
  lines.reserve(planes.size() + 3);
  const Q w12 = p1.w * p2.w;
  for (const HPlane& f : planes) {
    const Q a = eval(f, p1) * p2.w, b = eval(f, p2) * p1.w;
    lines.push_back({a, b - a, viewer_value(f, view) * w12});
  }
  return brute_force(std::move(lines));
}

std::vector<HPlane> hplanes(std::span<const ExactPlane> planes) {
  std::vector<HPlane> out;
  out.reserve(planes.size());
  for (const ExactPlane& f : planes) out.push_back(hplane(f));
  return out;
}

}  // namespace

struct ExactPlaneCache::Impl {
  std::unordered_map<const void*, std::vector<HPlane>> planes;
};
ExactPlaneCache::ExactPlaneCache() : impl(std::make_unique<Impl>()) {}
ExactPlaneCache::~ExactPlaneCache() = default;

namespace {

// hplanes(planes), from the cache when there is one (keyed by the occluder's plane list).
const std::vector<HPlane>& cached_hplanes(const std::vector<ExactPlane>& planes,
                                          ExactPlaneCache* cache, std::vector<HPlane>& local) {
  if (!cache) return local = hplanes(planes);
  auto [it, added] = cache->impl->planes.try_emplace(&planes);
  if (added) it->second = hplanes(planes);
  return it->second;
}

// The visible parts of P1P2 (fractions) against the candidates, exactly. A candidate that hides
// the whole segment ends the search (the rest cannot change the answer).
std::vector<Interval> visible_fracs(const HPoint& p1, const HPoint& p2, const Candidates& cand,
                                    const Viewpoint& view, bool brute,
                                    ExactPlaneCache* cache = nullptr) {
  std::vector<Interval> hidden;
  std::vector<HPlane> local;
  const Frac start{Q(0), Q(1)}, end{Q(1), Q(1)};
  for (const PieceOccluder* o : cand.pieces) {
    std::optional<Interval> part;
    if (brute) {
      part = hidden_brute_force(cached_hplanes(*o->faces, cache, local), view, p1, p2);
    } else {
      if (!o->volume) continue;
      part = clip_open_exact(cached_hplanes(o->volume->planes(), cache, local), p1, p2);
    }
    if (part) {
      if (cmp(part->lo, start) <= 0 && cmp(part->hi, end) >= 0) return {};
      hidden.push_back(std::move(*part));
    }
  }
  for (const FacetOccluder* f : cand.facets) {
    const HPlane c = hplane(f->plane);
    if (sgn(eval(c, p1)) != 0 || sgn(eval(c, p2)) != 0) continue;  // not in the facet's plane
    if (auto part = hidden_brute_force(hplanes(f->bounds), view, p1, p2))
      hidden.push_back(std::move(*part));
  }
  std::sort(hidden.begin(), hidden.end(),
            [](const Interval& a, const Interval& b) { return cmp(a.lo, b.lo) < 0; });
  // Complement of the union; hidden parts that touch leave no visible point.
  std::vector<Interval> visible;
  Frac from{Q(0), Q(1)};
  for (const Interval& h : hidden) {
    if (cmp(h.lo, from) > 0) visible.push_back({from, h.lo});
    if (cmp(h.hi, from) > 0) from = h.hi;
  }
  const Frac one{Q(1), Q(1)};
  if (cmp(from, one) < 0) visible.push_back({from, one});
  return visible;
}

// Exact point of P1P2 at t = N/D, rounded: ((D − N)·W2·X1 + N·W1·X2) / (W1·W2·D).
Vec3 point_at(const HPoint& p1, const HPoint& p2, const Frac& t) {
  const Q c1 = (t.den - t.num) * p2.w, c2 = t.num * p1.w, w = p1.w * p2.w * t.den;
  Vec3 out;
  for (int i = 0; i < 3; ++i) out[i] = to_double(c1 * p1.x[i] + c2 * p2.x[i], w);
  return out;
}

Vec3 rounded(const HPoint& p) {
  Vec3 out;
  for (int i = 0; i < 3; ++i) out[i] = to_double(p.x[i], p.w);
  return out;
}

// ---- Junction lines ----

// Order of two points of the junction line along its coordinate `axis`.
int cmp_along(const HPoint& a, const HPoint& b, int axis) {
  return sgn(a.x[axis] * b.w - b.x[axis] * a.w);
}

struct Span {
  HPoint lo, hi;  // lo before hi along the axis
};

// Closure of L ∩ relint(face), L = face plane ∩ plane g, as sorted disjoint spans. The line is
// pushed infinitesimally to the negative side of g (vertices on g count as positive), so its
// crossings with the face's loops alternate in and out; boundary edges lying on L are removed.
std::vector<Span> face_spans(const Body& body, int face, const ExactPlane& g, const HPlane& hg,
                             int axis) {
  const auto& v = body.vertices();
  std::vector<HPoint> crossings;
  std::vector<Span> on_line;
  for (const auto& loop : body.faces()[static_cast<size_t>(face)].loops) {
    const size_t m = loop.size();
    std::vector<Sign> side(m);
    for (size_t i = 0; i < m; ++i) side[i] = side_of_plane(g, v[static_cast<size_t>(loop[i])]);
    for (size_t i = 0; i < m; ++i) {
      const size_t j = (i + 1) % m;
      const Vec3 &u = v[static_cast<size_t>(loop[i])], &w = v[static_cast<size_t>(loop[j])];
      const Sign su = side[i], sw = side[j];
      if (su == Sign::Zero && sw == Sign::Zero) {
        HPoint a = hpoint(u), b = hpoint(w);
        if (cmp_along(a, b, axis) > 0) std::swap(a, b);
        on_line.push_back({a, b});
        continue;
      }
      if ((su != Sign::Negative) == (sw != Sign::Negative)) continue;
      if (su == Sign::Zero) {
        crossings.push_back(hpoint(u));
      } else if (sw == Sign::Zero) {
        crossings.push_back(hpoint(w));
      } else {
        // u + (w − u)·g(u)/(g(u) − g(w)) = (w·g(u) − u·g(w)) / (g(u) − g(w)).
        const HPoint hu = hpoint(u), hw = hpoint(w);
        const Q gu = eval(hg, hu), gw = eval(hg, hw);
        HPoint x;
        for (int k = 0; k < 3; ++k) x.x[k] = hw.x[k] * gu - hu.x[k] * gw;
        x.w = gu - gw;
        if (sgn(x.w) < 0) {
          for (Q& c : x.x) c = Q(0) - c;
          x.w = Q(0) - x.w;
        }
        crossings.push_back(std::move(x));
      }
    }
  }
  HEDRA_ASSERT(crossings.size() % 2 == 0,
               "junction lines: odd number of crossings of a face boundary");
  std::sort(crossings.begin(), crossings.end(),
            [axis](const HPoint& a, const HPoint& b) { return cmp_along(a, b, axis) < 0; });
  std::vector<Span> spans;
  for (size_t i = 0; i + 1 < crossings.size(); i += 2)
    if (cmp_along(crossings[i], crossings[i + 1], axis) < 0)
      spans.push_back({crossings[i], crossings[i + 1]});
  // Remove the boundary edges lying on L: there L touches the face without entering it.
  for (const Span& cut : on_line) {
    std::vector<Span> next;
    for (Span& s : spans) {
      if (cmp_along(cut.hi, s.lo, axis) <= 0 || cmp_along(cut.lo, s.hi, axis) >= 0) {
        next.push_back(std::move(s));
        continue;
      }
      if (cmp_along(s.lo, cut.lo, axis) < 0) next.push_back({s.lo, cut.lo});
      if (cmp_along(cut.hi, s.hi, axis) < 0) next.push_back({cut.hi, s.hi});
    }
    spans = std::move(next);
  }
  return spans;
}

}  // namespace

Eigen::AlignedBox3d face_box(const Body& body, int face) {
  Eigen::AlignedBox3d box;
  box.setEmpty();
  for (int i : body.faces()[static_cast<size_t>(face)].loops[0]) box.extend(body.vertices()[static_cast<size_t>(i)]);
  return box;
}

std::vector<char> faces_meeting(const Body& body, std::span<const Eigen::AlignedBox3d> boxes) {
  if (boxes.empty() || boxes.size() > kMaxMeetingBoxes)
    throw std::invalid_argument("faces_meeting: 1 to 10 boxes");
  // Outcodes (Cohen–Sutherland), six bits per box: a face's box misses box k exactly when all
  // its vertices lie beyond one side of k, i.e. when the AND of its vertices' codes has a bit
  // of k's group. Each vertex of a face ends one of its edges (hole vertices lie inside the
  // outer loop's box, so they change nothing), and the edges are one flat array: no face loop
  // is read.
  const std::vector<Vec3>& vs = body.vertices();
  std::vector<std::uint64_t> code(vs.size());
  for (size_t v = 0; v < vs.size(); ++v) {
    std::uint64_t c = 0;
    for (size_t k = 0; k < boxes.size(); ++k)
      for (int a = 0; a < 3; ++a) {
        const std::uint64_t below = vs[v][a] < boxes[k].min()[a], above = vs[v][a] > boxes[k].max()[a];
        c |= (below | above << 1) << (6 * k + 2 * static_cast<size_t>(a));
      }
    code[v] = c;
  }
  std::vector<std::uint64_t> face(static_cast<size_t>(body.face_count()), ~std::uint64_t{0});
  for (const Edge& e : body.edges()) {
    const std::uint64_t c = code[static_cast<size_t>(e.v0)] & code[static_cast<size_t>(e.v1)];
    face[static_cast<size_t>(e.left_face)] &= c;
    face[static_cast<size_t>(e.right_face)] &= c;
  }
  std::vector<char> out(face.size(), 0);
  for (size_t f = 0; f < face.size(); ++f)
    for (size_t k = 0; k < boxes.size() && !out[f]; ++k) out[f] = ((face[f] >> (6 * k)) & 63) == 0;
  // A plain loop, not std::views::iota: clang 14 (the sanitizer build) rejects that view with
  // libstdc++ 12.
  const auto agrees = [&] {
    for (int f = 0; f < body.face_count(); ++f) {
      const Eigen::AlignedBox3d box = face_box(body, f);
      const bool meets = std::any_of(boxes.begin(), boxes.end(), [&](const Eigen::AlignedBox3d& b) { return box.intersects(b); });
      if (meets != static_cast<bool>(out[static_cast<size_t>(f)])) return false;
    }
    return true;
  };
  HEDRA_EXPENSIVE_ASSERT(agrees(), "faces_meeting: an outcode disagrees with the face's box");
  return out;
}

std::optional<std::pair<double, double>> hidden_by_planes_brute_force(
    std::span<const ExactPlane> planes, const Viewpoint& view, const Vec3& p1, const Vec3& p2) {
  const std::vector<HPlane> h = hplanes(planes);
  const auto part = hidden_brute_force(h, view, hpoint(p1), hpoint(p2));
  if (!part) return std::nullopt;
  return std::make_pair(to_double(part->lo), to_double(part->hi));
}

std::vector<std::pair<double, double>> visible_parts_exact(const Vec3& p1, const Vec3& p2,
                                                           const Candidates& candidates,
                                                           const Viewpoint& view,
                                                           bool brute_force) {
  std::vector<std::pair<double, double>> out;
  for (const Interval& v : visible_fracs(hpoint(p1), hpoint(p2), candidates, view, brute_force))
    out.emplace_back(to_double(v.lo), to_double(v.hi));
  return out;
}

std::vector<JunctionPart> junction_lines(const Body& a, const Body& b,
                                         const FacePlane& planes_a, const FacePlane& planes_b,
                                         const Viewpoint& view, const CandidateQuery& query,
                                         bool brute, int& found, const std::vector<bool>& back_a,
                                         const std::vector<bool>& back_b, ExactPlaneCache* cache,
                                         const std::vector<int>* listed_a, const std::vector<int>* listed_b) {
  std::vector<JunctionPart> out;
  // Only B's faces whose boxes meet A's box can meet a face of A: O(Fb) box tests once (of the
  // faces listed, when a list is given), then each face of A near B is tested against those.
  std::vector<int> near_b;
  std::vector<Eigen::AlignedBox3d> boxes_b;
  if (listed_b) {
    for (int fb : *listed_b)
      if (Eigen::AlignedBox3d box = face_box(b, fb); box.intersects(a.bbox())) {
        near_b.push_back(fb);
        boxes_b.push_back(box);
      }
  } else {
    const std::vector<char> b_near_a = faces_meeting(b, std::span(&a.bbox(), 1));
    for (int fb = 0; fb < b.face_count(); ++fb) {
      if (!b_near_a[static_cast<size_t>(fb)]) continue;
      near_b.push_back(fb);
      boxes_b.push_back(face_box(b, fb));
    }
  }
  if (near_b.empty()) return out;
  // B's exact planes built on first use, then reused.
  std::vector<std::optional<HPlane>> hplanes_b(near_b.size());
  Candidates candidates;
  std::vector<int> near_a;
  if (listed_a) {
    for (int fa : *listed_a)
      if (face_box(a, fa).intersects(b.bbox())) near_a.push_back(fa);
  } else {
    const std::vector<char> a_near_b = faces_meeting(a, std::span(&b.bbox(), 1));
    for (int fa = 0; fa < a.face_count(); ++fa)
      if (a_near_b[static_cast<size_t>(fa)]) near_a.push_back(fa);
  }
  for (const int fa : near_a) {
    const Eigen::AlignedBox3d box_a = face_box(a, fa);
    std::optional<HPlane> ha_built;
    for (size_t kb = 0; kb < near_b.size(); ++kb) {
      const int fb = near_b[kb];
      if (!box_a.intersects(boxes_b[kb])) continue;
      if (!ha_built) ha_built = hplane(planes_a(fa));
      const HPlane& ha = *ha_built;
      std::optional<HPlane>& cached_b = hplanes_b[kb];
      if (!cached_b) cached_b = hplane(planes_b(fb));
      const HPlane& hb = *cached_b;
      // Direction of L = na × nb; parallel planes have no junction line.
      const Q dir[3] = {ha.n[1] * hb.n[2] - ha.n[2] * hb.n[1], ha.n[2] * hb.n[0] - ha.n[0] * hb.n[2],
                        ha.n[0] * hb.n[1] - ha.n[1] * hb.n[0]};
      int axis = -1;
      double best = 0;
      for (int k = 0; k < 3; ++k) {
        if (sgn(dir[k]) == 0) continue;
        const double m = std::abs(CGAL::to_double(dir[k]));
        if (axis < 0 || m > best) axis = k, best = m;
      }
      if (axis < 0) continue;
      const std::vector<Span> sa = face_spans(a, fa, planes_b(fb), hb, axis);
      if (sa.empty()) continue;
      const std::vector<Span> sb = face_spans(b, fb, planes_a(fa), ha, axis);
      // On a back face of a convex body: hidden by that body (counted, not tested).
      const bool hidden_by_own = (!back_a.empty() && back_a[static_cast<size_t>(fa)]) ||
                                 (!back_b.empty() && back_b[static_cast<size_t>(fb)]);
      // Intersection of the two sorted span lists.
      size_t i = 0, j = 0;
      while (i < sa.size() && j < sb.size()) {
        const HPoint& lo = cmp_along(sa[i].lo, sb[j].lo, axis) >= 0 ? sa[i].lo : sb[j].lo;
        const bool a_first = cmp_along(sa[i].hi, sb[j].hi, axis) <= 0;
        const HPoint& hi = a_first ? sa[i].hi : sb[j].hi;
        if (cmp_along(lo, hi, axis) < 0) {
          ++found;
          if (hidden_by_own) {
            if (a_first) ++i;
            else ++j;
            continue;
          }
          const Vec3 ra = rounded(lo), rb = rounded(hi);
          candidates.pieces.clear();
          candidates.facets.clear();
          query(ra, rb, fa, fb, candidates);
          for (const Interval& v : visible_fracs(lo, hi, candidates, view, brute, cache)) {
            JunctionPart part{point_at(lo, hi, v.lo), point_at(lo, hi, v.hi)};
            if (part.a != part.b) out.push_back(part);
          }
        }
        if (a_first)
          ++i;
        else
          ++j;
      }
    }
  }
  return out;
}

}  // namespace hedra::detail
