// Hidden-line benchmarks (issue 6), side by side in one run:
//  - hedra's Roberts (exact, object space, grid over the picture) on a jittered N×N grid of
//    boxes (pitch 15, sizes 8–12, heights 10/20/30 plus up to 2, seed 1), N = 5…40, parallel
//    (direction (−1, −1, −1)) and perspective (eye on the diagonal above the grid's centre), a
//    regular grid (boxes 10 × 10 × 20 at pitch 15: edges align in the picture), two boxes
//    interpenetrating at a corner, and a bar piercing a cube; its visible length is checked
//    against the ray-cast reference of the tests (tests/testing/hlr_reference.h);
//  - an image-space method: a z-buffer of the faces at 512², 1024², 2048², edges sampled
//    every half pixel and tested against it (3 × 3 neighbourhood, small depth bias); missed and
//    extra visible length against hedra's exact result;
//  - OCCT's HLRBRep_PolyAlgo (on BRepMesh triangulations; meshing timed apart) and the exact
//    HLRBRep_Algo on the same boxes, parallel view, when OpenCASCADE was found (HEDRA_HAVE_OCCT).
// HEDRA_BENCH_QUICK=1 drops N = 30 for the slow peers and the 2048² z-buffer on large grids.
// scripts/hlr_report.py turns the JSON output into the "Hidden lines" section of
// docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <random>
#include <string>

#include "hedra/core/primitives.h"
#include "hedra/visibility/roberts.h"
#include "hedra/render/svg.h"
#include "testing/hlr_reference.h"
#include "testing/zbuffer_lines.h"

#if HEDRA_HAVE_OCCT
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Builder.hxx>
#include <TopoDS_Compound.hxx>

#include "occt_hlr.h"
#endif

namespace {

using namespace hedra;

bool quick() { return std::getenv("HEDRA_BENCH_QUICK") != nullptr; }

struct BoxSpec {
  Vec3 min, max;
};

struct BenchScene {
  std::string name;
  std::vector<BoxSpec> boxes;  // empty for scenes that are not boxes only
  std::vector<Body> bodies;
  Camera camera;
};

// Scene ids: 0 jittered grid, 1 regular grid, 2 corner, 3 bar.
BenchScene make_scene(int kind, int n, bool perspective) {
  BenchScene s;
  if (kind == 0 || kind == 1) {
    std::mt19937 random(1);
    std::uniform_real_distribution<double> size(8, 12), jitter(0, 2);
    const double heights[3] = {10, 20, 30};
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < n; ++k) {
        const Vec3 lo(15.0 * i, 15.0 * k, 0);
        Vec3 hi = lo + Vec3(10, 10, 20);
        if (kind == 0) hi = lo + Vec3(size(random), size(random), heights[random() % 3] + jitter(random));
        s.boxes.push_back({lo, hi});
        s.bodies.push_back(box(lo, hi));
      }
    s.name = (kind == 0 ? "jittered" : "regular");
    const Vec3 centre(7.5 * n, 7.5 * n, 10);
    s.camera = perspective ? Camera::perspective(centre + Vec3(1, 1, 1) * (15.0 * n), centre, 60)
                           : Camera::parallel({-1, -1, -1});
  } else if (kind == 2) {
    s.name = "corner";
    s.boxes = {{{0, 0, 0}, {2, 2, 2}}, {{1, 1, 1}, {3, 3, 3}}};
    for (const BoxSpec& b : s.boxes) s.bodies.push_back(box(b.min, b.max));
    s.camera = perspective ? Camera::perspective({8, -6, 7}, {1.5, 1.5, 1.5}, 40) : Camera::parallel({-1, 3, -2});
  } else {
    s.name = "bar";
    s.boxes = {{{0, 0, 0}, {4, 4, 4}}, {{-1, 1, 1}, {5, 3, 3}}};
    for (const BoxSpec& b : s.boxes) s.bodies.push_back(box(b.min, b.max));
    s.camera = perspective ? Camera::perspective({-10, -5, 9}, {2, 2, 2}, 50) : Camera::parallel({1, 0.5, -0.7});
  }
  s.camera.width = s.camera.height = 1024;
  return s;
}

const BenchScene& scene(int kind, int n, bool perspective) {
  static std::map<std::tuple<int, int, bool>, BenchScene> cache;
  auto key = std::make_tuple(kind, n, perspective);
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, make_scene(kind, n, perspective)).first;
  return it->second;
}

double length_2d(const HlrResult& r) {
  double sum = 0;
  for (const HlrSegment& s : r.visible) sum += (s.b2 - s.a2).norm();
  return sum;
}

// The exact result per edge (no merging), for the accuracy of the other methods.
const HlrResult& exact(int kind, int n, bool perspective) {
  static std::map<std::tuple<int, int, bool>, HlrResult> cache;
  auto key = std::make_tuple(kind, n, perspective);
  auto it = cache.find(key);
  if (it == cache.end()) {
    HlrOptions o;
    o.merge_coincident = false;
    o.junctions = false;
    it = cache.emplace(key, hidden_lines(scene(kind, n, perspective).bodies, scene(kind, n, perspective).camera, o)).first;
  }
  return it->second;
}

// ---- hedra ----

void BM_Hedra(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0)), n = static_cast<int>(state.range(1));
  const bool perspective = state.range(2) != 0;
  const BenchScene& s = scene(kind, n, perspective);
  HlrResult r;
  for (auto _ : state) {
    r = hidden_lines(s.bodies, s.camera);
    benchmark::DoNotOptimize(r.visible.data());
  }
  state.counters["bodies"] = static_cast<double>(s.bodies.size());
  state.counters["edges"] = r.stats.edges;
  state.counters["occlusion_tests"] = static_cast<double>(r.stats.occlusion_tests);
  state.counters["junction_segments"] = r.stats.junction_segments;
  state.counters["junction_length"] = r.length(LineKind::Junction);
  state.counters["visible_length"] = r.length(LineKind::Edge);
  state.counters["visible_length_2d"] = length_2d(r);
  // Against the ray-cast reference, per edge (no merging, as the reference counts edges).
  static std::map<std::tuple<int, int, bool>, double> checked;
  auto key = std::make_tuple(kind, n, perspective);
  if (!checked.count(key)) {
    // Uniform samples plus the middles of hedra's parts and gaps, each classified by the
    // reference on its own (tests/testing/hlr_reference.h), transitions bisected.
    const testing::RayCastReference reference(s.bodies, s.camera);
    const HlrResult& per_edge = exact(kind, n, perspective);
    double expected = 0;
    for (size_t bi = 0; bi < s.bodies.size(); ++bi)
      for (int ei = 0; ei < s.bodies[bi].edge_count(); ++ei) {
        const Body& body = s.bodies[bi];
        const Edge& e = body.edges()[static_cast<size_t>(ei)];
        expected += reference.visible_length(body.vertices()[static_cast<size_t>(e.v0)],
                                             body.vertices()[static_cast<size_t>(e.v1)], quick() ? 64 : 256,
                                             testing::part_hints(per_edge, body, static_cast<int>(bi), ei));
      }
    checked[key] = std::abs(exact(kind, n, perspective).length(LineKind::Edge) - expected) / expected;
  }
  state.counters["reference_rel_error"] = checked[key];
}

// ---- Image space: z-buffer and sampled edges ----

void BM_ZBuffer(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0)), n = static_cast<int>(state.range(1));
  const bool perspective = state.range(2) != 0;
  const int res = static_cast<int>(state.range(3));
  const BenchScene& s = scene(kind, n, perspective);
  const HlrResult& ex = exact(kind, n, perspective);
  const auto visible_t = testing::visible_intervals(s.bodies, ex);
  testing::ZBufferLineError err;
  for (auto _ : state) err = testing::zbuffer_lines(s.bodies, s.camera, ex, visible_t, res);
  const double visible = err.visible, missed = err.missed, extra = err.extra;
  const double exact_length = ex.length(LineKind::Edge);
  state.counters["resolution"] = res;
  state.counters["visible_length"] = visible;
  state.counters["missed_length"] = missed;
  state.counters["extra_length"] = extra;
  state.counters["missed_fraction"] = missed / exact_length;
  state.counters["extra_fraction"] = extra / exact_length;
}

#if HEDRA_HAVE_OCCT
// ---- OCCT ----

TopoDS_Compound occt_scene(const BenchScene& s) {
  TopoDS_Builder builder;
  TopoDS_Compound c;
  builder.MakeCompound(c);
  for (const BoxSpec& b : s.boxes) builder.Add(c, bench::occt_box(b.min, b.max));
  return c;
}

void BM_OcctPoly(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0)), n = static_cast<int>(state.range(1));
  const BenchScene& s = scene(kind, n, false);
  double length = 0, mesh_ms = 0;
  // Built and destroyed outside the timed part: scene, meshing, and the previous iteration's
  // results.
  TopoDS_Compound c;
  bench::OcctLines lines;
  for (auto _ : state) {
    state.PauseTiming();
    lines.clear();
    c = occt_scene(s);
    const auto t0 = std::chrono::steady_clock::now();
    BRepMesh_IncrementalMesh mesh(c, 0.1);
    mesh_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    state.ResumeTiming();
    bench::occt_poly_lines(c, s.camera, lines);
    state.PauseTiming();
    length = lines.length();
    state.ResumeTiming();
  }
  const double hedra = length_2d(hidden_lines(s.bodies, s.camera));
  state.counters["mesh_ms"] = mesh_ms;
  state.counters["visible_length_2d"] = length;
  state.counters["rel_diff_vs_hedra"] = (length - hedra) / hedra;
}

void BM_OcctAlgo(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0)), n = static_cast<int>(state.range(1));
  const BenchScene& s = scene(kind, n, false);
  double length = 0;
  TopoDS_Compound c;
  bench::OcctLines lines;
  for (auto _ : state) {
    state.PauseTiming();
    lines.clear();
    c = occt_scene(s);
    state.ResumeTiming();
    bench::occt_exact_lines(c, s.camera, lines);
    state.PauseTiming();
    length = lines.length();
    state.ResumeTiming();
  }
  const double hedra = length_2d(hidden_lines(s.bodies, s.camera));
  state.counters["visible_length_2d"] = length;
  state.counters["rel_diff_vs_hedra"] = (length - hedra) / hedra;
}
#endif

std::vector<int> sizes() { return {5, 10, 20, 30, 40}; }

void hedra_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"scene", "n", "perspective"});
  for (int persp : {0, 1})
    for (int n : sizes()) b->Args({0, n, persp});
  b->Args({1, 20, 0});
  for (int persp : {0, 1}) {
    b->Args({2, 1, persp});
    b->Args({3, 1, persp});
  }
}

void zbuffer_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"scene", "n", "perspective", "res"});
  for (int res : {512, 1024, 2048})
    for (int persp : {0, 1})
      for (int n : sizes()) {
        if (quick() && (n == 30 || (res == 2048 && n > 10))) continue;
        b->Args({0, n, persp, res});
      }
  for (int res : {512, 1024, 2048}) b->Args({1, 20, 0, res});
}

#if HEDRA_HAVE_OCCT
void occt_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"scene", "n"});
  for (int n : sizes())
    if (!(quick() && n == 30)) b->Args({0, n});
  b->Args({1, 20});
}
void occt_exact_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"scene", "n"});
  for (int n : sizes())
    if (!(quick() && n >= 30)) b->Args({0, n});
}
#endif

}  // namespace

BENCHMARK(BM_Hedra)->Apply(hedra_args)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ZBuffer)->Apply(zbuffer_args)->UseRealTime()->Unit(benchmark::kMillisecond);
#if HEDRA_HAVE_OCCT
BENCHMARK(BM_OcctPoly)->Apply(occt_args)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OcctAlgo)->Apply(occt_exact_args)->UseRealTime()->Unit(benchmark::kMillisecond);
#endif

BENCHMARK_MAIN();
