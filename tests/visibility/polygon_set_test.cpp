// The exact 2D Boolean operations of hedra/visibility/polygon_set.h on regions (the rings that
// unite_convex chains), against the same operations on the pieces and against areas computed by
// hand or with exact rationals.
#include "hedra/visibility/polygon_set.h"

#include <gtest/gtest.h>

#include <random>

namespace hedra {
namespace {

Ring2 square(double x, double y, double s) {
  return {{x, y}, {x + s, y}, {x + s, y + s}, {x, y + s}};
}

double area_of(const Region2& region) {
  const std::optional<UnionResult> r = cgal_difference(region, {});
  EXPECT_TRUE(r.has_value());
  return r ? r->area : -1;
}

// Rings as unite_convex chains them can touch themselves (at a vertex they pass twice, or a
// vertex on another of their edges) and, after rounding, cross themselves by an ulp. The region
// is the points inside an odd number of the loops they split into.
TEST(PolygonSet, RingsThatTouchOrCrossThemselvesBoundTheirOddCoverage) {
  // Two squares meeting at a corner, chained as one ring through the corner twice.
  EXPECT_EQ(area_of({{{{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {1, 2}, {1, 1}, {0, 1}}, {}, 0}}), 2);
  // A vertex on another edge of the same ring, and an edge back along it: the triangle
  // (2,0) (4,0) (4,4) is all that is enclosed.
  EXPECT_EQ(area_of({{{{0, 0}, {4, 0}, {4, 4}, {2, 0}}, {}, 0}}), 4);
  // A bow tie: two triangles of area 1 (its signed area is 0).
  EXPECT_EQ(area_of({{{{0, 0}, {2, 2}, {2, 0}, {0, 2}}, {}, 0}}), 2);
  // An island inside another polygon's hole stays.
  EXPECT_EQ(area_of({{square(0, 0, 10), {{{2, 2}, {2, 8}, {8, 8}, {8, 2}}}, 0},
                     {square(4, 4, 2), {}, 0}}),
            100 - 36 + 4);
  // The four-vertex loop found on the edge of the shadow of the 986 048-triangle sphere on its
  // slab (issue 15's mesh scene): two of its edges cross 5.3e-13 of the way along one, an ulp
  // away from where the exact crossing of the pieces was. Its odd-coverage area, two triangles
  // meeting at the crossing, computed with exact rationals: 1.7302911928517004e-19 (its signed
  // area is -7.4e-20).
  const Region2 sliver{{{{-4, -1.4926789496891026},
                         {-3.9986076976140783, -1.4925382935135774},
                         {-4, -1.4930106858468366},
                         {-3.9986076976140787, -1.4925382935135776}},
                        {},
                        0}};
  EXPECT_NEAR(area_of(sliver), 1.7302911928517004e-19, 1e-12 * 1.7302911928517004e-19);
}

// Random convex pieces, half of them snapped to a grid (shared edges, vertices on edges, rings
// that pinch): the difference and the coverage levels of their unions equal those of the pieces.
TEST(PolygonSet, RegionsGiveTheDifferenceAndCountsOfTheirPieces) {
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(0, 1);
  const auto pieces = [&](int m, bool snap) {
    std::vector<Ring2> out;
    for (int k = 0; k < m; ++k) {
      const Vec2 c(10 * u(rng), 10 * u(rng));
      const double w = 0.5 + 2 * u(rng), h = 0.5 + 2 * u(rng);
      Ring2 r = u(rng) < 0.5 ? Ring2{c, c + Vec2(w, 0), c + Vec2(w, h), c + Vec2(0, h)}
                             : Ring2{c, c + Vec2(w, 0), c + Vec2(0.5 * w, h)};
      if (snap)
        for (Vec2& p : r) p = (p * 2).array().round() / 2;
      if (ring_area(r) > 0) out.push_back(r);
    }
    return out;
  };
  int snapped_pinches = 0;
#ifdef HEDRA_SANITIZED
  const int trials = 14;  // CGAL's exact references under ASan + UBSan: 20 s for 24 (13 is
                          // the first trial with a pinched ring)
#else
  const int trials = 24;
#endif
  for (int trial = 0; trial < trials; ++trial) {
    const bool snap = trial % 2 == 1;
    const std::vector<Ring2> a = pieces(4 + 2 * trial, snap), b = pieces(3 + trial, snap),
                             c = pieces(3 + trial, snap);
    const UnionResult ua = unite_convex(a, true), ub = unite_convex(b, true),
                      uc = unite_convex(c, true);
    for (const PolygonWithHoles2& p : ua.polygons)
      for (size_t i = 0; i < p.outer.size(); ++i)
        for (size_t j = i + 1; j < p.outer.size(); ++j) snapped_pinches += p.outer[i] == p.outer[j];

    const std::optional<UnionResult> mine = cgal_difference(ua.polygons, {ub.polygons, uc.polygons});
    std::vector<Ring2> bc = b;
    bc.insert(bc.end(), c.begin(), c.end());
    const UnionResult ref = cgal_difference(a, bc);
    ASSERT_TRUE(mine.has_value()) << trial;
    EXPECT_NEAR(mine->area, ref.area, 1e-12 * ua.area) << trial;
    EXPECT_EQ(mine->polygons.size(), ref.polygons.size()) << trial;

    const std::optional<std::vector<UnionResult>> levels =
        cgal_coverage_levels({ua.polygons, ub.polygons, uc.polygons});
    const std::vector<UnionResult> ref_levels = cgal_coverage_levels({a, b, c});
    ASSERT_TRUE(levels.has_value()) << trial;
    ASSERT_EQ(levels->size(), 3u);
    for (size_t k = 0; k < 3; ++k)
      EXPECT_NEAR((*levels)[k].area, ref_levels[k].area, 1e-12 * (ua.area + ub.area + uc.area))
          << trial << " level " << k + 1;
  }
  EXPECT_GT(snapped_pinches, 0);  // the pinched rings were exercised
}

}  // namespace
}  // namespace hedra
