#include "hedra/clip/polygon_clip.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "testing/clip_fixtures.h"
#include "hedra/core/error.h"
#include "hedra/baselines/outcodes.h"
#include "hedra/core/primitives.h"

namespace hedra {
namespace {

using testing::Rational;
using RPoint = std::array<Rational, 3>;

// The plane's exact affine function as rational coefficients (n, k).
std::array<Rational, 4> rational_plane(const ExactPlane& f) {
  std::array<Rational, 4> r;
  if (f.by_points()) {
    const auto& [a, b, c] = f.points();
    const RPoint ba{Rational(b.x()) - a.x(), Rational(b.y()) - a.y(), Rational(b.z()) - a.z()};
    const RPoint ca{Rational(c.x()) - a.x(), Rational(c.y()) - a.y(), Rational(c.z()) - a.z()};
    r[0] = ca[1] * ba[2] - ca[2] * ba[1];  // (c − a) × (b − a)
    r[1] = ca[2] * ba[0] - ca[0] * ba[2];
    r[2] = ca[0] * ba[1] - ca[1] * ba[0];
    r[3] = -(r[0] * a.x() + r[1] * a.y() + r[2] * a.z());
  } else {
    for (int i = 0; i < 4; ++i) r[i] = f.coefficients().coefficients[i];
  }
  if (f.negated())
    for (auto& v : r) v = -v;
  return r;
}

// The course's Sutherland–Hodgman (docs/algorithms.md §3.5) in exact rationals: one ring with
// bridges, whose shoelace area is exactly the area of polygon ∩ clipper. The polygons lie in planes
// z = const, so the clipping happens in 2D against the lines where the clipper's planes meet that
// plane. To keep the rationals small, every vertex is computed from the two input lines it lies on
// (an edge line of the polygon or a clipper line), never from earlier computed points: each ring
// vertex carries the line of the edge that leaves it.
struct Line {
  Rational a, b, c;  // a·x + b·y + c (≥ 0 inside, for clipper lines)
  Rational at(const Rational& x, const Rational& y) const { return a * x + b * y + c; }
};
struct RVertex {
  Rational x, y;
  int edge;  // index in `lines` of the line through this vertex and the next
};

RVertex meet(const std::vector<Line>& lines, int l1, int l2) {
  const Line &p = lines[static_cast<size_t>(l1)], &q = lines[static_cast<size_t>(l2)];
  const Rational det = p.a * q.b - p.b * q.a;
  return {(p.b * q.c - q.b * p.c) / det, (q.a * p.c - p.a * q.c) / det, -1};
}

Rational exact_clipped_area(const Polygon3& polygon, const ConvexClipper& clipper) {
  const Rational z = polygon[0].z();
  std::vector<Line> lines;
  std::vector<RVertex> ring;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec3& p = polygon[i];
    const Vec3& q = polygon[(i + 1) % polygon.size()];
    lines.push_back({Rational(q.y()) - p.y(), Rational(p.x()) - q.x(),
                     Rational(q.x()) * p.y() - Rational(p.x()) * q.y()});
    ring.push_back({p.x(), p.y(), static_cast<int>(i)});
  }
  for (const ExactPlane& f : clipper.planes()) {
    const auto k = rational_plane(f);
    const int cut = static_cast<int>(lines.size());
    lines.push_back({k[0], k[1], k[2] * z + k[3]});
    const Line& l = lines.back();
    std::vector<RVertex> out;
    for (size_t i = 0; i < ring.size(); ++i) {
      const RVertex& a = ring[i];
      const RVertex& b = ring[(i + 1) % ring.size()];
      const Rational va = l.at(a.x, a.y), vb = l.at(b.x, b.y);
      if (va >= 0) out.push_back(a);
      if (va == 0 && vb < 0) out.back().edge = cut;  // leaves along the cut
      if (va > 0 && vb < 0) {
        RVertex x = meet(lines, a.edge, cut);
        x.edge = cut;
        out.push_back(x);
      }
      if (va < 0 && vb > 0) {
        RVertex x = meet(lines, a.edge, cut);
        x.edge = a.edge;
        out.push_back(x);
      }
    }
    ring = std::move(out);
    if (ring.empty()) return 0;
  }
  Rational twice = 0;
  for (size_t i = 0; i < ring.size(); ++i) {
    const RVertex& a = ring[i];
    const RVertex& b = ring[(i + 1) % ring.size()];
    twice += a.x * b.y - b.x * a.y;
  }
  return CGAL::abs(twice) / 2;
}

double total_area(const std::vector<Polygon3>& pieces) {
  double a = 0;
  for (const Polygon3& p : pieces) a += polygon_area(p);
  return a;
}

// Every turn of the ring goes the same way as its normal (a convex polygon).
bool is_convex(const Polygon3& ring) {
  const Vec3 n = polygon_normal(ring);
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec3& a = ring[i];
    const Vec3& b = ring[(i + 1) % ring.size()];
    const Vec3& c = ring[(i + 2) % ring.size()];
    if ((b - a).cross(c - b).dot(n) < -1e-12 * n.norm()) return false;
  }
  return true;
}

Polygon3 comb(int teeth, double z = 0) {
  // A spine [0, 2·teeth − 1] × [0, 1] with teeth of width 1 up to y = 3, counter-clockwise.
  Polygon3 p{{0, 0, z}, {2.0 * teeth - 1, 0, z}};
  for (int i = teeth - 1; i >= 0; --i) {
    p.emplace_back(2.0 * i + 1, 3, z);
    p.emplace_back(2.0 * i, 3, z);
    if (i > 0) {
      p.emplace_back(2.0 * i, 1, z);
      p.emplace_back(2.0 * i - 1, 1, z);
    }
  }
  return p;
}

ConvexClipper half_space(double a, double b, double c, double d) {
  return ConvexClipper::from_planes({ExactPlane::from_coefficients(Plane(a, b, c, d))});
}

TEST(PolygonClip, SquareAgainstABox) {
  const Polygon3 square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const auto pieces =
      clip_polygon(square, box_clipper(ClipBox::from_bounds({0.5, -1, -1}, {2, 0.5, 1})));
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(pieces[0].size(), 4u);
  EXPECT_EQ(polygon_area(pieces[0]), 0.25);
  EXPECT_GT(polygon_normal(pieces[0]).z(), 0);  // orientation kept
}

TEST(PolygonClip, VerticesOnThePlaneAreKeptExactly) {
  // The plane x = 1 runs through the apex (1, 1) and crosses the base at (1, 0).
  const Polygon3 tri{{0, 0, 0}, {2, 0, 0}, {1, 1, 0}};
  const auto right = clip_polygon(tri, half_space(1, 0, 0, -1));
  ASSERT_EQ(right.size(), 1u);
  ASSERT_EQ(right[0].size(), 3u);
  EXPECT_EQ(right[0][0], Vec3(1, 0, 0));
  EXPECT_EQ(right[0][1], Vec3(2, 0, 0));
  EXPECT_EQ(right[0][2], Vec3(1, 1, 0));
  EXPECT_EQ(polygon_area(right[0]), 0.5);
  // Touching the plane at a vertex from outside, or along an edge: nothing of positive area.
  EXPECT_TRUE(clip_polygon(tri, half_space(0, 1, 0, -1)).empty());  // y ≥ 1: the apex only
  EXPECT_TRUE(clip_polygon(tri, half_space(0, -1, 0, 0)).empty());  // y ≤ 0: the base only
  // Entirely in the closed half-space, with an edge on the plane: unchanged.
  const auto whole = clip_polygon(tri, half_space(0, 1, 0, 0));
  ASSERT_EQ(whole.size(), 1u);
  EXPECT_EQ(whole[0], tri);
  // A polygon lying in the plane is on the closed clipper: kept.
  EXPECT_EQ(clip_polygon(tri, half_space(0, 0, 1, 0)).size(), 1u);
}

TEST(PolygonClip, ConvexStaysOneConvexPolygonWithExactArea) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::vector<ConvexClipper> clippers = {
      ConvexClipper(testing::icosahedron(1.2)),
      box_clipper(ClipBox::from_bounds({-0.7, -0.4, -1}, {0.6, 0.9, 1})),
      ConvexClipper(testing::random_convex_body(rng, 12, 1, {0.1, -0.2, 0}))};
  for (const ConvexClipper& c : clippers) {
    for (int i = 0; i < 200; ++i) {
      // A random convex polygon in a plane z = const: points on an ellipse, in angle order.
      const double z = 0.8 * u(rng), rx = 0.3 + std::abs(u(rng)), ry = 0.3 + std::abs(u(rng));
      const Vec3 centre(0.5 * u(rng), 0.5 * u(rng), z);
      std::vector<double> angles;
      for (int k = 0; k < 3 + i % 9; ++k) angles.push_back(std::numbers::pi * (1 + u(rng)));
      std::sort(angles.begin(), angles.end());
      Polygon3 poly;
      for (double a : angles) poly.push_back(centre + Vec3(rx * std::cos(a), ry * std::sin(a), 0));
      const auto pieces = clip_polygon(poly, c);
      ASSERT_LE(pieces.size(), 1u);
      const double exact = testing::to_double(exact_clipped_area(poly, c));
      EXPECT_NEAR(total_area(pieces), exact, 1e-14);
      if (!pieces.empty()) {
        EXPECT_TRUE(is_convex(pieces[0]));
        for (const Vec3& p : pieces[0]) EXPECT_LT(std::abs(p.z() - z), 1e-15);
      }
    }
  }
}

TEST(PolygonClip, NonConvexGivesOnePiecePerPart) {
  const Polygon3 c = comb(3);  // teeth at x ∈ [0,1], [2,3], [4,5]
  ASSERT_NEAR(polygon_area(c), 5 + 3 * 2, 1e-15);
  // Above y = 2: the three tooth tips.
  auto tips = clip_polygon(c, half_space(0, 1, 0, -2));
  ASSERT_EQ(tips.size(), 3u);
  for (const Polygon3& p : tips) {
    EXPECT_EQ(polygon_area(p), 1);
    EXPECT_EQ(p.size(), 4u);
  }
  // Above y = 1, a plane through the notch bottoms (vertices and edges on the plane): the three
  // whole teeth; the edges lying in the plane between them leave nothing.
  auto teeth = clip_polygon(c, half_space(0, 1, 0, -1));
  ASSERT_EQ(teeth.size(), 3u);
  for (const Polygon3& p : teeth) EXPECT_EQ(polygon_area(p), 2);
  // Below y = 1: the spine, one piece with the teeth's bases on its boundary.
  auto spine = clip_polygon(c, half_space(0, -1, 0, 1));
  ASSERT_EQ(spine.size(), 1u);
  EXPECT_EQ(polygon_area(spine[0]), 5);
  // The same comb running clockwise gives the same pieces, clockwise.
  Polygon3 cw(c.rbegin(), c.rend());
  auto cw_tips = clip_polygon(cw, half_space(0, 1, 0, -2));
  ASSERT_EQ(cw_tips.size(), 3u);
  for (const Polygon3& p : cw_tips) EXPECT_LT(polygon_normal(p).z(), 0);
  // The course's single ring has the same area, joined along the plane.
  const Polygon3 ring = sutherland_hodgman(c, half_space(0, 1, 0, -2));
  EXPECT_EQ(polygon_area(ring), 3);
  // A slanted cut x + 2y ≥ 5.5: the tops of the first two teeth, and the third tooth with the
  // end of the spine; area against exact rationals.
  const ConvexClipper slanted = half_space(1, 2, 0, -5.5);
  const auto cut = clip_polygon(c, slanted);
  EXPECT_NEAR(total_area(cut), testing::to_double(exact_clipped_area(c, slanted)), 1e-14);
  EXPECT_EQ(cut.size(), 3u);
}

TEST(PolygonClip, RandomStarPolygonsAgainstExactAreas) {
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> u(-1, 1);
  // Clippers that hold some of the star's tips but not its centre, so tips come out as pieces.
  const ConvexClipper ico(testing::icosahedron(1).translated({1.5, 0, 0}));
  const ConvexClipper cube = box_clipper(ClipBox::from_bounds({0.45, -2, -1}, {2, 2, 1}));
  int several = 0;
  for (int i = 0; i < 400; ++i) {
    const ConvexClipper& c = i % 2 ? ico : cube;
    // A star-shaped polygon: radii alternating in and out around a centre.
    const double z = 0.6 * u(rng);
    const Vec3 centre(0.3 * u(rng), 0.3 * u(rng), z);
    const int n = 5 + i % 12;
    Polygon3 star;
    for (int k = 0; k < 2 * n; ++k) {
      const double a = std::numbers::pi * k / n + 0.1 * u(rng);
      const double r = k % 2 ? 0.15 + 0.2 * std::abs(u(rng)) : 0.6 + 0.6 * std::abs(u(rng));
      star.push_back(centre + Vec3(r * std::cos(a), r * std::sin(a), 0));
    }
    const auto pieces = clip_polygon(star, c);
    several += pieces.size() > 1;
    EXPECT_NEAR(total_area(pieces), testing::to_double(exact_clipped_area(star, c)), 1e-13);
    for (const Polygon3& p : pieces)
      for (const Vec3& q : p) {
        // Every vertex of every piece lies in the clipper, up to the rounding of new points.
        for (const ExactPlane& f : c.planes()) EXPECT_GT(f.value(q), -1e-14);
      }
  }
  EXPECT_GT(several, 50);  // star tips cut off by the clipper's faces come out as pieces
}

// ---- clip_convex_polygon_open: every decision on the exact polygon ----

Rational rational_value(const std::array<Rational, 4>& k, const RPoint& p) {
  return k[0] * p[0] + k[1] * p[1] + k[2] * p[2] + k[3];
}

RPoint rational_point(const Vec3& p) { return {Rational(p.x()), Rational(p.y()), Rational(p.z())}; }

// p moved along the axis onto the plane k (what clip_convex_polygon_open takes a vertex for).
RPoint lifted(const std::array<Rational, 4>& k, int axis, const Vec3& p) {
  RPoint r = rational_point(p);
  r[axis] = 0;
  r[axis] = -rational_value(k, r) / k[axis];
  return r;
}

// The same clipping in exact rationals: the open Sutherland–Hodgman of the lifted polygon.
std::vector<RPoint> exact_open_clip(const Polygon3& polygon, const ExactPlane& plane, int axis,
                                    const ConvexClipper& clipper) {
  const auto own = rational_plane(plane);
  std::vector<RPoint> ring;
  for (const Vec3& p : polygon) ring.push_back(lifted(own, axis, p));
  for (const ExactPlane& f : clipper.planes()) {
    const auto k = rational_plane(f);
    std::vector<Rational> v;
    int pos = 0, neg = 0;
    for (const RPoint& p : ring) {
      v.push_back(rational_value(k, p));
      pos += v.back() > 0;
      neg += v.back() < 0;
    }
    if (pos == 0) return {};
    if (neg == 0) continue;
    std::vector<RPoint> out;
    for (size_t i = 0; i < ring.size(); ++i) {
      const size_t j = (i + 1) % ring.size();
      if (v[i] >= 0) out.push_back(ring[i]);
      if ((v[i] > 0 && v[j] < 0) || (v[i] < 0 && v[j] > 0)) {
        const Rational t = v[i] / (v[i] - v[j]);
        RPoint x;
        for (int c = 0; c < 3; ++c) x[c] = ring[i][c] + t * (ring[j][c] - ring[i][c]);
        out.push_back(x);
      }
    }
    ring = std::move(out);
    if (ring.size() < 3) return {};
  }
  return ring;
}

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

// A random plane: unit normal n, orthonormal e1, e2 in it, a point o.
struct Frame {
  Vec3 n, e1, e2, o;
};
Frame random_frame(std::mt19937_64& rng, std::uniform_real_distribution<double>& u) {
  Frame f;
  f.n = random_unit(rng);
  f.e1 = f.n.unitOrthogonal();
  f.e2 = f.n.cross(f.e1);
  f.o = Vec3(u(rng), u(rng), u(rng));
  return f;
}

// The coordinate axis along which a plane's normal is largest (the projection axis).
int dominant_axis(const ExactPlane& f) {
  int axis = 0;
  f.normal().cwiseAbs().maxCoeff(&axis);
  return axis;
}

// The plane through p, q and p + d, its positive side holding `inside`.
ExactPlane toward(const Vec3& p, const Vec3& q, const Vec3& d, const Vec3& inside) {
  const ExactPlane f = ExactPlane::through(p, q, p + d);
  return side_of_plane(f, inside) == Sign::Negative ? f.flipped() : f;
}

// Three clipper planes through one line that crosses the polygon's plane at X, a point that is
// no double: the first two bound a wedge with its apex at X, the third holds the wedge and
// passes through X. Rounded, the apex made by the second plane lies off the third by ulps; a
// decision on it cut a sliver off the apex (an extra vertex) for some of these seeds.
TEST(PolygonClip, OpenClipDecidesAVertexOnALaterPlaneExactly) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(-1, 1);
  int rounded_apex_outside = 0;
  for (int seed = 0; seed < 200; ++seed) {
    const auto [n, e1, e2, o] = random_frame(rng, u);
    const Polygon3 tri{o + 3 * e1, o - 1.5 * e1 + 2.6 * e2, o - 1.5 * e1 - 2.6 * e2};
    const ExactPlane plane = ExactPlane::through(tri[0], tri[1], tri[2]);
    const int axis = dominant_axis(plane);
    // The line PQ, slanted, through the polygon's plane near o.
    const Vec3 slant = (n + 0.3 * random_unit(rng)).normalized();
    const Vec3 centre = o + 0.2 * u(rng) * e1 + 0.2 * u(rng) * e2;
    const Vec3 p = centre + 0.7 * slant, q = centre - 0.9 * slant;
    const Vec3 w1 = slant.unitOrthogonal(), w2 = slant.cross(w1);
    const auto dir = [&](double angle) { return std::cos(angle) * w1 + std::sin(angle) * w2; };
    const double a = 2 * std::numbers::pi * (u(rng) + 1) / 2, b = a + 0.8 + 0.5 * u(rng);
    const Vec3 mid = p + dir((a + b) / 2);
    const ExactPlane f1 = toward(p, q, dir(a), mid), f2 = toward(p, q, dir(b), mid);
    const ExactPlane f3 = toward(p, q, dir(a - 0.4), mid);
    const auto wedge = ConvexClipper::from_planes({f1, f2});
    const auto all = ConvexClipper::from_planes({f1, f2, f3});
    PolygonClipScratch scratch;
    Polygon3 two, three;
    ASSERT_TRUE(clip_convex_polygon_open(tri, plane, axis, true, wedge, two, scratch)) << seed;
    ASSERT_TRUE(clip_convex_polygon_open(tri, plane, axis, true, all, three, scratch)) << seed;
    // The third plane holds the wedge exactly: it changes nothing.
    EXPECT_EQ(three, two) << "seed " << seed;
    // The apex X: the line PQ meets the plane.
    const auto own = rational_plane(plane);
    const Rational vp = rational_value(own, rational_point(p)), vq = rational_value(own, rational_point(q));
    const Rational t = vp / (vp - vq);
    Vec3 apex;
    for (int c = 0; c < 3; ++c)
      apex[c] = CGAL::to_double(Rational(p[c]) + t * (Rational(q[c]) - Rational(p[c])));
    int near_apex = 0;
    for (const Vec3& v : two) {
      near_apex += (v - apex).cwiseAbs().maxCoeff() < 1e-12;
      if ((v - apex).cwiseAbs().maxCoeff() < 1e-12 && side_of_plane(f3, v) == Sign::Negative)
        ++rounded_apex_outside;
    }
    EXPECT_EQ(near_apex, 1) << "seed " << seed;
  }
  // Deciding on the rounded apex would have cut these.
  EXPECT_GT(rounded_apex_outside, 10);
}

// Random triangles and rounded (not exactly planar) quadrilaterals in generic planes against
// random clippers: the same vertices as the exact rational clipping of the lifted polygon, each
// within its tracked error bound.
TEST(PolygonClip, OpenClipMatchesExactRationalsWithinItsBound) {
  std::mt19937_64 rng(1414);
  std::uniform_real_distribution<double> u(-1, 1);
  int clipped = 0;
  for (int seed = 0; seed < 300; ++seed) {
    const auto [n, e1, e2, o] = random_frame(rng, u);
    Polygon3 poly;
    if (seed % 2 == 0) {
      poly = {o + 2 * e1, o - e1 + 1.7 * e2, o - e1 - 1.7 * e2};
    } else {
      poly = {o + e1 + e2, o - e1 + e2, o - e1 - e2, o + e1 - e2};  // rounded: folds by ulps
    }
    const ExactPlane plane = ExactPlane::through(poly[0], poly[1], poly[2]);
    const int axis = dominant_axis(plane);
    std::vector<ExactPlane> planes;
    const int count = 3 + seed % 4;
    for (int i = 0; i < count; ++i) {
      const Vec3 a = o + 0.8 * Vec3(u(rng), u(rng), u(rng));
      const Vec3 b = a + random_unit(rng), c = a + random_unit(rng);
      const ExactPlane f = ExactPlane::through(a, b, c);
      planes.push_back(side_of_plane(f, o) == Sign::Negative ? f.flipped() : f);
    }
    const auto clipper = ConvexClipper::from_planes(planes);
    PolygonClipScratch scratch;
    Polygon3 out;
    const bool any = clip_convex_polygon_open(poly, plane, axis, seed % 2 == 0, clipper, out, scratch);
    const std::vector<RPoint> exact = exact_open_clip(poly, plane, axis, clipper);
    ASSERT_EQ(any, !exact.empty()) << "seed " << seed;
    if (!any) continue;
    ++clipped;
    ASSERT_EQ(out.size(), exact.size()) << "seed " << seed;
    for (size_t i = 0; i < out.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        // An input vertex keeps its own coordinates: its lift is within the bound too.
        EXPECT_LE(CGAL::abs(Rational(out[i][c]) - exact[i][c]), Rational(scratch.error[i]))
            << "seed " << seed << " vertex " << i;
      }
  }
  EXPECT_GT(clipped, 100);
}

TEST(PolygonClip, BadInput) {
  EXPECT_THROW(clip_polygon(Polygon3{{0, 0, 0}, {1, 0, 0}}, half_space(1, 0, 0, 0)), InvalidInput);
  EXPECT_THROW(clip_polygon(Polygon3{{0, 0, 0}, {1, 0, 0}, {0, NAN, 0}}, half_space(1, 0, 0, 0)),
               InvalidInput);
}

}  // namespace
}  // namespace hedra
