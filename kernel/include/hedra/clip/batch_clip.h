// Clipping millions of segments against one convex clipper: structure-of-arrays input, a
// branch-free inner loop over four segments at a time (GCC/Clang vector extensions: AVX2 where
// the CPU has it, else SSE2), TBB threads for large batches, and results
// identical, bit for bit, to the scalar Cyrus–Beck (hedra/clip/cyrus_beck.h).
//
// How the results stay identical: the vectorized loop evaluates the same double expressions as
// the scalar path (ExactPlane::value, crossing_from_values) and accepts a segment only when
// every decision is certain under error bounds no smaller than the scalar path's: each end
// point's side of each plane, which crossing is the exact maximum of the lower and the exact
// minimum of the upper bounds (the largest computed t ahead of the second largest by more than
// twice the bound), and the order of those two. Any segment with a doubtful decision (an end
// point within rounding of a plane, near-equal crossings, a touching segment, non-finite
// input) goes through the scalar clip_segment, which decides exactly. On random data that is a
// vanishing fraction; on data built to be degenerate it can be all of it, and the batch is then
// as fast as the scalar path.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "hedra/clip/convex_clipper.h"
#include "hedra/clip/cyrus_beck.h"

namespace hedra {

/// Segments as structure of arrays: segment i runs from (x1[i], y1[i], z1[i]) to
/// (x2[i], y2[i], z2[i]).
struct SegmentArrays {
  std::vector<double> x1, y1, z1, x2, y2, z2;

  size_t size() const { return x1.size(); }
  void resize(size_t n);
  void reserve(size_t n);
  void push_back(const Vec3& p1, const Vec3& p2);
  Vec3 start(size_t i) const { return {x1[i], y1[i], z1[i]}; }
  Vec3 end(size_t i) const { return {x2[i], y2[i], z2[i]}; }
};

/// Flags of one result.
enum BatchClipFlag : std::uint8_t {
  kClipVisible = 1,    // some part is inside
  kClipPoint = 2,      // that part is a single point
  kClipExactPath = 4,  // the segment went through the scalar exact path (a statistic)
};

/// Result i is clip_segment(clipper, start(i), end(i)): when visible, the part
/// [t_start[i], t_end[i]] with the planes that fix its ends (−1: the segment's own end).
/// Entries of invisible segments are 0, 0, −1, −1.
struct BatchClipResult {
  std::vector<double> t_start, t_end;
  std::vector<std::int32_t> start_plane, end_plane;
  std::vector<std::uint8_t> flags;

  size_t size() const { return flags.size(); }
  void resize(size_t n);
  bool visible(size_t i) const { return flags[i] & kClipVisible; }
  /// The part as clip_segment returns it (piece 0). \pre visible(i).
  ClipPart part(size_t i) const;
};

struct BatchClipOptions {
  /// Worker threads: 0 uses TBB's default (every core); 1 runs on the calling thread.
  int threads = 0;
  /// Batches smaller than this run on the calling thread (threads do not pay off).
  size_t min_parallel = size_t{1} << 15;
  /// false: use the x86-64 baseline (SSE2) code even on a CPU with AVX2 (for tests and
  /// comparisons; the results are the same).
  bool allow_avx2 = true;
};

/// Clips every segment of `segments` against `clipper`; `out` is resized to match and
/// equals the scalar clip_segment result for result, bit for bit, for any thread count.
/// \throw InvalidInput for a non-finite coordinate or one beyond ±kMaxAbsCoordinate (as
///   clip_segment). Cost O(n·planes) with vectorized arithmetic; memory-bandwidth bound for
///   small clippers.
void clip_batch(const ConvexClipper& clipper, const SegmentArrays& segments, BatchClipResult& out,
                const BatchClipOptions& options = {});

}  // namespace hedra
