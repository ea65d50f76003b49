#include "hedra/visibility/polygon_union.h"

#include <CGAL/Mpzf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>

#include "hedra/core/tolerance.h"

namespace hedra {
namespace {

// ---- Exact signs of polynomials in double coordinates ----
//
// An expression is evaluated twice at most: first in double carrying a forward error bound
// (Approx), which decides whenever |value| > bound; otherwise in CGAL::Mpzf, which represents
// sums and products of doubles exactly.

constexpr double kU = 0.5 * std::numeric_limits<double>::epsilon();  // unit roundoff 2^-53
// Absolute slack per operation: covers underflow (subnormal results lose relative accuracy).
constexpr double kTiny = 1e-300;

struct Approx {
  double v = 0;  // computed value
  double e = 0;  // |v − exact| ≤ e
  Approx() = default;
  Approx(double x) : v(x), e(0) {}  // NOLINT: exact doubles convert implicitly
  Approx(double x, double err) : v(x), e(err) {}
};

// The bound of a result: the propagated error plus the rounding of the result itself
// (≤ u·|v|/(1 − u)), inflated for the roundings of computing the bound in double.
inline Approx operator+(const Approx& a, const Approx& b) {
  const double v = a.v + b.v;
  return {v, (a.e + b.e + kU * std::abs(v)) * (1 + 4 * kU) + kTiny};
}
inline Approx operator-(const Approx& a, const Approx& b) {
  const double v = a.v - b.v;
  return {v, (a.e + b.e + kU * std::abs(v)) * (1 + 4 * kU) + kTiny};
}
inline Approx operator*(const Approx& a, const Approx& b) {
  const double v = a.v * b.v;
  return {
      v, (std::abs(a.v) * b.e + std::abs(b.v) * a.e + a.e * b.e + kU * std::abs(v)) * (1 + 8 * kU) +
             kTiny};
}

template <class Expr>
Sign exact_sign(const Expr& expr) {
  const Approx a = expr(Approx(0));
  if (a.v > a.e) return Sign::Positive;
  if (a.v < -a.e) return Sign::Negative;
  const CGAL::Mpzf x = expr(CGAL::Mpzf(0));
  const CGAL::Sign s = CGAL::sign(x);
  return s == CGAL::POSITIVE ? Sign::Positive : (s == CGAL::NEGATIVE ? Sign::Negative : Sign::Zero);
}

// (b − a) × (c − a): Positive when c lies to the left of a → b.
template <class T>
T orient_value(const Vec2& a, const Vec2& b, const Vec2& c) {
  const T bax = T(b.x()) - T(a.x()), bay = T(b.y()) - T(a.y());
  const T cax = T(c.x()) - T(a.x()), cay = T(c.y()) - T(a.y());
  return bax * cay - bay * cax;
}

// Orientation with its double value (for constructions). Shewchuk's orient2d filter first.
struct Orient {
  double v;
  Sign s;
};
inline Orient orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double l = (b.x() - a.x()) * (c.y() - a.y());
  const double r = (b.y() - a.y()) * (c.x() - a.x());
  const double v = l - r;
  const double bound = (3 + 16 * kU) * kU * (std::abs(l) + std::abs(r)) + kTiny;
  if (v > bound) return {v, Sign::Positive};
  if (v < -bound) return {v, Sign::Negative};
  // Three points on one axis-parallel line (pieces cut by the same face edge or axis plane):
  // exactly collinear, without the slow path.
  if ((a.x() == b.x() && b.x() == c.x()) || (a.y() == b.y() && b.y() == c.y()))
    return {0, Sign::Zero};
  // Two of the points equal (pieces sharing a vertex: the projected triangles of a mesh).
  if (c == a || c == b || a == b) return {0, Sign::Zero};
  return {v, exact_sign([&](auto zero) { return orient_value<decltype(zero)>(a, b, c); })};
}

// ---- Positions along an edge a → b ----

// A point of line ab: either a point exactly on it (an end of the edge, or a vertex of another
// piece lying exactly on the line), or the crossing of the line with the line of edge c → d.
struct Param {
  bool explicit_point = true;
  Vec2 p = Vec2::Zero();                    // explicit point
  Vec2 c = Vec2::Zero(), d = Vec2::Zero();  // crossing line
  Sign rising = Sign::Zero;                 // sign(orient(c, d, b) − orient(c, d, a)): ≠ 0
};

struct Edge2 {
  Vec2 a, b;
  int axis;  // a coordinate in which a and b differ (the larger difference)
  Sign dir;  // sign(b[axis] − a[axis])
};

Edge2 make_edge(const Vec2& a, const Vec2& b) {
  Edge2 e{a, b, 0, Sign::Zero};
  e.axis = std::abs(b.x() - a.x()) >= std::abs(b.y() - a.y()) ? 0 : 1;
  e.dir = b[e.axis] > a[e.axis] ? Sign::Positive : Sign::Negative;
  return e;
}

inline Sign mul(Sign a, Sign b) {
  return static_cast<Sign>(static_cast<int>(a) * static_cast<int>(b));
}

inline Sign cmp_double(double x, double y) {
  return x < y ? Sign::Negative : (x > y ? Sign::Positive : Sign::Zero);
}

// Exact sign of t(P) − t(Q) along edge e.
Sign compare(const Edge2& e, const Param& P, const Param& Q) {
  if (P.explicit_point && Q.explicit_point) return mul(cmp_double(P.p[e.axis], Q.p[e.axis]), e.dir);
  if (P.explicit_point) {
    // g(X) = orient(c, d, X) is affine along the line, zero at Q, rising with Q.rising.
    return mul(orient(Q.c, Q.d, P.p).s, Q.rising);
  }
  if (Q.explicit_point) return -compare(e, Q, P);
  if (P.c == Q.c && P.d == Q.d) return Sign::Zero;
  // t_P − t_Q = (oQa·oPb − oPa·oQb) / ((oPa − oPb)(oQa − oQb)), the denominator's sign being
  // rising_P · rising_Q.
  const Sign num = exact_sign([&](auto zero) {
    using T = decltype(zero);
    const T pa = orient_value<T>(P.c, P.d, e.a), pb = orient_value<T>(P.c, P.d, e.b);
    const T qa = orient_value<T>(Q.c, Q.d, e.a), qb = orient_value<T>(Q.c, Q.d, e.b);
    return qa * pb - pa * qb;
  });
  return mul(num, mul(P.rising, Q.rising));
}

// Lexicographic order of points, for canonical constructions.
inline bool lex_less(const Vec2& p, const Vec2& q) {
  return p.x() < q.x() || (p.x() == q.x() && p.y() < q.y());
}

// The crossing point of lines (a, b) and (c, d), computed from the unordered pair of
// segments in a canonical order, so every edge that asks for it gets the same bits.
Vec2 crossing_point(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  if (lex_less(b, a)) std::swap(a, b);
  if (lex_less(d, c)) std::swap(c, d);
  if (lex_less(c, a) || (c == a && lex_less(d, b))) {
    std::swap(a, c);
    std::swap(b, d);
  }
  const double oa = orient(c, d, a).v, ob = orient(c, d, b).v;
  double t = oa / (oa - ob);
  if (!(t >= 0)) t = 0;
  if (t > 1) t = 1;
  if (t == 0) return a;
  if (t == 1) return b;
  return {a.x() + (b.x() - a.x()) * t, a.y() + (b.y() - a.y()) * t};
}

Vec2 point_of(const Edge2& e, const Param& P) {
  return P.explicit_point ? P.p : crossing_point(e.a, e.b, P.c, P.d);
}

// The crossing of edge e with the line of edge (c, d), as an explicit point whenever it is
// exactly an input point (an end of e, or c or d).
Param crossing_param(const Edge2& e, const Vec2& c, const Vec2& d, const Orient& oa,
                     const Orient& ob) {
  Param P;
  if (oa.s == Sign::Zero) {
    P.p = e.a;
    return P;
  }
  if (ob.s == Sign::Zero) {
    P.p = e.b;
    return P;
  }
  if (orient(e.a, e.b, c).s == Sign::Zero) {
    P.p = c;
    return P;
  }
  if (orient(e.a, e.b, d).s == Sign::Zero) {
    P.p = d;
    return P;
  }
  P.explicit_point = false;
  P.c = c;
  P.d = d;
  // orient(c, d, ·) goes from oa to ob along e; they have opposite strict signs here.
  P.rising = oa.s == Sign::Negative ? Sign::Positive : Sign::Negative;
  return P;
}

struct Box2 {
  Vec2 lo, hi;
  bool overlaps(const Box2& o) const {
    return lo.x() <= o.hi.x() && o.lo.x() <= hi.x() && lo.y() <= o.hi.y() && o.lo.y() <= hi.y();
  }
};

Box2 box_of(const Ring2& r) {
  Box2 b{r[0], r[0]};
  for (const Vec2& p : r) {
    b.lo = b.lo.cwiseMin(p);
    b.hi = b.hi.cwiseMax(p);
  }
  return b;
}

struct Interval {
  Param lo, hi;
};

// The parts of edge e (of piece i) covered by piece j: the open part strictly inside it, or,
// when e runs along one of its edges, the overlap if that edge has the opposite direction or
// the same direction with j < i. Appends to `out`.
void coverage(const Edge2& e, int i, const Ring2& pj, int j, std::vector<Interval>& out) {
  const size_t n = pj.size();
  Param lower, upper;
  lower.p = e.a;
  upper.p = e.b;
  bool collinear = false;
  for (size_t k = 0; k < n; ++k) {
    const Vec2& c = pj[k];
    const Vec2& d = pj[(k + 1) % n];
    const Orient oa = orient(c, d, e.a), ob = orient(c, d, e.b);
    if (oa.s == Sign::Zero && ob.s == Sign::Zero) {
      collinear = true;
      continue;
    }
    if (oa.s != Sign::Positive && ob.s != Sign::Positive) return;  // outside the open half-plane
    if (oa.s == Sign::Positive && ob.s == Sign::Positive) continue;
    const Param X = crossing_param(e, c, d, oa, ob);
    if (oa.s == Sign::Positive) {
      if (compare(e, X, upper) == Sign::Negative) upper = X;
    } else {
      if (compare(e, X, lower) == Sign::Positive) lower = X;
    }
  }
  if (!collinear) {
    if (compare(e, lower, upper) == Sign::Negative) out.push_back({lower, upper});
    return;
  }
  // e lies on the line of one or more edges of j (j convex: it meets j only on its boundary).
  for (size_t k = 0; k < n; ++k) {
    const Vec2& c = pj[k];
    const Vec2& d = pj[(k + 1) % n];
    if (orient(c, d, e.a).s != Sign::Zero || orient(c, d, e.b).s != Sign::Zero) continue;
    const Sign same = mul(cmp_double(d[e.axis], c[e.axis]), e.dir);
    if (same == Sign::Zero) continue;  // c = d cannot happen for a valid ring
    if (same == Sign::Positive && j > i) continue;
    Param pc, pd;
    pc.p = c;
    pd.p = d;
    Param lo = same == Sign::Positive ? pc : pd, hi = same == Sign::Positive ? pd : pc;
    Param a, b;
    a.p = e.a;
    b.p = e.b;
    if (compare(e, lo, a) == Sign::Negative) lo = a;
    if (compare(e, hi, b) == Sign::Positive) hi = b;
    if (compare(e, lo, hi) == Sign::Negative) out.push_back({lo, hi});
  }
}

struct Portion {
  Vec2 p, q;
};

// Neumaier's compensated sum.
struct Sum {
  double s = 0, c = 0;
  void add(double x) {
    const double t = s + x;
    c += std::abs(s) >= std::abs(x) ? (s - t) + x : (x - t) + s;
    s = t;
  }
  double value() const { return s + c; }
};

// Angle of v counter-clockwise from r, in [0, 2π).
double ccw_angle(const Vec2& r, const Vec2& v) {
  double a = std::atan2(r.x() * v.y() - r.y() * v.x(), r.x() * v.x() + r.y() * v.y());
  if (a < 0) a += 2 * std::numbers::pi;
  return a;
}

// Location of p with respect to a ring: +1 inside, 0 on the boundary, −1 outside (exact).
int locate(const Ring2& ring, const Vec2& p) {
  int winding = 0;
  const size_t n = ring.size();
  for (size_t k = 0; k < n; ++k) {
    const Vec2& u = ring[k];
    const Vec2& w = ring[(k + 1) % n];
    const Sign s = orient(u, w, p).s;
    if (s == Sign::Zero && std::min(u.x(), w.x()) <= p.x() && p.x() <= std::max(u.x(), w.x()) &&
        std::min(u.y(), w.y()) <= p.y() && p.y() <= std::max(u.y(), w.y()))
      return 0;
    if (u.y() <= p.y()) {
      if (w.y() > p.y() && s == Sign::Positive) ++winding;
    } else if (w.y() <= p.y() && s == Sign::Negative) {
      --winding;
    }
  }
  return winding != 0 ? 1 : -1;
}

// Drops vertices where the ring goes straight on (exactly collinear, same direction). O(n).
Ring2 drop_straight(const Ring2& ring) {
  const auto straight = [](const Vec2& u, const Vec2& v, const Vec2& w) {
    return orient(u, v, w).s == Sign::Zero && (v - u).dot(w - v) > 0;
  };
  Ring2 out;
  out.reserve(ring.size());
  for (const Vec2& v : ring) {
    out.push_back(v);
    while (out.size() >= 3 && straight(out[out.size() - 3], out[out.size() - 2], out.back())) {
      out[out.size() - 2] = out.back();
      out.pop_back();
    }
  }
  // Around the seam.
  size_t first = 0;
  bool changed = true;
  while (changed && out.size() - first > 3) {
    changed = false;
    if (straight(out[out.size() - 2], out.back(), out[first])) {
      out.pop_back();
      changed = true;
    } else if (straight(out.back(), out[first], out[first + 1])) {
      ++first;
      changed = true;
    }
  }
  return Ring2(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
}

// Chains the boundary portions into rings and groups them into polygons with holes.
// Returns false when some portion has no successor (rounded crossings that differ).
bool chain(std::vector<Portion> portions, std::vector<PolygonWithHoles2>& result) {
  // Starts and ends sorted by exact point; one merge of the two gives every portion the range
  // of starts at its end point (its candidate successors). O(n log n) for the sorts, then
  // linear: no search per portion.
  const auto by_point = [](const std::pair<Vec2, int>& a, const std::pair<Vec2, int>& b) {
    return lex_less(a.first, b.first) || (a.first == b.first && a.second < b.second);
  };
  std::vector<std::pair<Vec2, int>> starts(portions.size()), ends(portions.size());
  for (size_t k = 0; k < portions.size(); ++k) starts[k] = {portions[k].p, static_cast<int>(k)};
  std::sort(starts.begin(), starts.end(), by_point);
  std::vector<std::pair<int, int>> successors(portions.size());  // [lo, hi) in starts
  // Fills successors; false when some end has no start at its point.
  const auto match = [&] {
    for (size_t k = 0; k < portions.size(); ++k) ends[k] = {portions[k].q, static_cast<int>(k)};
    std::sort(ends.begin(), ends.end(), by_point);
    bool all = true;
    size_t a = 0;
    for (size_t b = 0; b < ends.size();) {
      const Vec2 q = ends[b].first;
      while (a < starts.size() && lex_less(starts[a].first, q)) ++a;
      size_t hi = a;
      while (hi < starts.size() && starts[hi].first == q) ++hi;
      all = all && hi > a;
      for (; b < ends.size() && ends[b].first == q; ++b)
        successors[static_cast<size_t>(ends[b].second)] = {static_cast<int>(a), static_cast<int>(hi)};
    }
    return all;
  };
  // Where three or more edges cross at one exact point, the rounded crossings of different
  // pairs can differ by an ulp: an end with no start at its point is joined to the nearest
  // start that has no end at its point (within rounding of the coordinates).
  if (!match()) {
    std::vector<Vec2> free_starts;
    std::vector<int> orphan_ends;
    size_t a = 0, b = 0;
    while (a < starts.size() || b < ends.size()) {
      Vec2 q = a < starts.size() && (b == ends.size() || !lex_less(ends[b].first, starts[a].first))
                   ? starts[a].first
                   : ends[b].first;
      size_t na = 0, nb = 0;
      while (a < starts.size() && starts[a].first == q) ++a, ++na;
      while (b < ends.size() && ends[b].first == q) ++b, ++nb;
      for (size_t i = nb; i < na; ++i) free_starts.push_back(q);
      for (size_t i = na; i < nb; ++i) orphan_ends.push_back(ends[b - 1 - (i - na)].second);
    }
    for (int k : orphan_ends) {
      Vec2& q = portions[static_cast<size_t>(k)].q;
      size_t best = free_starts.size();
      double best_d = 0;
      for (size_t f = 0; f < free_starts.size(); ++f) {
        const double d = (free_starts[f] - q).cwiseAbs().maxCoeff();
        if (best == free_starts.size() || d < best_d) {
          best = f;
          best_d = d;
        }
      }
      const double scale = q.cwiseAbs().maxCoeff() + 1e-300;
      if (best == free_starts.size() || best_d > kChainJoinTolerance * scale) return false;
      q = free_starts[best];
      free_starts.erase(free_starts.begin() + static_cast<std::ptrdiff_t>(best));
    }
    if (!match()) return false;
  }
  std::vector<char> used(portions.size(), 0);
  std::vector<Ring2> outers, holes;
  for (size_t first = 0; first < portions.size(); ++first) {
    if (used[first]) continue;
    Ring2 ring;
    int cur = static_cast<int>(first);
    for (;;) {
      used[static_cast<size_t>(cur)] = 1;
      const Portion& P = portions[static_cast<size_t>(cur)];
      ring.push_back(P.p);
      const auto [lo, hi] = successors[static_cast<size_t>(cur)];
      if (lo == hi) return false;
      int next = -1;
      double best = -1;
      const Vec2 back = P.p - P.q;
      if (hi - lo == 1) next = starts[static_cast<size_t>(lo)].second;  // the only way on
      for (int it = lo; hi - lo > 1 && it != hi; ++it) {
        const int cand = starts[static_cast<size_t>(it)].second;
        if (used[static_cast<size_t>(cand)] && cand != static_cast<int>(first)) continue;
        const Portion& C = portions[static_cast<size_t>(cand)];
        const double a = ccw_angle(back, C.q - C.p);
        if (a > best) {
          best = a;
          next = cand;
        }
      }
      if (next < 0) return false;
      if (next == static_cast<int>(first)) break;
      if (used[static_cast<size_t>(next)]) return false;
      cur = next;
    }
    // Two portions there and back (a sliver of zero width between pieces that meet along it,
    // their edges an ulp apart): a ring of no area, which carries nothing.
    if (ring.size() < 3) continue;
    ring = drop_straight(ring);
    const double a = ring_area(ring);
    if (a > 0)
      outers.push_back(std::move(ring));
    else if (a < 0)
      holes.push_back(std::move(ring));
    // A ring of zero area (two coincident opposite portions) carries nothing: drop it.
  }
  // Group: each hole goes to the smallest outer ring that contains it.
  std::vector<double> outer_area(outers.size());
  for (size_t k = 0; k < outers.size(); ++k) outer_area[k] = ring_area(outers[k]);
  result.clear();
  for (size_t k = 0; k < outers.size(); ++k) result.push_back({outers[k], {}, outer_area[k]});
  std::vector<Box2> outer_box(outers.size());
  for (size_t k = 0; k < outers.size(); ++k) outer_box[k] = box_of(outers[k]);
  for (Ring2& h : holes) {
    int best = -1;
    const Box2 hb = box_of(h);
    for (size_t k = 0; k < outers.size(); ++k) {
      const Box2& ob = outer_box[k];
      if (hb.lo.x() < ob.lo.x() || hb.lo.y() < ob.lo.y() || hb.hi.x() > ob.hi.x() || hb.hi.y() > ob.hi.y())
        continue;  // a ring inside another lies inside its box
      int where = 0;
      for (size_t v = 0; v < h.size() && where == 0; ++v) where = locate(outers[k], h[v]);
      if (where == 0) where = locate(outers[k], 0.5 * (h[0] + h[1]));
      if (where > 0 && (best < 0 || outer_area[k] < outer_area[static_cast<size_t>(best)]))
        best = static_cast<int>(k);
    }
    if (best < 0) return false;
    PolygonWithHoles2& poly = result[static_cast<size_t>(best)];
    poly.area += ring_area(h);
    poly.holes.push_back(std::move(h));
  }
  return true;
}

// Candidate pieces for an edge: a uniform grid in which each piece is listed in the cells its
// polygon meets (not every cell of its box), and an edge visits only the cells its segment
// crosses. Long thin pieces across the grid (the shadows of a star's spikes under a low
// light) then meet only their true neighbours: with box cells every edge visited every piece
// listed anywhere in its box, hundreds of times over.
// Conservative by construction: per row of cells, the x-range of the polygon (or segment)
// within the row's strip, both widened by a relative margin far above rounding, so any point
// common to a piece and an edge lies in a cell both list; the exact decisions are made later
// (coverage), the grid only drops pairs that cannot meet. Cost O(rows × k) per piece of k
// vertices and O(rows) per edge, rows of the grid its box spans.
class PieceGrid {
 public:
  PieceGrid(const std::vector<Ring2>& pieces, const std::vector<Box2>& boxes)
      : boxes_(boxes) {
    const size_t m = boxes.size();
    if (m <= 16) return;  // brute force
    lo_ = boxes[0].lo;
    Vec2 hi = boxes[0].hi;
    for (const Box2& b : boxes) {
      lo_ = lo_.cwiseMin(b.lo);
      hi = hi.cwiseMax(b.hi);
    }
    const int g =
        std::clamp(static_cast<int>(std::ceil(1 * std::sqrt(static_cast<double>(m)))), 1, 1024);
    nx_ = ny_ = g;
    size_ = (hi - lo_).cwiseMax(Vec2(1e-300, 1e-300));
    inv_ = Vec2(nx_ / size_.x(), ny_ / size_.y());
    cells_.assign(static_cast<size_t>(nx_ * ny_) + 1, 0);
    // Counting sort into a compressed row layout.
    for (size_t k = 0; k < m; ++k)
      for_ring_cells(pieces[k], boxes[k], [&](int c) {
        ++cells_[static_cast<size_t>(c) + 1];
        return true;
      });
    for (size_t c = 1; c < cells_.size(); ++c) cells_[c] += cells_[c - 1];
    items_.resize(static_cast<size_t>(cells_.back()));
    std::vector<int> fill(cells_.begin(), cells_.end() - 1);
    for (size_t k = 0; k < m; ++k)
      for_ring_cells(pieces[k], boxes[k], [&](int c) {
        items_[static_cast<size_t>(fill[static_cast<size_t>(c)]++)] = static_cast<int>(k);
        return true;
      });
    stamp_.assign(m, -1);
  }

  // Pieces that may meet segment ab (closed) and whose boxes meet its box, each once, until
  // f returns false.
  template <class F>
  void query(const Vec2& a, const Vec2& b, int key, F&& f) {
    const Box2 box{a.cwiseMin(b), a.cwiseMax(b)};
    const size_t m = boxes_.size();
    if (cells_.empty()) {
      for (size_t k = 0; k < m; ++k)
        if (boxes_[k].overlaps(box) && !f(static_cast<int>(k))) return;
      return;
    }
    const Ring2 seg{a, b};
    for_ring_cells(seg, box, [&](int c) {
      for (int q = cells_[static_cast<size_t>(c)]; q < cells_[static_cast<size_t>(c) + 1]; ++q) {
        const int k = items_[static_cast<size_t>(q)];
        if (stamp_[static_cast<size_t>(k)] == key) continue;
        stamp_[static_cast<size_t>(k)] = key;
        if (boxes_[static_cast<size_t>(k)].overlaps(box) && !f(k)) return false;
      }
      return true;
    });
  }

 private:
  int cell(double v, double lo, double inv, int n) const {
    const double x = (v - lo) * inv;
    if (!(x > 0)) return 0;
    return static_cast<int>(std::min(x, static_cast<double>(n - 1)));
  }
  // The cells a convex ring (or a segment: a ring of two points) meets, until f returns false,
  // row by row: in row y,
  // the x-range of the ring's edges clipped to the row's strip (the first and last rows reach
  // to infinity), widened by the margins.
  template <class F>
  void for_ring_cells(const Ring2& ring, const Box2& b, F&& f) const {
    const int y0 = cell(b.lo.y(), lo_.y(), inv_.y(), ny_), y1 = cell(b.hi.y(), lo_.y(), inv_.y(), ny_);
    const double h = size_.y() / ny_, w = size_.x() / nx_;
    const double my = 1e-6 * h + 1e-12 * (std::abs(lo_.y()) + size_.y());
    const double mx = 1e-6 * w + 1e-12 * (std::abs(lo_.x()) + size_.x());
    const double inf = std::numeric_limits<double>::infinity();
    const size_t n = ring.size();
    for (int y = y0; y <= y1; ++y) {
      const double s0 = y == 0 ? -inf : lo_.y() + y * h - my;
      const double s1 = y == ny_ - 1 ? inf : lo_.y() + (y + 1) * h + my;
      double x0 = inf, x1 = -inf;
      for (size_t k = 0; k < n; ++k) {
        const Vec2& p = ring[k];
        const Vec2& q = ring[(k + 1) % n];
        const double pl = std::min(p.y(), q.y()), ph = std::max(p.y(), q.y());
        if (ph < s0 || pl > s1) continue;
        if (p.y() == q.y()) {
          x0 = std::min({x0, p.x(), q.x()});
          x1 = std::max({x1, p.x(), q.x()});
          continue;
        }
        // The edge's part within the strip: its ends at y = max(pl, s0) and min(ph, s1).
        const double t0 = (std::max(pl, s0) - p.y()) / (q.y() - p.y());
        const double t1 = (std::min(ph, s1) - p.y()) / (q.y() - p.y());
        for (const double t : {t0, t1}) {
          const double x = p.x() + std::clamp(t, 0.0, 1.0) * (q.x() - p.x());
          x0 = std::min(x0, x);
          x1 = std::max(x1, x);
        }
      }
      if (x0 > x1) continue;
      x0 = std::max(x0 - mx, b.lo.x() - mx);
      x1 = std::min(x1 + mx, b.hi.x() + mx);
      const int c0 = cell(x0, lo_.x(), inv_.x(), nx_), c1 = cell(x1, lo_.x(), inv_.x(), nx_);
      for (int x = c0; x <= c1; ++x)
        if (!f(y * nx_ + x)) return;
    }
  }

  const std::vector<Box2>& boxes_;
  Vec2 lo_ = Vec2::Zero(), size_ = Vec2::Ones(), inv_ = Vec2::Ones();
  int nx_ = 0, ny_ = 0;
  std::vector<int> cells_, items_, stamp_;
};

}  // namespace

double ring_area(const Ring2& ring) {
  if (ring.size() < 3) return 0;
  const Vec2 o = ring[0];
  Sum s;
  for (size_t k = 1; k + 1 < ring.size(); ++k) {
    const Vec2 a = ring[k] - o, b = ring[k + 1] - o;
    s.add(a.x() * b.y() - a.y() * b.x());
  }
  return 0.5 * s.value();
}

double polygon_area(const PolygonWithHoles2& polygon) {
  double a = ring_area(polygon.outer);
  for (const Ring2& h : polygon.holes) a += ring_area(h);  // holes are clockwise: negative
  return a;
}

UnionResult unite_convex(const std::vector<Ring2>& pieces, bool want_polygons) {
  UnionResult out;
  if (pieces.empty()) return out;
  if (pieces.size() == 1) {
    out.area = ring_area(pieces[0]);
    if (want_polygons) out.polygons.push_back({pieces[0], {}, out.area});
    return out;
  }
  std::vector<Box2> boxes;
  boxes.reserve(pieces.size());
  for (const Ring2& r : pieces) boxes.push_back(box_of(r));
  PieceGrid grid(pieces, boxes);

  // Stage 1: for every edge, the parts not covered by another piece.
  const Vec2 origin = boxes[0].lo;
  Sum area;
  std::vector<Portion> portions;
  std::vector<Interval> covered;
  int key = 0;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const Ring2& ring = pieces[i];
    for (size_t k = 0; k < ring.size(); ++k) {
      const Edge2 e = make_edge(ring[k], ring[(k + 1) % ring.size()]);
      covered.clear();
      bool whole = false;  // some piece covers all of the edge: nothing more to learn
      grid.query(e.a, e.b, key++, [&](int j) {
        if (static_cast<size_t>(j) == i) return true;
        const size_t before = covered.size();
        coverage(e, static_cast<int>(i), pieces[static_cast<size_t>(j)], j, covered);
        for (size_t q = before; q < covered.size(); ++q)
          if (covered[q].lo.explicit_point && covered[q].lo.p == e.a &&
              covered[q].hi.explicit_point && covered[q].hi.p == e.b)
            whole = true;
        return !whole;
      });
      if (whole) continue;
      // Stage 2: the gaps between the covered intervals, in exact order along the edge.
      std::sort(covered.begin(), covered.end(), [&](const Interval& x, const Interval& y) {
        return compare(e, x.lo, y.lo) == Sign::Negative;
      });
      Param at;
      at.p = e.a;
      Param end;
      end.p = e.b;
      auto emit = [&](const Param& s, const Param& t) {
        const Vec2 p = point_of(e, s), q = point_of(e, t);
        if (p == q) return;
        const Vec2 pp = p - origin, qq = q - origin;
        area.add(pp.x() * qq.y() - pp.y() * qq.x());
        portions.push_back({p, q});
      };
      for (const Interval& iv : covered) {
        if (compare(e, iv.lo, at) == Sign::Positive) emit(at, iv.lo);
        if (compare(e, iv.hi, at) == Sign::Positive) at = iv.hi;
      }
      if (compare(e, end, at) == Sign::Positive) emit(at, end);
    }
  }
  out.area = 0.5 * area.value();
  if (!want_polygons) return out;
  // Stage 3: rings.
  if (!chain(portions, out.polygons)) {
    // Rare: three or more edges through one exact point. The exact union gives the rings.
    out = cgal_union(pieces, true);
    out.chained = false;
  }
  return out;
}

}  // namespace hedra
