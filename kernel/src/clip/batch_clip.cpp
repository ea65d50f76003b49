#include "hedra/clip/batch_clip.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "hedra/core/error.h"
#include "hedra/core/parallel.h"
#include "hedra/core/tolerance.h"

// The vector helpers below are internal and inlined, so GCC's note that passing 32-byte vectors
// without AVX changes the ABI does not concern them (it is emitted at the end of the file, hence
// for the whole file).
#pragma GCC diagnostic ignored "-Wpsabi"

namespace hedra {
namespace {

// Segments per block: a block is scanned in groups of four, and the segments it could not
// decide go through the exact path before the next block.
constexpr size_t kBlock = 256;
// Segments per TBB task.
constexpr size_t kGrain = 8 * kBlock;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Raw output columns for the vectorized scan (which touches nothing that can throw).
struct Output {
  double* t_start;
  double* t_end;
  std::int32_t* start_plane;
  std::int32_t* end_plane;
  std::uint8_t* flags;
};

// N segments side by side (GCC/Clang vector extensions): N = 4 fills an AVX register, N = 2
// an SSE2 one. Every operation is the IEEE operation of the scalar code, lane by lane, and a
// select `m ? a : b` is the scalar ternary, so each lane computes the scalar path's bits.
template <int N>
struct Lanes;
template <>
struct Lanes<2> {
  typedef double D __attribute__((vector_size(16)));
  typedef std::int64_t M __attribute__((vector_size(16)));  // comparison: −1 (true) or 0
  typedef std::int32_t I __attribute__((vector_size(8)));
  typedef std::uint8_t U __attribute__((vector_size(2)));
};
template <>
struct Lanes<4> {
  typedef double D __attribute__((vector_size(32)));
  typedef std::int64_t M __attribute__((vector_size(32)));
  typedef std::int32_t I __attribute__((vector_size(16)));
  typedef std::uint8_t U __attribute__((vector_size(4)));
};

template <class D>
D splat(double x) {
  return x - D{};  // x − 0 is x for every x, −0 included
}
template <class D>
D load(const double* p) {
  D v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <class D>
void store(double* p, const D& v) {
  std::memcpy(p, &v, sizeof v);
}
template <class D, class M>
D pick(const M& m, const D& a, const D& b) {  // m ? a : b, lane by lane
  if constexpr (sizeof(D) == 16) {
    // SSE2 has no blend and no 64-bit integer compare, which `m ? a : b` needs to turn an
    // integer mask into a selection; the masks are all ones or all zeros, so bit operations do.
    return std::bit_cast<D>((std::bit_cast<M>(a) & m) | (std::bit_cast<M>(b) & ~m));
  } else {
    return m ? a : b;
  }
}
// The comparison written into the ternary: GCC maps exactly this form to MAXPD / MINPD.
template <class D>
D larger(const D& a, const D& b) {
  return a > b ? a : b;
}
template <class D>
D smaller(const D& a, const D& b) {
  return a < b ? a : b;
}
template <class D, class M>
D absolute(const D& x) {  // std::abs: clears the sign bit
  return std::bit_cast<D>(std::bit_cast<M>(x) & (M{} + 0x7fffffffffffffff));
}

// A plane's double form, error bound and index, each spread over four lanes once per batch
// (N = 2 reads the first two).
struct alignas(32) PlaneData {
  double nx[4], ny[4], nz[4], k[4], slope[4], offset[4], index[4];
};

// Scans one block, N segments at a time with their state in registers while every plane is
// applied; writes the results it can certify and returns how many segments it could not,
// their offsets in `doubtful`. Which results it certifies, and why they equal the scalar
// path's, is in batch_clip.h. The bounds here are coarser than the scalar path's (max(|P1|, |P2|)
// for both ends; one crossing error for all crossings of a segment, from the largest plane bound
// and the smallest |w − e|): they certify less, never differently.
template <int N>
[[gnu::always_inline]] inline size_t scan_block(const PlaneData* planes, size_t plane_count,
                                                const PlaneData& largest, const SegmentArrays& seg,
                                                size_t begin, size_t count, const Output& out,
                                                std::uint16_t* doubtful) noexcept {
  using L = Lanes<N>;
  using D = typename L::D;
  using M = typename L::M;
  using I = typename L::I;
  using U = typename L::U;
  const D max_slope = load<D>(largest.slope), max_offset = load<D>(largest.offset);
  const double* columns[6] = {seg.x1.data() + begin, seg.y1.data() + begin, seg.z1.data() + begin,
                              seg.x2.data() + begin, seg.y2.data() + begin, seg.z2.data() + begin};
  const D zero = splat<D>(0), one = splat<D>(1), minus_one = splat<D>(-1);
  const D infinity = splat<D>(kInf), minus_infinity = splat<D>(-kInf);
  size_t doubtful_count = 0;
  for (size_t g = 0; g < count; g += N) {
    const size_t lanes = std::min<size_t>(N, count - g);
    // Inputs of N segments; a short last group repeats its first segment.
    D in[6];
    for (int c = 0; c < 6; ++c) {
      if (lanes == N) {
        in[c] = load<D>(columns[c] + g);
      } else {
        double pad[N];
        for (size_t l = 0; l < N; ++l) pad[l] = columns[c][g + (l < lanes ? l : 0)];
        in[c] = load<D>(pad);
      }
    }
    const D x1 = in[0], y1 = in[1], z1 = in[2], x2 = in[3], y2 = in[4], z2 = in[5];

    // Magnitude for the error bounds; out-of-range or NaN coordinates are left to the exact
    // path, which reports them.
    const D a1 = absolute<D, M>(x1), b1 = absolute<D, M>(y1), c1 = absolute<D, M>(z1);
    const D a2 = absolute<D, M>(x2), b2 = absolute<D, M>(y2), c2 = absolute<D, M>(z2);
    const D m = larger(larger(larger(a1, b1), c1), larger(larger(a2, b2), c2));
    const D limit = splat<D>(kMaxAbsCoordinate);
    const M valid = (a1 <= limit) & (b1 <= limit) & (c1 <= limit) & (a2 <= limit) & (b2 <= limit) &
                    (c2 <= limit);
    // The mask logic is done in doubles so that no step combines two masks (SSE2 has no
    // 64-bit integer compare, and GCC would turn `mask & mask` into lane-by-lane code):
    // every sign is certain iff min over planes of (min(|w|, |e|) − bound) > 0, and both ends
    // are surely outside one plane iff min over planes of (max(w, e) + bound) < 0 (the sign of
    // a rounded sum or difference is the sign of the exact one).
    D certainty = infinity, outside_margin = infinity;
    // Lower end: the largest crossing t so far (first plane on ties) and the second largest;
    // upper end likewise with the smallest. ±∞ start values lose against any crossing.
    D lo_t = minus_infinity, lo_second = minus_infinity, lo_plane = minus_one;
    D up_t = infinity, up_second = infinity, up_plane = minus_one;
    // The smallest |w − e| of a crossing: with the largest plane bound it bounds every
    // crossing's error (see below).
    D closest = infinity;

    for (size_t f = 0; f < plane_count; ++f) {
      const PlaneData& p = planes[f];
      const D nx = load<D>(p.nx), ny = load<D>(p.ny), nz = load<D>(p.nz), k = load<D>(p.k);
      // ExactPlane::value, operation for operation.
      const D w = ((nx * x1 + ny * y1) + nz * z1) + k;
      const D e = ((nx * x2 + ny * y2) + nz * z2) + k;
      // No smaller than either end's own bound.
      const D bound = load<D>(p.slope) * m + load<D>(p.offset);
      certainty = smaller(certainty, smaller(absolute<D, M>(w), absolute<D, M>(e)) - bound);
      outside_margin = smaller(outside_margin, larger(w, e) + bound);
      // crossing_from_values, operation for operation, before its clamp to [0, 1] (applied to
      // the results; the bound holds for the raw value).
      const D difference = w - e;
      const D t = w * (one / difference);
      // Where the signs are certain they are exact: w < 0 < e enters (Dn > 0, a lower bound),
      // w > 0 > e leaves (Dn < 0, an upper bound). Other lanes are decided by the exact path.
      const M enter = smaller(-w, e) > zero, exit = smaller(w, -e) > zero;
      const D gap = absolute<D, M>(difference);
      closest = smaller(closest, pick(enter, gap, infinity));
      closest = smaller(closest, pick(exit, gap, infinity));
      const D index = load<D>(p.index);

      const D lo_candidate = pick(enter, t, minus_infinity);
      lo_second = larger(lo_second, smaller(lo_candidate, lo_t));
      lo_plane = pick(lo_candidate > lo_t, index, lo_plane);
      lo_t = larger(lo_candidate, lo_t);

      const D up_candidate = pick(exit, t, infinity);
      up_second = smaller(up_second, larger(up_candidate, up_t));
      up_plane = pick(up_candidate < up_t, index, up_plane);
      up_t = smaller(up_candidate, up_t);
    }
    const M sure = valid & (certainty > zero);
    const M outside = outside_margin < zero;

    // One error bound for every crossing of the segment: |t − t_exact| ≤ (δw + δe)/|w − e| + 3u
    // (crossing()) with δw, δe ≤ the largest plane bound B (rounding is monotone, so B computed
    // from the largest slope and offset is no smaller) and |w − e| ≥ closest/(1 + u); the
    // inflation covers the roundings of this expression.
    const D largest_bound = max_slope * m + max_offset;
    const D error =
        (largest_bound * splat<D>(2 * kCrossingInflation)) / closest + splat<D>(kCrossingAbsolute);

    // Decide: surely outside one plane, or certain signs with t_low > t_up whichever planes are
    // extreme: invisible. Certain signs, extreme planes strictly ahead of the second ones, and
    // t_low < t_up: visible. Anything else: the exact path.
    const M has_lo = lo_plane >= zero, has_up = up_plane >= zero;
    const M invisible =
        (outside & valid) | (sure & has_lo & has_up & (lo_t - error > up_t + error));
    const M separated = ~(has_lo & (lo_second + error >= lo_t - error)) &
                        ~(has_up & (up_second - error <= up_t + error));
    const M visible =
        sure & ~outside & separated & ~(has_lo & has_up & ~(lo_t + error < up_t - error));
    const M point = (x1 == x2) & (y1 == y2) & (z1 == z2);
    // The clamp of crossing_from_values.
    lo_t = pick(lo_t > one, one, lo_t);
    lo_t = pick(lo_t < zero, zero, lo_t);
    up_t = pick(up_t > one, one, up_t);
    up_t = pick(up_t < zero, zero, up_t);
    const D t_start = pick(visible & has_lo, lo_t, zero);
    const D t_end = pick(visible, pick(has_up, up_t, one), zero);
    const I start_plane = __builtin_convertvector(pick(visible, lo_plane, minus_one), I);
    const I end_plane = __builtin_convertvector(pick(visible, up_plane, minus_one), I);
    const D flag_value = pick(
        visible, pick(point, splat<D>(kClipVisible | kClipPoint), splat<D>(kClipVisible)), zero);
    const U flags = __builtin_convertvector(__builtin_convertvector(flag_value, I), U);
    const M undecided = ~(visible | invisible);
    if (lanes == N) {
      store(out.t_start + begin + g, t_start);
      store(out.t_end + begin + g, t_end);
      std::memcpy(out.start_plane + begin + g, &start_plane, sizeof start_plane);
      std::memcpy(out.end_plane + begin + g, &end_plane, sizeof end_plane);
      std::memcpy(out.flags + begin + g, &flags, sizeof flags);
    } else {
      for (size_t l = 0; l < lanes; ++l) {
        const size_t i = begin + g + l;
        out.t_start[i] = t_start[l];
        out.t_end[i] = t_end[l];
        out.start_plane[i] = start_plane[l];
        out.end_plane[i] = end_plane[l];
        out.flags[i] = flags[l];
      }
    }
    std::int64_t any = 0;
    for (int l = 0; l < N; ++l) any |= undecided[l];
    if (any != 0)
      for (size_t l = 0; l < lanes; ++l)
        if (undecided[l]) doubtful[doubtful_count++] = static_cast<std::uint16_t>(g + l);
  }
  return doubtful_count;
}

// The two instantiations: four lanes with AVX2 where the CPU has it, two lanes with the
// x86-64 baseline (SSE2) otherwise. Both give the same bits.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define HEDRA_BATCH_AVX2 1
__attribute__((target("avx2"))) size_t scan_block_avx2(const PlaneData* planes, size_t plane_count,
                                                       const PlaneData& largest,
                                                       const SegmentArrays& seg, size_t begin,
                                                       size_t count, const Output& out,
                                                       std::uint16_t* doubtful) noexcept {
  return scan_block<4>(planes, plane_count, largest, seg, begin, count, out, doubtful);
}
#endif

size_t scan_block_baseline(const PlaneData* planes, size_t plane_count, const PlaneData& largest,
                           const SegmentArrays& seg, size_t begin, size_t count, const Output& out,
                           std::uint16_t* doubtful) noexcept {
  return scan_block<2>(planes, plane_count, largest, seg, begin, count, out, doubtful);
}

using ScanBlock = size_t (*)(const PlaneData*, size_t, const PlaneData&, const SegmentArrays&,
                             size_t, size_t, const Output&, std::uint16_t*) noexcept;

ScanBlock pick_scan(bool allow_avx2) {
#ifdef HEDRA_BATCH_AVX2
  static const bool has_avx2 = __builtin_cpu_supports("avx2");
  if (allow_avx2 && has_avx2) return scan_block_avx2;
#endif
  (void)allow_avx2;
  return scan_block_baseline;
}

void write_part(BatchClipResult& out, size_t i, const std::optional<ClipPart>& part) {
  out.t_start[i] = part ? part->start.t : 0;
  out.t_end[i] = part ? part->end.t : 0;
  out.start_plane[i] = part ? part->start.plane : -1;
  out.end_plane[i] = part ? part->end.plane : -1;
  out.flags[i] = static_cast<std::uint8_t>(
      kClipExactPath | (part ? kClipVisible | (part->point ? kClipPoint : 0) : 0));
}

void clip_range(ScanBlock scan, const ConvexClipper& clipper, const std::vector<PlaneData>& planes,
                const PlaneData& largest, const SegmentArrays& seg, size_t begin, size_t end,
                BatchClipResult& out) {
  const Output columns{out.t_start.data(), out.t_end.data(), out.start_plane.data(),
                       out.end_plane.data(), out.flags.data()};
  std::uint16_t doubtful[kBlock];
  for (size_t b = begin; b < end; b += kBlock) {
    const size_t n = scan(planes.data(), planes.size(), largest, seg, b, std::min(kBlock, end - b),
                          columns, doubtful);
    for (size_t k = 0; k < n; ++k) {
      const size_t i = b + doubtful[k];
      write_part(out, i, clip_segment(clipper, seg.start(i), seg.end(i)));
    }
  }
}

}  // namespace

void SegmentArrays::resize(size_t n) {
  for (auto* v : {&x1, &y1, &z1, &x2, &y2, &z2}) v->resize(n);
}

void SegmentArrays::reserve(size_t n) {
  for (auto* v : {&x1, &y1, &z1, &x2, &y2, &z2}) v->reserve(n);
}

void SegmentArrays::push_back(const Vec3& p1, const Vec3& p2) {
  x1.push_back(p1.x());
  y1.push_back(p1.y());
  z1.push_back(p1.z());
  x2.push_back(p2.x());
  y2.push_back(p2.y());
  z2.push_back(p2.z());
}

void BatchClipResult::resize(size_t n) {
  t_start.resize(n);
  t_end.resize(n);
  start_plane.resize(n);
  end_plane.resize(n);
  flags.resize(n);
}

ClipPart BatchClipResult::part(size_t i) const {
  ClipPart p;
  p.start = {t_start[i], start_plane[i], 0};
  p.end = {t_end[i], end_plane[i], 0};
  p.point = flags[i] & kClipPoint;
  return p;
}

void clip_batch(const ConvexClipper& clipper, const SegmentArrays& segments, BatchClipResult& out,
                const BatchClipOptions& options) {
  const size_t n = segments.size();
  for (const auto* v : {&segments.y1, &segments.z1, &segments.x2, &segments.y2, &segments.z2})
    if (v->size() != n) throw InvalidInput("segment arrays of different lengths");
  out.resize(n);
  // Each plane's coefficients, bound and index spread over the lanes; and the largest error
  // slope and offset (for the bound shared by all crossings of a segment).
  const auto spread = [](double* lanes, double v) { std::fill(lanes, lanes + 4, v); };
  std::vector<PlaneData> planes(clipper.planes().size());
  PlaneData largest{};
  double max_slope = 0, max_offset = 0;
  for (size_t i = 0; i < planes.size(); ++i) {
    const ExactPlane& f = clipper.planes()[i];
    spread(planes[i].nx, f.normal().x());
    spread(planes[i].ny, f.normal().y());
    spread(planes[i].nz, f.normal().z());
    spread(planes[i].k, f.offset());
    spread(planes[i].slope, f.error_slope());
    spread(planes[i].offset, f.error_offset());
    spread(planes[i].index, static_cast<double>(i));
    max_slope = std::max(max_slope, f.error_slope());
    max_offset = std::max(max_offset, f.error_offset());
  }
  spread(largest.slope, max_slope);
  spread(largest.offset, max_offset);

  const ScanBlock scan = pick_scan(options.allow_avx2);
  const auto run = [&](size_t begin, size_t end) {
    clip_range(scan, clipper, planes, largest, segments, begin, end, out);
  };
  if (options.threads == 1 || n < options.min_parallel) {
    run(0, n);
    return;
  }
  parallel_blocks(n, options.threads, kGrain, run);
}

}  // namespace hedra
