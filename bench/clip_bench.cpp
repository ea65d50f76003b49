// Clipping benchmarks (issue 4), in one run:
//  - throughput: batch Cyrus–Beck against a 6-face box and a 20-face icosahedron on 10 M random
//    segments (2 M with HEDRA_BENCH_QUICK), with 1 and 2 threads, next to the plain scalar loop
//    (the course's algorithm, docs/algorithms.md §4, in double, one segment at a time), the exact
//    scalar path, and a memory copy of the same segment data (the bandwidth roofline);
//  - speed against accuracy: exact Cyrus–Beck, plain double, and midpoint subdivision at ε = 1e-2 …
//    1e-12, each against exact rational results (tests/testing/clip_fixtures.h), on random segments
//    and on segments built through vertices, along edges and in face planes.
// scripts/clip_report.py turns the JSON output into the "Clipping" section of docs/benchmarks.md.
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cstdlib>
#include <cstring>
#include <random>

#include "hedra/baselines/cyrus_beck_double.h"
#include "hedra/clip/batch_clip.h"
#include "hedra/clip/cyrus_beck.h"
#include "hedra/baselines/midpoint_clip.h"
#include "hedra/core/primitives.h"
#include "testing/clip_fixtures.h"

namespace {

using namespace hedra;
using testing::Rational;

enum Shape { kBox = 0, kIcosahedron = 1 };

struct Target {
  Body body;
  ConvexClipper clipper;
};

const Target& target(int shape) {
  static const Target box_target{box({-1, -1, -1}, {1, 1, 1}),
                                 ConvexClipper(box({-1, -1, -1}, {1, 1, 1}))};
  static const Body ico = testing::icosahedron(1.2);
  static const Target ico_target{ico, ConvexClipper(ico)};
  return shape == kBox ? box_target : ico_target;
}

size_t segment_count() { return std::getenv("HEDRA_BENCH_QUICK") ? 2'000'000 : 10'000'000; }

// Random segments with both ends uniform in [−2, 2]³: about a third miss the clipper, the rest
// cross it or lie inside.
const SegmentArrays& segments() {
  static const SegmentArrays s = [] {
    SegmentArrays a;
    const size_t n = segment_count();
    a.resize(n);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-2, 2);
    for (size_t i = 0; i < n; ++i) {
      a.x1[i] = u(rng), a.y1[i] = u(rng), a.z1[i] = u(rng);
      a.x2[i] = u(rng), a.y2[i] = u(rng), a.z2[i] = u(rng);
    }
    return a;
  }();
  return s;
}

void set_throughput(benchmark::State& state) {
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * segments().size()));
  state.counters["segments"] = static_cast<double>(segments().size());
}

// The roofline: copying the same six coordinate arrays (48 bytes read, 48 written per segment).
void BM_Memcpy(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const SegmentArrays& s = segments();
  static SegmentArrays copy;
  copy.resize(s.size());
  const std::vector<double>* from[6] = {&s.x1, &s.y1, &s.z1, &s.x2, &s.y2, &s.z2};
  std::vector<double>* to[6] = {&copy.x1, &copy.y1, &copy.z1, &copy.x2, &copy.y2, &copy.z2};
  tbb::task_arena arena(threads);
  for (auto _ : state) {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, s.size(), 1 << 16),
                        [&](const tbb::blocked_range<size_t>& r) {
                          for (int k = 0; k < 6; ++k)
                            std::memcpy(to[k]->data() + r.begin(), from[k]->data() + r.begin(),
                                        (r.end() - r.begin()) * sizeof(double));
                        });
    });
    benchmark::ClobberMemory();
  }
  set_throughput(state);
}

// Batch Cyrus–Beck (exact decisions, results identical to the scalar path).
void BM_Batch(benchmark::State& state) {
  const Target& t = target(static_cast<int>(state.range(0)));
  const SegmentArrays& s = segments();
  BatchClipOptions options;
  options.threads = static_cast<int>(state.range(1));
  options.allow_avx2 = state.range(2) != 0;
  static BatchClipResult result;
  clip_batch(t.clipper, s, result, options);  // first touch of the output outside the timing
  for (auto _ : state) {
    clip_batch(t.clipper, s, result, options);
    benchmark::ClobberMemory();
  }
  set_throughput(state);
  size_t exact = 0, visible = 0;
  for (size_t i = 0; i < result.size(); ++i) {
    exact += (result.flags[i] & kClipExactPath) != 0;
    visible += (result.flags[i] & kClipVisible) != 0;
  }
  state.counters["exact_path_fraction"] = static_cast<double>(exact) / result.size();
  state.counters["visible_fraction"] = static_cast<double>(visible) / result.size();
}

// The plain scalar loop: the course's algorithm in double on the body matrix, one segment at a
// time, writing the same outputs.
void BM_PlainScalar(benchmark::State& state) {
  const Target& t = target(static_cast<int>(state.range(0)));
  const SegmentArrays& s = segments();
  static std::vector<double> t0, t1;
  t0.resize(s.size());
  t1.resize(s.size());
  const BodyMatrix& m = t.body.matrix();
  for (auto _ : state) {
    for (size_t i = 0; i < s.size(); ++i) {
      const auto r = cyrus_beck_double(m, s.start(i), s.end(i));
      t0[i] = r ? r->first : 1;
      t1[i] = r ? r->second : 0;
    }
    benchmark::ClobberMemory();
  }
  set_throughput(state);
}

// The exact scalar path, one segment at a time.
void BM_ExactScalar(benchmark::State& state) {
  const Target& t = target(static_cast<int>(state.range(0)));
  const SegmentArrays& s = segments();
  static std::vector<double> t0, t1;
  t0.resize(s.size());
  t1.resize(s.size());
  for (auto _ : state) {
    for (size_t i = 0; i < s.size(); ++i) {
      const auto r = clip_segment(t.clipper, s.start(i), s.end(i));
      t0[i] = r ? r->start.t : 1;
      t1[i] = r ? r->end.t : 0;
    }
    benchmark::ClobberMemory();
  }
  set_throughput(state);
}

// ---- Speed against accuracy ----

enum Dataset { kRandom = 0, kDegenerate = 1 };
constexpr size_t kAccuracySegments = 20000;

struct AccuracyCase {
  Body body;
  ConvexClipper clipper;
  std::vector<std::pair<Vec3, Vec3>> segments;
  std::vector<testing::ExactClip> exact;
};

const AccuracyCase& accuracy_case(int dataset) {
  static const AccuracyCase random_case = [] {
    const Body b = testing::icosahedron(1.2);
    AccuracyCase c{b, ConvexClipper(b), {}, {}};
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(-2, 2);
    for (size_t i = 0; i < kAccuracySegments; ++i)
      c.segments.push_back({{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}});
    for (const auto& [p, q] : c.segments) c.exact.push_back(testing::exact_clip(c.clipper, p, q));
    return c;
  }();
  // A pyramid with integer coordinates: vertices, midpoints of vertex pairs and points on the
  // lines through them lie exactly on faces, edges and vertices. Its body matrix has unit
  // normals, rounded, which is what the plain double variant works with.
  static const AccuracyCase degenerate_case = [] {
    const Body b = pyramid({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 0, {2, 2, 4});
    AccuracyCase c{b, ConvexClipper(b), {}, {}};
    std::mt19937_64 rng(3);
    const auto& v = b.vertices();
    std::uniform_int_distribution<size_t> pick(0, v.size() - 1);
    std::uniform_int_distribution<int> kind(0, 3);
    const auto special = [&]() -> Vec3 {
      const Vec3 a = v[pick(rng)], d = v[pick(rng)];
      switch (kind(rng)) {
        case 0:
          return a;
        case 1:
          return 0.5 * (a + d);
        case 2:
          return a + (a - d);
        default:
          return 0.25 * (3 * a + d);
      }
    };
    while (c.segments.size() < kAccuracySegments) {
      const Vec3 p = special(), q = special();
      if (p != q) c.segments.push_back({p, q});
    }
    for (const auto& [p, q] : c.segments) c.exact.push_back(testing::exact_clip(c.clipper, p, q));
    return c;
  }();
  return dataset == kRandom ? random_case : degenerate_case;
}

double distance_to_exact(const Vec3& computed, const Vec3& p1, const Vec3& p2, const Rational& t) {
  double sum = 0;
  for (int i = 0; i < 3; ++i) {
    const Rational exact = Rational(p1[i]) + (Rational(p2[i]) - p1[i]) * t;
    const double d = testing::to_double(Rational(computed[i]) - exact);
    sum += d * d;
  }
  return std::sqrt(sum);
}

// Compares the results with the exact ones: largest end-point error where both see a part,
// decisions that differ (a part seen by one only), and the longest part missed or invented.
struct Accuracy {
  double max_error = 0;
  size_t wrong = 0;
  double worst_wrong_length = 0;

  void add(const AccuracyCase& c, size_t i, const std::optional<std::pair<Vec3, Vec3>>& part) {
    const auto& [p1, p2] = c.segments[i];
    const testing::ExactClip& e = c.exact[i];
    if (part.has_value() != e.visible) {
      ++wrong;
      const double length = part ? (part->second - part->first).norm()
                                 : (p2 - p1).norm() * testing::to_double(e.t_up - e.t_low);
      worst_wrong_length = std::max(worst_wrong_length, length);
      return;
    }
    if (!part) return;
    max_error = std::max({max_error, distance_to_exact(part->first, p1, p2, e.t_low),
                          distance_to_exact(part->second, p1, p2, e.t_up)});
  }
  void report(benchmark::State& state) const {
    state.counters["max_error"] = max_error;
    state.counters["wrong_decisions"] = static_cast<double>(wrong);
    state.counters["worst_wrong_length"] = worst_wrong_length;
  }
};

// range(0): dataset; range(1): variant (0 exact, 1 plain double, 2 midpoint); range(2): −log10 ε.
void BM_Accuracy(benchmark::State& state) {
  const AccuracyCase& c = accuracy_case(static_cast<int>(state.range(0)));
  const int variant = static_cast<int>(state.range(1));
  const double eps = std::pow(10.0, -static_cast<double>(state.range(2)));
  std::vector<std::optional<std::pair<Vec3, Vec3>>> parts(c.segments.size());
  const auto run = [&](size_t i) -> std::optional<std::pair<Vec3, Vec3>> {
    const auto& [p1, p2] = c.segments[i];
    if (variant == 0) {
      const auto r = clip_segment(c.clipper, p1, p2);
      if (!r) return std::nullopt;
      return std::make_pair(point_at(p1, p2, r->start.t), point_at(p1, p2, r->end.t));
    }
    if (variant == 1) {
      const auto r = cyrus_beck_double(c.body.matrix(), p1, p2);
      if (!r) return std::nullopt;
      return std::make_pair(point_at(p1, p2, r->first), point_at(p1, p2, r->second));
    }
    const auto r = midpoint_clip(c.clipper, p1, p2, eps);
    if (!r) return std::nullopt;
    return std::make_pair(r->start, r->end);
  };
  for (auto _ : state) {
    for (size_t i = 0; i < c.segments.size(); ++i) parts[i] = run(i);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * c.segments.size()));
  Accuracy a;
  for (size_t i = 0; i < c.segments.size(); ++i) a.add(c, i, parts[i]);
  a.report(state);
  state.counters["eps"] = variant == 2 ? eps : 0;
}

void throughput_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"shape", "threads", "avx2"});
  for (int shape : {kBox, kIcosahedron}) {
    for (int threads : {1, 2}) b->Args({shape, threads, 1});
    b->Args({shape, 1, 0});  // the x86-64 baseline (SSE2) code, for comparison
  }
}

void accuracy_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"dataset", "variant", "neg_log10_eps"});
  for (int dataset : {kRandom, kDegenerate}) {
    b->Args({dataset, 0, 0});
    b->Args({dataset, 1, 0});
    for (int e = 2; e <= 12; e += 2) b->Args({dataset, 2, e});
  }
}

BENCHMARK(BM_Memcpy)->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(
    benchmark::kMillisecond);
BENCHMARK(BM_Batch)->Apply(throughput_args)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlainScalar)
    ->ArgName("shape")
    ->Arg(kBox)
    ->Arg(kIcosahedron)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ExactScalar)
    ->ArgName("shape")
    ->Arg(kBox)
    ->Arg(kIcosahedron)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Accuracy)->Apply(accuracy_args)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
