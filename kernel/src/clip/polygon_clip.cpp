#include "hedra/clip/polygon_clip.h"

#include <algorithm>
#include <cmath>

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

Vec3 canonical_crossing(const ExactPlane& f, Vec3 v, Vec3 w) {
  if (lex_less(w, v)) std::swap(v, w);
  double t = crossing(f, v, w).t;
  // Both plane values can round to the same double when the segment lies within rounding of
  // the plane (the exact signs still differ): then every point of it is within the bound.
  if (!std::isfinite(t)) t = 0.5;
  Vec3 p = point_at(v, w, t);
  // On a plane perpendicular to a coordinate axis the exact crossing has that plane's
  // coordinate: set it, so that pieces cut by one such plane meet along exactly the same line.
  if (const int k = axis_plane(f); k >= 0) p[k] = f.points()[0][k];
  return p;
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

bool clip_convex_polygon_open(const Polygon3& polygon, const ConvexClipper& clipper,
                              Polygon3& out, PolygonClipScratch& scratch) {
  out = polygon;
  std::vector<Sign>& side = scratch.side;
  for (const ExactPlane& f : clipper.planes()) {
    const size_t n = out.size();
    side.resize(n);
    size_t pos = 0, neg = 0;
    for (size_t i = 0; i < n; ++i) {
      // side_of_plane(f, p) with its static filter inline (the common case, no call).
      const Vec3& p = out[i];
      side[i] = side_of_plane(f, p, f.value(p), f.error_bound(p.cwiseAbs().maxCoeff()));
      pos += side[i] == Sign::Positive;
      neg += side[i] == Sign::Negative;
    }
    // Open: no vertex strictly inside leaves nothing of positive area strictly inside.
    if (pos == 0) return false;
    if (neg == 0) continue;
    scratch.ring.clear();
    stage(
        n, side, [&](size_t i) { scratch.ring.push_back(out[i]); },
        [&](size_t i, size_t j) { scratch.ring.push_back(canonical_crossing(f, out[i], out[j])); });
    std::swap(out, scratch.ring);
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
