// The exact plane splitting's internals (kernel/src/decompose/split_internal.h): how large the
// exact coordinates of the points made by cuts become.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <gmpxx.h>

#include "decompose/split_internal.h"
#include "hedra/core/primitives.h"
#include "testing/decomposition_suite.h"

namespace hedra::internal {
namespace {

size_t bits(const EK::FT& x) {
  const mpq_class& q = CGAL::exact(x);
  return std::max(mpz_sizeinbase(q.get_num_mpz_t(), 2), mpz_sizeinbase(q.get_den_mpz_t(), 2));
}

EK::FT volume6(const Piece& piece) {
  EK::FT v = 0;
  for (const Tri& t : piece.tris)
    v += CGAL::determinant(piece.pts[t.v[0]].p - CGAL::ORIGIN, piece.pts[t.v[1]].p - CGAL::ORIGIN,
                           piece.pts[t.v[2]].p - CGAL::ORIGIN);
  return v;
}

// Bug: the point where a cut crossed an edge was built from the edge's two ends, which were
// themselves points made by earlier cuts. On a rotated body (faces coplanar only within
// rounding, so never re-triangulated) every cut through a region deepened its points, and
// their exact coordinates grew by about 150 bits a cut: a rotated 35-point star prism took
// minutes to decompose, spent in GMP's gcd. Now the parts of a folded triangle are
// re-triangulated together (Tri::own), which removes the points cuts leave on their
// diagonals, so the size stays bounded however many cuts cross the same place. Checked on a
// binary space partition of a rotated star prism by every one of its face planes (each region
// of the top face is cut again and again), with the exact volume kept.
TEST(Split, CutPointsOfARotatedBodyStayBoundedUnderRepeatedCuts) {
  const Body body = suite::rotated(prism(suite::star(12, 1, 0.45), 0, 1));
  Context ctx;
  const Piece whole = piece_of(body, ctx);
  const EK::FT volume = volume6(whole);
  std::vector<Piece> pieces{whole};
  const int planes = static_cast<int>(ctx.planes.size());
  size_t largest = 0;
  int cuts = 0;
  for (int plane = 0; plane < planes; ++plane) {
    std::vector<Piece> next;
    for (const Piece& piece : pieces) {
      Sides sides = split_piece(ctx, piece, plane);
      cuts += sides.cut;
      for (auto* side : {&sides.below, &sides.above})
        for (Piece& p : *side) {
          simplify(ctx, p);
          for (const Point& q : p.pts) largest = std::max({largest, bits(q.p.x()), bits(q.p.y()), bits(q.p.z())});
          next.push_back(std::move(p));
        }
    }
    pieces = std::move(next);
  }
  EXPECT_GT(cuts, 100);
  EXPECT_GT(pieces.size(), 50u);
  EK::FT sum = 0;
  for (const Piece& p : pieces) sum += volume6(p);
  EXPECT_TRUE(sum == volume);
  EXPECT_LE(largest, 1500u);  // 1157 now; 2098 before, growing with the number of cuts
}

}  // namespace
}  // namespace hedra::internal
