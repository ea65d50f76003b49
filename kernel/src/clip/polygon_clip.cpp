#include "hedra/clip/polygon_clip.h"

#include <CGAL/Gmpq.h>
#include <CGAL/Mpzf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <limits>
#include <optional>
#include <utility>

#include "core/exact_plane.h"
#include "hedra/clip/cyrus_beck.h"
#include "hedra/core/error.h"

namespace hedra {
namespace {

void check_polygon(const Polygon3& polygon) {
  if (polygon.size() < 3)
    throw InvalidInput("a polygon needs at least 3 vertices, got " +
                       std::to_string(polygon.size()));
  for (const Vec3& p : polygon)
    if (!p.allFinite()) throw InvalidInput("polygon vertex with a coordinate that is not finite");
}

// A vertex of the output with whether it lies exactly on the current plane.
struct Point {
  Vec3 p;
  bool on;
};

// The crossing of edge vw with f at the rounded parameter (cheap; polygon vertices need no more).
Vec3 rounded_crossing(const ExactPlane& f, const Vec3& v, const Vec3& w) {
  return point_at(v, w, crossing(f, v, w).t);
}

// Consecutive duplicates removed (around the ring too); fewer than 3 left, or every vertex on
// the plane (a part of zero area), gives an empty ring.
Polygon3 finish(const std::vector<Point>& points) {
  Polygon3 ring;
  bool all_on = true;
  for (const Point& q : points) {
    all_on = all_on && q.on;
    if (ring.empty() || ring.back() != q.p) ring.push_back(q.p);
  }
  while (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
  if (all_on || ring.size() < 3) return {};
  return ring;
}

// The classic one-plane Sutherland–Hodgman stage: every vertex inside or on the plane
// (keep(i)), and a new point where an edge crosses the plane strictly (cross(i, j)); a
// crossing ending or starting at a vertex on the plane is that vertex.
template <class Keep, class Cross>
void stage(size_t n, const std::vector<Sign>& side, Keep&& keep, Cross&& cross) {
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    if (side[i] != Sign::Negative) keep(i);
    if ((side[i] == Sign::Positive && side[j] == Sign::Negative) ||
        (side[i] == Sign::Negative && side[j] == Sign::Positive))
      cross(i, j);
  }
}

std::vector<Point> single_ring(const Polygon3& poly, const std::vector<Sign>& side,
                               const ExactPlane& f) {
  std::vector<Point> out;
  stage(
      poly.size(), side, [&](size_t i) { out.push_back({poly[i], side[i] == Sign::Zero}); },
      [&](size_t i, size_t j) { out.push_back({rounded_crossing(f, poly[i], poly[j]), true}); });
  return out;
}

bool lex_less(const Vec3& a, const Vec3& b) {
  return a.x() < b.x() || (a.x() == b.x() && (a.y() < b.y() || (a.y() == b.y() && a.z() < b.z())));
}

// The coordinate axis a plane is perpendicular to, decided exactly from its defining points
// (three points, or two points and a direction), or −1.
int axis_plane(const ExactPlane& f) {
  if (!f.by_points()) return -1;
  const auto& p = f.points();
  for (int k = 0; k < 3; ++k) {
    const bool third = f.by_direction() ? p[2][k] == 0 : p[2][k] == p[0][k];
    if (p[0][k] == p[1][k] && third) return k;
  }
  return -1;
}

struct Chain {
  std::vector<Point> points;
  size_t entry_edge = 0, exit_edge = 0;  // edges i → i + 1 where it enters and leaves
};

// A crossing of the boundary with the plane, for ordering along the cutting line.
struct Transition {
  size_t edge;
  bool entry;
  size_t chain;
};

}  // namespace

std::vector<Polygon3> clip_polygon(const Polygon3& polygon, const ExactPlane& f) {
  check_polygon(polygon);
  const size_t n = polygon.size();
  // Stage 1: exact sides.
  std::vector<Sign> side(n);
  size_t positive = 0, negative = 0;
  for (size_t i = 0; i < n; ++i) {
    side[i] = side_of_plane(f, polygon[i]);
    positive += side[i] == Sign::Positive;
    negative += side[i] == Sign::Negative;
  }
  // In the closed half-space (a polygon lying in the plane included): unchanged. Only
  // touching it (no vertex strictly inside): nothing of positive area.
  if (negative == 0) return {polygon};
  if (positive == 0) return {};
  // Otherwise the pieces are those of polygon ∩ {f > ε} as ε → 0: a vertex on the plane counts
  // as outside, so parts that meet only along the plane come out as separate pieces and no
  // piece has a zero-width strip along the plane.
  const auto in = [&](size_t i) { return side[i % n] == Sign::Positive; };

  // Stage 2: the chains of the boundary inside, each from an entry to the next exit. The point
  // where a chain enters or leaves is the vertex itself when that vertex lies on the plane, a
  // new point only where an edge crosses the plane strictly.
  std::vector<Chain> chains;
  for (size_t i = 0; i < n; ++i) {
    if (in(i) || !in(i + 1)) continue;
    Chain c;
    c.entry_edge = i;
    size_t j = (i + 1) % n;
    if (side[i] == Sign::Zero)
      c.points.push_back({polygon[i], true});
    else
      c.points.push_back({rounded_crossing(f, polygon[i], polygon[j]), true});
    for (;;) {
      c.points.push_back({polygon[j], false});
      if (!in(j + 1)) break;
      j = (j + 1) % n;
    }
    c.exit_edge = j;
    const size_t k = (j + 1) % n;
    if (side[k] == Sign::Zero)
      c.points.push_back({polygon[k], true});
    else
      c.points.push_back({rounded_crossing(f, polygon[j], polygon[k]), true});
    chains.push_back(std::move(c));
  }

  // Stage 3: order the entries and exits along the cutting line, exactly, by the coordinate in
  // which the line (polygon normal × plane normal) moves most.
  std::vector<Transition> t;
  for (size_t c = 0; c < chains.size(); ++c) {
    t.push_back({chains[c].entry_edge, true, c});
    t.push_back({chains[c].exit_edge, false, c});
  }
  int axis = 0;
  polygon_normal(polygon).cross(f.normal()).cwiseAbs().maxCoeff(&axis);
  const auto order = [&](const Transition& a, const Transition& b) {
    return compare_crossings_along(f, polygon[a.edge], polygon[(a.edge + 1) % n], polygon[b.edge],
                                   polygon[(b.edge + 1) % n], axis);
  };
  std::sort(t.begin(), t.end(), [&](const Transition& a, const Transition& b) {
    return order(a, b) == Sign::Negative;
  });

  // Along the line, inside the polygon, the clipped region's boundary runs from an exit to the
  // next entry: sorted, the transitions alternate exit, entry, exit, … (or the reverse when
  // the axis runs against the line). Equal points (a vertex on the plane whose neighbours are
  // both inside: an exit and an entry at one place) take the order the alternation needs,
  // read from a transition that is alone at its place.
  bool even_is_exit = true;
  bool found = false;
  for (size_t i = 0; i < t.size() && !found; ++i) {
    const bool alone = (i == 0 || order(t[i - 1], t[i]) != Sign::Zero) &&
                       (i + 1 == t.size() || order(t[i], t[i + 1]) != Sign::Zero);
    if (alone) {
      even_is_exit = (i % 2 == 0) == !t[i].entry;
      found = true;
    }
  }
  for (size_t i = 0; i < t.size();) {
    size_t end = i + 1;
    while (end < t.size() && order(t[i], t[end]) == Sign::Zero) ++end;
    for (size_t pos = i; pos + 1 < end; ++pos) {
      const bool want_exit = (pos % 2 == 0) == even_is_exit;
      for (size_t q = pos; q < end; ++q) {
        if (t[q].entry != want_exit) {
          std::swap(t[pos], t[q]);
          break;
        }
      }
    }
    i = end;
  }

  // Stage 4: bridge each exit to its partner entry and follow the cycles.
  std::vector<size_t> next(chains.size(), chains.size());
  bool consistent = true;
  for (size_t i = 0; i + 1 < t.size(); i += 2) {
    const Transition& a = t[i];
    const Transition& b = t[i + 1];
    if (a.entry == b.entry) {
      consistent = false;
      break;
    }
    const Transition& exit = a.entry ? b : a;
    const Transition& entry = a.entry ? a : b;
    next[exit.chain] = entry.chain;
  }
  std::vector<Polygon3> pieces;
  std::vector<char> used(chains.size(), 0);
  for (size_t c = 0; c < chains.size() && consistent; ++c) {
    if (used[c]) continue;
    std::vector<Point> ring;
    size_t cur = c;
    while (cur < chains.size() && !used[cur]) {
      used[cur] = 1;
      ring.insert(ring.end(), chains[cur].points.begin(), chains[cur].points.end());
      cur = next[cur];
    }
    if (cur != c) {
      consistent = false;
      break;
    }
    if (Polygon3 piece = finish(ring); !piece.empty()) pieces.push_back(std::move(piece));
  }
  if (consistent) return pieces;
  // Only a polygon that is not simple gets here: keep the classic single ring.
  Polygon3 ring = finish(single_ring(polygon, side, f));
  if (ring.empty()) return {};
  return {ring};
}

std::vector<Polygon3> clip_polygon(const Polygon3& polygon, const ConvexClipper& clipper) {
  check_polygon(polygon);
  std::vector<Polygon3> pieces{polygon};
  for (const ExactPlane& f : clipper.planes()) {
    std::vector<Polygon3> next;
    for (const Polygon3& piece : pieces)
      for (Polygon3& part : clip_polygon(piece, f)) next.push_back(std::move(part));
    pieces = std::move(next);
    if (pieces.empty()) break;
  }
  return pieces;
}

Polygon3 sutherland_hodgman(const Polygon3& polygon, const ConvexClipper& clipper) {
  check_polygon(polygon);
  Polygon3 ring = polygon;
  for (const ExactPlane& f : clipper.planes()) {
    if (ring.empty()) break;
    std::vector<Sign> side(ring.size());
    for (size_t i = 0; i < ring.size(); ++i) side[i] = side_of_plane(f, ring[i]);
    const std::vector<Point> out = single_ring(ring, side, f);
    ring.clear();
    for (const Point& q : out) ring.push_back(q.p);
  }
  return ring;
}

namespace {

using internal::ClipVertex;
using Row = std::array<CGAL::Mpzf, 4>;

constexpr double kUnit = 0.5 * std::numeric_limits<double>::epsilon();
// A made vertex whose tracked error exceeds this fraction of its edge's ends' coordinates is
// rounded from its exact point instead: an edge that the plane cuts at a grazing angle (about
// 1e-4 rad or less; a smooth terrain's triangle cut by its neighbour's plane).
constexpr double kRecompute = 0x1p-36;

// The homogeneous point where the planes a, b, c meet: X = (X0, X1, X2) / X3, the cofactors
// of the last row of det[a; b; c; f], so that f(X) = det[a; b; c; f] / X3 for any plane f.
// Cost about 25 multiprecision products.
std::array<CGAL::Mpzf, 4> meet(const Row& a, const Row& b, const Row& c) {
  using Q = CGAL::Mpzf;
  Q m[4][4];  // 2 × 2 minors of rows a, b
  for (int p = 0; p < 4; ++p)
    for (int q = p + 1; q < 4; ++q) m[p][q] = a[p] * b[q] - a[q] * b[p];
  // 3 × 3 minors of rows a, b, c without column x, expanded along c.
  const auto minor3 = [&](int x) {
    int col[3], k = 0;
    for (int i = 0; i < 4; ++i)
      if (i != x) col[k++] = i;
    return c[col[0]] * m[col[1]][col[2]] - c[col[1]] * m[col[0]][col[2]] +
           c[col[2]] * m[col[0]][col[1]];
  };
  std::array<Q, 4> x{Q(0) - minor3(0), minor3(1), Q(0) - minor3(2), minor3(3)};
  if (CGAL::sign(x[3]) == CGAL::ZERO)
    throw InternalError("polygon clipping: a vertex whose planes do not meet in a point");
  return x;
}

// The sign of f at the point x (homogeneous, from meet).
Sign side_at_point(const std::array<CGAL::Mpzf, 4>& x, const Row& f) {
  const int s = CGAL::sign(f[0] * x[0] + f[1] * x[1] + f[2] * x[2] + f[3] * x[3]) * CGAL::sign(x[3]);
  return s > 0 ? Sign::Positive : (s < 0 ? Sign::Negative : Sign::Zero);
}

// The exact planes of one clipping: the polygon's plane, the lines of its edges (the plane
// through an edge's ends containing the projection axis, so it holds the lifted ends), the
// coordinate planes through an input vertex, the clipper's planes (cached: built when a
// decision first needs them).
class ExactPolygon {
 public:
  ExactPolygon(const Polygon3& polygon, const ExactPlane& plane, int axis,
               const ConvexClipper& clipper)
      : polygon_(polygon), plane_(plane), axis_(axis), plane_axis_(axis_plane(plane)),
        clipper_(clipper) {}

  // The side of the clipper's plane `f` at vertex v.
  Sign side(ClipVertex& v, int f) {
    // An input vertex on the plane is its own lift: the predicate on its doubles (cheaper, and
    // what a polygon sharing it with a caster needs: a vertex exactly on a plane of the caster).
    if (v.input < 0) {
      // Made by a cut: its exact point, kept for the planes after this one.
      if (v.exact < 0) {
        points_.push_back(point(v));
        v.exact = static_cast<int>(points_.size()) - 1;
      }
      return side_at_point(points_[static_cast<size_t>(v.exact)], row(f));
    }
    const Vec3& p = polygon_[static_cast<size_t>(v.input)];
    if (on_plane(static_cast<size_t>(v.input))) return side_of_plane(clipper_.plane(f), p);
    // Off it (a face planar only within rounding): its lift p + s·e_axis, R(p) + s·R_axis = 0,
    // has f = (f(p)·R_axis − R(p)·f_axis) / R_axis.
    const Row& g = row(f);
    const Row& r = own();
    const auto at = [&p](const Row& c) {
      return c[0] * CGAL::Mpzf(p.x()) + c[1] * CGAL::Mpzf(p.y()) + c[2] * CGAL::Mpzf(p.z()) + c[3];
    };
    const size_t k = static_cast<size_t>(axis_);
    const int sign = CGAL::sign(at(g) * r[k] - at(r) * g[k]) * CGAL::sign(r[k]);
    return sign > 0 ? Sign::Positive : (sign < 0 ? Sign::Negative : Sign::Zero);
  }

  // Whether the rounded point p of a made vertex is its exact point, known from doubles alone:
  // each of its three planes perpendicular to a coordinate axis and p on it (the vertices of
  // axis-aligned walls, floors and their cuts). `cut_axis`: axis_plane of the cutting plane.
  // Cost O(1), no multiprecision.
  bool exact_in_doubles(const ClipVertex& v, const Vec3& p, int cut_axis) const {
    const auto on = [&p](const ExactPlane& g, int k) { return k >= 0 && p[k] == g.points()[0][k]; };
    if (!on(plane_, plane_axis_) || !on(clipper_.plane(v.cut), cut_axis)) return false;
    if (v.on < 0) {
      const ExactPlane& g = clipper_.plane(-1 - v.on);
      return on(g, axis_plane(g));
    }
    const Vec3& a = polygon_[static_cast<size_t>(v.on)];
    const Vec3& b = polygon_[(static_cast<size_t>(v.on) + 1) % polygon_.size()];
    // The input edge's line plane (through its ends along the axis) is x_m = a_m when the ends
    // share coordinate m (m not the axis).
    for (int m = 0; m < 3; ++m)
      if (m != axis_ && a[m] == b[m] && p[m] == a[m]) return true;
    return false;
  }

  // The vertex's exact point rounded to doubles, each coordinate within 6u of its size (the
  // quotient of two enclosures one unit in the last place wide), through rationals where
  // those leave the range of doubles.
  Vec3 rounded(const ClipVertex& v) {
    const std::array<CGAL::Mpzf, 4> x = point(v);
    const std::pair<double, double> w = x[3].to_interval();
    Vec3 p;
    bool fine = std::isnormal(w.first) && std::isnormal(w.second);
    for (int i = 0; i < 3 && fine; ++i) {
      p[i] = x[static_cast<size_t>(i)].to_interval().first / w.first;
      fine = std::isfinite(p[i]) && (p[i] == 0 || std::isnormal(p[i]));
    }
    if (fine) return p;
    const CGAL::Gmpq q(x[3]);
    for (int i = 0; i < 3; ++i) p[i] = CGAL::to_double(CGAL::Gmpq(x[static_cast<size_t>(i)]) / q);
    return p;
  }

 private:
  std::array<CGAL::Mpzf, 4> point(const ClipVertex& v) {
    if (v.input >= 0) {
      const Vec3& p = polygon_[static_cast<size_t>(v.input)];
      return meet(own(), coordinate((axis_ + 1) % 3, p), coordinate((axis_ + 2) % 3, p));
    }
    const Row a = line(v.on);
    return meet(own(), a, row(v.cut));
  }

  bool on_plane(size_t i) {
    if (on_.empty()) on_.assign(polygon_.size(), -1);
    if (on_[i] < 0) {
      const Vec3& p = polygon_[i];
      bool on = false;
      if (plane_.by_points() && !plane_.by_direction())
        for (const Vec3& q : plane_.points()) on = on || q == p;
      on_[i] = on || side_of_plane(plane_, p) == Sign::Zero;
    }
    return on_[i] != 0;
  }

  // The exact coefficients of the polygon's plane, made once per clipping.
  const Row& own() {
    if (!own_) own_ = internal::exact_coefficients(plane_);
    return *own_;
  }

  // The exact coefficients of the clipper's plane i, made once per clipping.
  const Row& row(int i) {
    if (rows_.empty()) rows_.resize(static_cast<size_t>(clipper_.plane_count()));
    auto& r = rows_[static_cast<size_t>(i)];
    if (!r) r = std::make_unique<const Row>(internal::exact_coefficients(clipper_.plane(i)));
    return *r;
  }
  static Row coordinate(int i, const Vec3& p) {
    using Q = CGAL::Mpzf;
    Row r{Q(0), Q(0), Q(0), Q(-p[i])};
    r[static_cast<size_t>(i)] = Q(1);
    return r;
  }
  Row line(int l) {
    if (l < 0) return row(-1 - l);
    using Q = CGAL::Mpzf;
    const size_t n = polygon_.size(), e = static_cast<size_t>(l);
    const Vec3& v = polygon_[e];
    const Vec3& w = polygon_[(e + 1) % n];
    const Q d[3] = {Q(w.x()) - Q(v.x()), Q(w.y()) - Q(v.y()), Q(w.z()) - Q(v.z())};
    // (w − v) × e_axis
    const int i = (axis_ + 1) % 3, j = (axis_ + 2) % 3;
    Row r{Q(0), Q(0), Q(0), Q(0)};
    r[static_cast<size_t>(i)] = d[j];
    r[static_cast<size_t>(j)] = Q(0) - d[i];
    r[3] = Q(0) - (r[static_cast<size_t>(i)] * Q(v[i]) + r[static_cast<size_t>(j)] * Q(v[j]));
    return r;
  }

  const Polygon3& polygon_;
  const ExactPlane& plane_;
  int axis_;
  int plane_axis_;  // axis_plane of the polygon's plane
  std::optional<Row> own_;
  std::vector<std::array<CGAL::Mpzf, 4>> points_;  // exact points of made vertices
  std::vector<signed char> on_;  // per input vertex: on the plane (1), off it (0), not known
  const ConvexClipper& clipper_;
  // Each row on the heap, so a reference stays valid; nothing is allocated until a decision
  // needs the exact planes.
  std::vector<std::unique_ptr<const Row>> rows_;
};

// The side of f at a vertex: the filter on its rounded point p, whose exact point is within
// `error` (max-norm) of it, then the exact planes.
Sign side_at(const ExactPlane& f, int index, double norm1, const Vec3& p, double error,
             ClipVertex& v, ExactPolygon& exact) {
  const double value = f.value(p);
  // A vertex that is its exact point (an input vertex of a planar face, a made vertex certified
  // from doubles): side_of_plane with its static filter inline.
  if (error == 0) return side_of_plane(f, p, value, f.error_bound(p.cwiseAbs().maxCoeff()));
  const double bound =
      (f.error_bound(p.cwiseAbs().maxCoeff()) + norm1 * error * (1 + 1e-6)) * (1 + 8 * kUnit);
  if (value > bound) return Sign::Positive;
  if (value < -bound) return Sign::Negative;
  return exact.side(v, index);
}

}  // namespace

bool clip_convex_polygon_open(const Polygon3& polygon, const ExactPlane& plane, int axis,
                              bool planar, const ConvexClipper& clipper, Polygon3& out,
                              PolygonClipScratch& s) {
  if (axis < 0 || axis > 2 || !(std::abs(plane.normal()[axis]) > 0))
    throw InvalidInput("clip_convex_polygon_open: the plane is parallel to the projection axis");
  out = polygon;
  const size_t n0 = polygon.size();
  s.error.resize(n0);
  s.made.resize(n0);
  // An input vertex's exact point is its lift onto the plane, |f(p)| / |n_axis| away.
  const double lift = (1 + 1e-6) / std::abs(plane.normal()[axis]);
  for (size_t i = 0; i < n0; ++i) {
    const Vec3& p = polygon[i];
    s.error[i] =
        planar ? 0 : (std::abs(plane.value(p)) + plane.error_bound(p.cwiseAbs().maxCoeff())) * lift;
    s.made[i] = ClipVertex{static_cast<int>(i), 0, 0, static_cast<int>(i), -1};
  }
  ExactPolygon exact(polygon, plane, axis, clipper);
  std::vector<Sign>& side = s.side;
  for (int index = 0; index < clipper.plane_count(); ++index) {
    const ExactPlane& f = clipper.plane(index);
    const size_t n = out.size();
    const double norm1 = f.normal().cwiseAbs().sum();
    side.resize(n);
    size_t pos = 0, neg = 0;
    for (size_t i = 0; i < n; ++i) {
      side[i] = side_at(f, index, norm1, out[i], s.error[i], s.made[i], exact);
      pos += side[i] == Sign::Positive;
      neg += side[i] == Sign::Negative;
    }
    // Open: no vertex strictly inside leaves nothing of positive area strictly inside.
    if (pos == 0) return false;
    if (neg == 0) continue;
    s.ring.clear();
    s.ring_error.clear();
    s.ring_made.clear();
    const int along = -1 - index;
    const int f_axis = axis_plane(f);
    stage(
        n, side,
        [&](size_t i) {
          ClipVertex v = s.made[i];
          // A vertex on f followed by one outside: the boundary runs along f from here.
          if (side[i] == Sign::Zero && side[(i + 1) % n] == Sign::Negative) v.after = along;
          s.ring.push_back(out[i]);
          s.ring_error.push_back(s.error[i]);
          s.ring_made.push_back(v);
        },
        [&](size_t i, size_t j) {
          Vec3 a = out[i], b = out[j];
          double ea = s.error[i], eb = s.error[j];
          if (lex_less(b, a)) {
            std::swap(a, b);
            std::swap(ea, eb);
          }
          const double ma = a.cwiseAbs().maxCoeff(), mb = b.cwiseAbs().maxCoeff();
          const Crossing c = crossing_from_values(f.value(a), f.value(b),
                                                  f.error_bound(ma) + norm1 * ea * (1 + 1e-6),
                                                  f.error_bound(mb) + norm1 * eb * (1 + 1e-6));
          double t = c.t;
          // Both values can round alike when the edge lies within rounding of f: any point of
          // it is then within the bound below.
          if (!std::isfinite(t)) t = 0.5;
          Vec3 p = point_at(a, b, t);
          if (f_axis >= 0) p[f_axis] = f.points()[0][f_axis];
          // The exact crossing X lies on the exact edge AB at t*: p − X = (1 − t*)(a − A) +
          // t*(b − B) + (t − t*)(b − a) + the rounding of point_at (≤ 3u·max(|a|, |b|) a
          // coordinate). It lies on the segment anyway: within its span of p.
          const double span = (b - a).cwiseAbs().maxCoeff();
          const double rounding = 8 * kUnit * std::max(ma, mb);
          double e = std::max(ea, eb) + c.error * span + rounding;
          if (!(e <= std::max(ea, eb) + span + rounding)) e = std::max(ea, eb) + span + rounding;
          e *= 1 + 8 * kUnit;
          const ClipVertex made{-1, s.made[i].after, index,
                                side[i] == Sign::Positive ? along : s.made[i].after, -1};
          // Far from its exact point (an edge nearly along f, ends far from theirs): the exact
          // point rounded once instead.
          if (exact.exact_in_doubles(made, p, f_axis)) {
            e = 0;
          } else if (!(e <= kRecompute * std::max(ma, mb))) {
            p = exact.rounded(made);
            e = 8 * kUnit * p.cwiseAbs().maxCoeff() + std::numeric_limits<double>::min();
          }
          s.ring.push_back(p);
          s.ring_error.push_back(e);
          s.ring_made.push_back(made);
        });
    std::swap(out, s.ring);
    std::swap(s.error, s.ring_error);
    std::swap(s.made, s.ring_made);
    if (out.size() < 3) return false;
  }
  return true;
}

Vec3 polygon_normal(const Polygon3& polygon) {
  Vec3 n = Vec3::Zero();
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec3& a = polygon[i];
    const Vec3& b = polygon[(i + 1) % polygon.size()];
    n += Vec3((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
              (a.x() - b.x()) * (a.y() + b.y()));
  }
  return n;
}

double polygon_area(const Polygon3& polygon) { return 0.5 * polygon_normal(polygon).norm(); }

}  // namespace hedra
