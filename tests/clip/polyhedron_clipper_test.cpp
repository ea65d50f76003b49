// Clipping segments against non-convex bodies without decomposing them (PolyhedronClipper),
// differentially against the clipping of the body's exact convex decomposition, and against
// Body::classify (exact ray parity) at sample points.
#include "hedra/clip/polyhedron_clipper.h"

#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>

#include "hedra/core/error.h"
#include "hedra/core/primitives.h"
#include "hedra/decompose/decompose.h"
#include "hedra/mesh/convexity.h"
#include "testing/clip_fixtures.h"
#include "testing/decomposition_suite.h"

namespace hedra {
namespace {

// The body with every vertex rounded to float32 and every face fanned into triangles, as an
// STL file stores it: each triangle exactly planar, the surface exactly non-convex where the
// rounding bends a face the wrong way.
Body float32_triangles(const Body& body) {
  std::vector<Vec3> v;
  for (const Vec3& p : body.vertices())
    v.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  std::vector<Face> faces;
  for (const Triangle& t : body.triangles()) faces.push_back(Face{t.v[0], t.v[1], t.v[2]});
  return Body(v, faces);
}

Body float32_sphere() { return float32_triangles(sphere({0.1, 0.2, 0.3}, 1.5, 0.02)); }

std::vector<ConvexClipper> pieces_of(const Body& body) {
  std::vector<ConvexClipper> pieces;
  for (const Body& piece : decompose(body).pieces) pieces.emplace_back(piece);
  return pieces;
}

// Segments that hit the degenerate cases: random points, points on a grid of the body's
// coordinates (faces, edges, vertices), vertex to vertex (edges, face diagonals), through a
// vertex, and in the planes of faces.
// "x y z -> x y z" with every digit (%.17g).
std::string text(const Vec3& p1, const Vec3& p2) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g -> %.17g %.17g %.17g", p1.x(), p1.y(), p1.z(),
                p2.x(), p2.y(), p2.z());
  return buf;
}

std::vector<std::pair<Vec3, Vec3>> segments_for(const Body& body, int count, std::mt19937_64& rng) {
  const auto& v = body.vertices();
  const Eigen::AlignedBox3d box = body.bbox();
  const Vec3 lo = box.min() - 0.3 * box.sizes(), hi = box.max() + 0.3 * box.sizes();
  std::uniform_real_distribution<double> u(0, 1);
  std::uniform_int_distribution<size_t> pick(0, v.size() - 1);
  std::uniform_int_distribution<int> kind(0, 6);
  const auto random_point = [&] {
    return Vec3(lo.x() + (hi.x() - lo.x()) * u(rng), lo.y() + (hi.y() - lo.y()) * u(rng),
                lo.z() + (hi.z() - lo.z()) * u(rng));
  };
  // A coordinate of some vertex or a half-way value between two (grid of the body).
  const auto grid = [&](int axis) {
    const double a = v[pick(rng)][axis], b = v[pick(rng)][axis];
    switch (static_cast<int>(u(rng) * 4)) {
      case 0: return a;
      case 1: return 0.5 * (a + b);
      case 2: return lo[axis] + (hi[axis] - lo[axis]) * u(rng);
      default: return a + (a - b);
    }
  };
  const auto grid_point = [&] { return Vec3(grid(0), grid(1), grid(2)); };
  std::vector<std::pair<Vec3, Vec3>> out;
  while (static_cast<int>(out.size()) < count) {
    Vec3 p1, p2;
    switch (kind(rng)) {
      case 0: p1 = random_point(), p2 = random_point(); break;
      case 1: p1 = grid_point(), p2 = grid_point(); break;
      case 2: p1 = v[pick(rng)], p2 = v[pick(rng)]; break;
      case 3: {  // through a vertex (exactly when 2v − p1 is representable)
        const Vec3 w = v[pick(rng)];
        p1 = grid_point();
        p2 = 2 * w - p1;
        break;
      }
      case 4: {  // in the plane of a face, through its support triple
        const Face& f = body.faces()[pick(rng) % body.faces().size()];
        const Vec3 a = v[f.loops[0][0]], b = v[f.loops[0][1]], c = v[f.loops[0][2]];
        const double s1 = 2 * u(rng) - 0.5, r1 = 2 * u(rng) - 0.5, s2 = 2 * u(rng) - 0.5,
                     r2 = 2 * u(rng) - 0.5;
        p1 = a + s1 * (b - a) + r1 * (c - a);
        p2 = a + s2 * (b - a) + r2 * (c - a);
        break;
      }
      case 5: {  // along a vertical line through a vertex (prism edges)
        const Vec3 w = v[pick(rng)];
        p1 = Vec3(w.x(), w.y(), grid(2));
        p2 = Vec3(w.x(), w.y(), grid(2));
        break;
      }
      default: {  // a vertex to a random point
        p1 = v[pick(rng)];
        p2 = u(rng) < 0.5 ? random_point() : grid_point();
        if (u(rng) < 0.5) std::swap(p1, p2);
      }
    }
    out.emplace_back(p1, p2);
  }
  return out;
}

struct Differences {
  int segments = 0;
  int different_parts = 0;   // part counts or point flags differ
  int different_points = 0;  // an end point differs
  int joined_gaps = 0;       // decomposition gaps of rounding size joined before comparing
  double largest_gap = 0;    // largest |coordinate difference| of end points
  bool report = true;        // each different part count is a failure
};

struct Part {
  Vec3 a, b;
  bool point;
};

// The decomposition's parts as points, with the artifacts of its rounded cut vertices removed
// (docs/clipping.md): inside parts that meet across a gap of at most `tol` are joined, and
// outside parts that short are dropped. Each such repair is counted.
std::vector<Part> decomposition_parts(const std::vector<ConvexClipper>& pieces, const Vec3& p1,
                                      const Vec3& p2, bool outside, double tol, int& joined) {
  std::vector<Part> out;
  const std::vector<ClipPart> parts =
      outside ? clip_segment_outside(pieces, p1, p2) : clip_segment(pieces, p1, p2);
  for (const ClipPart& p : parts) {
    const Part part{end_point(pieces, p.start, p1, p2), end_point(pieces, p.end, p1, p2), p.point};
    if (outside && !part.point && (part.b - part.a).cwiseAbs().maxCoeff() <= tol) {
      ++joined;
      continue;
    }
    if (!outside && !out.empty() && (part.a - out.back().b).cwiseAbs().maxCoeff() <= tol) {
      ++joined;
      out.back().b = part.b;
      out.back().point = false;
      continue;
    }
    out.push_back(part);
  }
  return out;
}

// The direct parts against the decomposition's, inside and outside.
void compare(const PolyhedronClipper& direct, const std::vector<ConvexClipper>& pieces,
             const Vec3& p1, const Vec3& p2, Differences& d, bool outside) {
  const std::vector<ClipPart> a =
      outside ? clip_segment_outside(direct, p1, p2) : clip_segment(direct, p1, p2);
  // Gaps of rounding size are joined only where the decomposition rounds (not `report`): exact
  // decompositions are compared as they are (a segment may pass within an ulp of a corner).
  const double tol = d.report ? -1 : 1e-12 * direct.body().scale();
  const std::vector<Part> b = decomposition_parts(pieces, p1, p2, outside, tol, d.joined_gaps);
  ++d.segments;
  bool same = a.size() == b.size();
  for (size_t i = 0; same && i < a.size(); ++i) same = a[i].point == b[i].point;
  if (!same) {
    ++d.different_parts;
    if (d.report)
      ADD_FAILURE() << (outside ? "outside" : "inside") << ": " << a.size() << " direct parts, "
                    << b.size() << " decomposition parts for " << text(p1, p2);
    return;
  }
  bool points_equal = true;
  for (size_t i = 0; i < a.size(); ++i) {
    const Vec3 a0 = end_point(direct, a[i].start, p1, p2), a1 = end_point(direct, a[i].end, p1, p2);
    d.largest_gap = std::max({d.largest_gap, (a0 - b[i].a).cwiseAbs().maxCoeff(),
                              (a1 - b[i].b).cwiseAbs().maxCoeff()});
    points_equal = points_equal && a0 == b[i].a && a1 == b[i].b;
  }
  if (!points_equal) ++d.different_points;
}

// The independent exact oracle: the body's triangles as a CGAL surface mesh with exact rational
// coordinates, and CGAL's point-in-mesh test (ray shooting, exact in this kernel) at exact
// rational points of the segment.
using EK = CGAL::Simple_cartesian<testing::Rational>;
using ExactMesh = CGAL::Surface_mesh<EK::Point_3>;

class ExactSolid {
 public:
  explicit ExactSolid(const Body& body) {
    std::vector<ExactMesh::Vertex_index> index;
    for (const Vec3& p : body.vertices()) index.push_back(mesh_.add_vertex(point(p)));
    for (const Triangle& t : body.triangles())
      mesh_.add_face(index[static_cast<size_t>(t.v[0])], index[static_cast<size_t>(t.v[1])],
                     index[static_cast<size_t>(t.v[2])]);
    side_ = std::make_unique<CGAL::Side_of_triangle_mesh<ExactMesh, EK>>(mesh_);
  }
  static EK::Point_3 point(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
  CGAL::Bounded_side at(const Vec3& p1, const Vec3& p2, const testing::Rational& t) const {
    const EK::Point_3 a = point(p1), b = point(p2);
    return (*side_)(a + (b - a) * t);
  }

 private:
  ExactMesh mesh_;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<ExactMesh, EK>> side_;
};

// The exact parameter of a part's end.
testing::Rational exact_t(const PolyhedronClipper& direct, const ClipEnd& end, const Vec3& p1,
                          const Vec3& p2) {
  if (end.plane < 0) return end.t;
  const ExactPlane f = direct.plane(end.plane);
  const testing::Rational w = testing::exact_value(f, p1), e = testing::exact_value(f, p2);
  return w / (w - e);
}

// The direct parts against the exact oracle: ends in order, every end and every part's middle
// in the closed body, a single point on its boundary, every gap's middle outside. Returns
// whether all hold.
bool matches_exact_solid(const PolyhedronClipper& direct, const ExactSolid& solid,
                         const std::vector<ClipPart>& parts, const Vec3& p1, const Vec3& p2) {
  using testing::Rational;
  if (p1 == p2) return parts.empty() == (solid.at(p1, p2, 0) == CGAL::ON_UNBOUNDED_SIDE);
  const auto outside = [&](const Rational& t) {
    return solid.at(p1, p2, t) == CGAL::ON_UNBOUNDED_SIDE;
  };
  // Whether the open interval (a, b) is outside (or, `want_outside` false, in the body) at
  // five exact points.
  const auto interval = [&](const Rational& a, const Rational& b, bool want_outside) {
    for (int k = 1; k <= 5; ++k)
      if (outside(a + (b - a) * Rational(k, 6)) != want_outside) return false;
    return true;
  };
  Rational previous = 0;  // the end of the last part
  bool first = true;
  for (const ClipPart& part : parts) {
    const Rational a = exact_t(direct, part.start, p1, p2), b = exact_t(direct, part.end, p1, p2);
    if (b < a || part.point != (a == b)) return false;
    if (first ? a > 0 && (!outside(0) || !interval(0, a, true))
              : !(previous < a) || !interval(previous, a, true))
      return false;  // the gap before the part
    if (outside(a) || outside(b) || (a < b && !interval(a, b, false))) return false;
    if (part.point && a > 0 && a < 1 && solid.at(p1, p2, a) != CGAL::ON_BOUNDARY) return false;
    previous = b;
    first = false;
  }
  if (first) return outside(0) && interval(0, 1, true) && outside(1);
  return previous == 1 || (interval(previous, 1, true) && outside(1));
}

// Every direct result is checked against the exact oracle; the decomposition's are compared
// with it (inside and outside), a difference failing the test when `strict`.
Differences run_differential(const Body& body, int count, std::uint64_t seed, bool strict = true) {
#ifdef HEDRA_SANITIZED
  count = std::max(count / 10, 20);  // exact oracles under ASan + UBSan: a tenth of the segments
#endif
  EXPECT_FALSE(is_convex(body));
  const PolyhedronClipper direct(body);
  const std::vector<ConvexClipper> pieces = pieces_of(body);
  const ExactSolid solid(body);
  std::mt19937_64 rng(seed);
  Differences d;
  d.report = strict;
  for (const auto& [p1, p2] : segments_for(body, count, rng)) {
    const std::vector<ClipPart> parts = clip_segment(direct, p1, p2);
    EXPECT_TRUE(matches_exact_solid(direct, solid, parts, p1, p2)) << text(p1, p2);
    compare(direct, pieces, p1, p2, d, false);
    compare(direct, pieces, p1, p2, d, true);
  }
  return d;
}

// Hand-made degenerate cases on the L prism {0 ≤ x ≤ 4, 0 ≤ y ≤ 1} ∪ {0 ≤ x ≤ 1, 0 ≤ y ≤ 3},
// 0 ≤ z ≤ 2, with their exact end points.
TEST(PolyhedronClipper, LPrismDegenerateCases) {
  const PolyhedronClipper l(suite::shapes(false)[0].body);
  struct Case {
    Vec3 p1, p2;
    std::vector<std::pair<Vec3, Vec3>> parts;  // end points
    std::vector<std::pair<Vec3, Vec3>> outside;
  };
  const std::vector<Case> cases = {
      // Across the foot: x in [0, 4].
      {{-1, 0.5, 1}, {5, 0.5, 1}, {{{0, 0.5, 1}, {4, 0.5, 1}}},
       {{{-1, 0.5, 1}, {0, 0.5, 1}}, {{4, 0.5, 1}, {5, 0.5, 1}}}},
      // In the plane x = 1 (inside the body, where a decomposition cuts): y in [0, 3].
      {{1, -1, 1}, {1, 4, 1}, {{{1, 0, 1}, {1, 3, 1}}}, {{{1, -1, 1}, {1, 0, 1}}, {{1, 3, 1}, {1, 4, 1}}}},
      // Across the notch: two parts.
      {{0.5, 2.5, 1}, {3.5, 0.5, 1}, {{{0.5, 2.5, 1}, {1, 2.1666666666666665, 1}}, {{2.75, 1, 1}, {3.5, 0.5, 1}}},
       {{{1, 2.1666666666666665, 1}, {2.75, 1, 1}}}},
      // Touching the corner (4, 1, 2) only: a single point; outside, the whole segment.
      {{3, 2, 2}, {5, 0, 2}, {{{4, 1, 2}, {4, 1, 2}}}, {{{3, 2, 2}, {5, 0, 2}}}},
      // Along the bottom edge y = z = 0: x in [0, 4], on the boundary.
      {{-1, 0, 0}, {5, 0, 0}, {{{0, 0, 0}, {4, 0, 0}}}, {{{-1, 0, 0}, {0, 0, 0}}, {{4, 0, 0}, {5, 0, 0}}}},
      // Along the reflex edge x = y = 1: z in [0, 2].
      {{1, 1, -1}, {1, 1, 3}, {{{1, 1, 0}, {1, 1, 2}}}, {{{1, 1, -1}, {1, 1, 0}}, {{1, 1, 2}, {1, 1, 3}}}},
      // In the notch, through the reflex edge's line beyond the body: nothing inside.
      {{1.5, 1.5, 1}, {3, 3, 1}, {}, {{{1.5, 1.5, 1}, {3, 3, 1}}}},
      // Through the reflex edge from the notch into the body: it only passes the edge, then
      // runs inside.
      {{2, 2, 1}, {0.5, 0.5, 1}, {{{1, 1, 1}, {0.5, 0.5, 1}}}, {{{2, 2, 1}, {1, 1, 1}}}},
      // In the top face plane z = 2, across the notch: two parts on the boundary.
      {{0.5, 2.5, 2}, {3.5, 0.5, 2}, {{{0.5, 2.5, 2}, {1, 2.1666666666666665, 2}}, {{2.75, 1, 2}, {3.5, 0.5, 2}}},
       {{{1, 2.1666666666666665, 2}, {2.75, 1, 2}}}},
      // Points: inside, on a vertex, outside.
      {{0.5, 0.5, 1}, {0.5, 0.5, 1}, {{{0.5, 0.5, 1}, {0.5, 0.5, 1}}}, {}},
      {{4, 1, 2}, {4, 1, 2}, {{{4, 1, 2}, {4, 1, 2}}}, {}},
      {{2, 2, 1}, {2, 2, 1}, {}, {{{2, 2, 1}, {2, 2, 1}}}},
  };
  const auto points = [&](const std::vector<ClipPart>& parts, const Vec3& p1, const Vec3& p2) {
    std::vector<std::pair<Vec3, Vec3>> out;
    for (const ClipPart& p : parts)
      out.emplace_back(end_point(l, p.start, p1, p2), end_point(l, p.end, p1, p2));
    return out;
  };
  for (const Case& c : cases) {
    EXPECT_EQ(points(clip_segment(l, c.p1, c.p2), c.p1, c.p2), c.parts) << text(c.p1, c.p2);
    EXPECT_EQ(points(clip_segment_outside(l, c.p1, c.p2), c.p1, c.p2), c.outside)
        << text(c.p1, c.p2);
  }
  EXPECT_THROW(clip_segment(l, {0, 0, NAN}, {1, 1, 1}), InvalidInput);
  EXPECT_THROW(clip_segment(l, {0, 0, 1e110}, {1, 1, 1}), InvalidInput);  // beyond kMaxAbsCoordinate
}

// The oracle is not vacuous: it rejects a missing part, a part too long and a spurious one.
TEST(PolyhedronClipper, OracleRejectsWrongParts) {
  const Body l = suite::shapes(false)[0].body;  // the L prism
  const PolyhedronClipper direct(l);
  const ExactSolid solid(l);
  const Vec3 p1(-1, 0.5, 1), p2(5, 0.5, 1);  // x in [0, 4]: t in [1/6, 5/6]
  std::vector<ClipPart> parts = clip_segment(direct, p1, p2);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_TRUE(matches_exact_solid(direct, solid, parts, p1, p2));
  EXPECT_FALSE(matches_exact_solid(direct, solid, {}, p1, p2));
  std::vector<ClipPart> longer = parts;
  longer[0].end = {1, -1, 0};
  EXPECT_FALSE(matches_exact_solid(direct, solid, longer, p1, p2));
  EXPECT_FALSE(matches_exact_solid(direct, solid, parts, Vec3(-1, 2, 1), Vec3(5, 2, 1)));
}

// Bodies with integer coordinates: the decomposition's cut vertices are exact too, so the
// same parts and the very same end points, without any repair.
TEST(PolyhedronClipper, SameAsDecompositionOnIntegerBodies) {
  std::uint64_t seed = 100;
  for (const suite::Shape& shape : suite::shapes(false)) {
    if (shape.name.find("star") != std::string::npos) continue;
    SCOPED_TRACE(shape.name);
    const Differences d = run_differential(shape.body, 300, ++seed);
    EXPECT_EQ(d.different_parts, 0);
    EXPECT_EQ(d.different_points, 0) << "largest difference " << d.largest_gap;
  }
}

// Star prisms: exactly planar faces, irrational corners. The decomposition rounds the cut
// vertices that doubles cannot hold, and its pieces' faces through them are then off the body's
// faces by rounding: a segment crossing such a cut face shows a gap of rounding size (joined
// before comparing), and a segment running exactly along an edge there can lose its part (the
// decomposition's documented artifact). The direct path has no cut faces: every one of its
// results agrees with the exact oracle, and with the decomposition wherever the decomposition is
// not off by its rounding.
TEST(PolyhedronClipper, StarPrismsExactWhereTheDecompositionRounds) {
  std::uint64_t seed = 200;
  for (const suite::Shape& shape : suite::shapes(false)) {
    if (shape.name.find("star") == std::string::npos) continue;
    SCOPED_TRACE(shape.name);
    const Differences d = run_differential(shape.body, 400, ++seed, false);
    EXPECT_LE(d.different_parts, d.segments / 20);
    std::printf("%s: %d comparisons, %d with other parts and %d with other end points in the "
                "decomposition (largest difference %.3g), %d of its gaps joined\n",
                shape.name.c_str(), d.segments, d.different_parts, d.different_points,
                d.largest_gap, d.joined_gaps);
  }
}

// Rotated bodies: faces planar only within rounding. The direct path takes the triangulated
// boundary as the body, exactly (by the oracle); the decomposition each face's support plane and
// rounded cut vertices. They differ by rounding, which segments nearly parallel to a face (those
// drawn in a face plane, rounded) turn into large differences of parameter: the comparison is
// reported, not asserted.
TEST(PolyhedronClipper, RotatedBodiesExactOnTheirTriangles) {
  std::uint64_t seed = 300;
  const std::vector<suite::Shape> shapes = {
      {"rotated L prism", suite::rotated(suite::shapes(false)[0].body)},
      {"rotated star 8", suite::rotated(prism(suite::star(8, 2.5, 1), 0, 1))}};
  for (const suite::Shape& shape : shapes) {
    SCOPED_TRACE(shape.name);
    const Differences d = run_differential(shape.body, 400, ++seed, false);
    std::printf("%s: %d comparisons, %d with other parts and %d with other end points in the "
                "decomposition (largest difference %.3g), %d of its gaps joined\n",
                shape.name.c_str(), d.segments, d.different_parts, d.different_points,
                d.largest_gap, d.joined_gaps);
  }
}

// A float32 sphere of several hundred triangles (each exactly planar, the surface exactly
// non-convex): exact by the oracle; the decomposition's results agree up to its rounding.
TEST(PolyhedronClipper, Float32Sphere) {
  const Body s = float32_sphere();
  ASSERT_GE(s.face_count(), 400);
  ASSERT_LE(s.face_count(), 800);
  const Differences d = run_differential(s, 600, 7, false);
  EXPECT_LE(d.different_parts, d.segments / 20);
  std::printf("float32 sphere (%d triangles): %d comparisons, %d with other parts and %d with "
              "other end points in the decomposition (largest difference %.3g), %d of its gaps "
              "joined\n", s.face_count(), d.segments, d.different_parts, d.different_points,
              d.largest_gap, d.joined_gaps);
}

}  // namespace
}  // namespace hedra
