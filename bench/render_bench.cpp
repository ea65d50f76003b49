// Rendering benchmarks (issue 8), in one run, on 2 threads:
//  - time per image at 1024 × 1024, Phong, for each shadow method: none, exact (shadow
//    polygons from hedra/visibility/shadows.h as surface detail; the time includes computing them),
//    shadow maps at 512² … 4096² with biases 0.5 … 4 texels, shadow rays at 1 … 16 probes per
//    pixel; scenes: the N × N city of issue 7 (N = 10, 40) and the demo scene;
//  - accuracy against the exact method, measured once per configuration outside the timed
//    loop: the fraction of visible pixels whose shadow state (shadowed when at least half the
//    probes are blocked) differs from the exact method's at the same pixel centre, and the
//    relative error of the shadowed ground area measured from a top view against the exact
//    area of hedra/visibility/shadows.h (the ground's shadow polygons, footprints included).
// scripts/render_report.py turns the JSON output into the "Rendering" section of
// docs/benchmarks.md and the speed–accuracy chart.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <mutex>
#include <random>

#include "hedra/scene/demo.h"
#include "hedra/core/primitives.h"
#include "hedra/visibility/shadows.h"
#include "hedra/render/raster.h"

namespace {

using namespace hedra;

bool quick() { return std::getenv("HEDRA_BENCH_QUICK") != nullptr; }

// The city of issue 7: a ground slab [0, 100]² with its top at z = 0 and an N × N grid of
// boxes, cell p = 100/N, each box's footprint [0.2p, 0.8p]² inside its cell, heights uniform in
// [p/4, 9p/8] (seeded as in bench/shadows_bench.cpp), the sun travelling along (−1, −2, −3).
Scene city(int n) {
  Scene scene;
  const double p = 100.0 / n;
  Material ground;
  ground.color = Vec3(0.75, 0.75, 0.7);
  ground.ks = 0;
  scene.add("ground", box({0, 0, -1}, {100, 100, 0}), ground);
  // The same generator and seed as bench/shadows_bench.cpp: the same city.
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double h = p / 4 + (9 * p / 8 - p / 4) * u(rng);
      scene.add("b" + std::to_string(i) + "_" + std::to_string(j),
                box({i * p + 0.2 * p, j * p + 0.2 * p, 0}, {i * p + 0.8 * p, j * p + 0.8 * p, h}));
    }
  scene.camera = Camera::perspective({140, -35, 85}, {50, 50, 0}, 50);
  scene.camera.width = scene.camera.height = 1024;
  scene.lights.push_back(Light::directional({-1, -2, -3}, 0.9));
  return scene;
}

enum SceneId { kCity10 = 0, kCity40 = 1, kDemo = 2 };

const Scene& scene_of(int id) {
  static const Scene scenes[3] = {city(10), city(40), [] {
                                    Scene s = demo_scene();
                                    return s;
                                  }()};
  return scenes[id];
}

// The same scene seen from straight above (parallel), for the ground-area error.
Scene top_view(const Scene& scene) {
  Scene s = scene;
  s.camera = Camera::parallel({0, 0, -1}, {0, 1, 0});
  s.camera.width = s.camera.height = 1024;
  return s;
}

// Methods: 0 none, 1 exact, then maps (resolution × bias), then rays (probes).
const std::vector<int> kResolutions = {512, 1024, 2048, 4096};
const std::vector<double> kBiases = {0.5, 1, 2, 4};
const std::vector<int> kProbes = {1, 2, 4, 8, 16};

ShadowSettings method_of(int m) {
  ShadowSettings s;
  if (m == 0) return s;
  if (m == 1) {
    s.method = ShadowSettings::Method::Exact;
    return s;
  }
  const int maps = static_cast<int>(kResolutions.size() * kBiases.size());
  if (m < 2 + maps) {
    s.method = ShadowSettings::Method::Map;
    s.map_resolution = kResolutions[(m - 2) / kBiases.size()];
    s.map_bias = kBiases[(m - 2) % kBiases.size()];
    return s;
  }
  s.method = ShadowSettings::Method::Rays;
  s.ray_samples = kProbes[static_cast<size_t>(m - 2 - maps)];
  return s;
}

int method_count() { return static_cast<int>(2 + kResolutions.size() * kBiases.size() + kProbes.size()); }

bool in_quick_set(int m) {
  const ShadowSettings s = method_of(m);
  if (s.method == ShadowSettings::Method::Map)
    return (s.map_resolution == 512 || s.map_resolution == 2048) && (s.map_bias == 1 || s.map_bias == 4);
  if (s.method == ShadowSettings::Method::Rays) return s.ray_samples == 1 || s.ray_samples == 4;
  return true;
}

RenderOptions options_of(int m) {
  RenderOptions o;
  o.shading = Shading::Phong;
  o.shadows = method_of(m);
  o.threads = 2;
  return o;
}

// Accuracy, computed once per (scene, method) outside the timed loop.
struct Accuracy {
  double pixel_error = 0;  // fraction of visible pixels whose shadow state differs from exact
  double area_error = 0;   // |ground shadow area − exact| / exact, from the top view
  double ground_area = 0;  // the estimate
  double exact_area = 0;
};

double footprints(const Scene& scene) {
  // Areas of the faces resting on z = 0 with outward normal −z (bodies standing on the ground).
  double area = 0;
  for (size_t b = 1; b < scene.bodies().size(); ++b) {
    const Body& body = scene.bodies()[b].body;
    for (int f = 0; f < body.face_count(); ++f) {
      if (body.inner_normal(f).z() < 1 - 1e-12) continue;  // inner normal +z: a bottom face
      bool on_ground = true;
      for (int v : body.faces()[f].loops[0]) on_ground = on_ground && body.vertices()[v].z() == 0;
      if (on_ground) area += body.face_area(f);
    }
  }
  return area;
}

Accuracy accuracy(int scene_id, int m) {
  static std::mutex mutex;
  static std::map<std::pair<int, int>, Accuracy> cache;
  static std::map<int, SampleRecord> exact_view;
  static std::map<int, double> exact_area;
  std::lock_guard<std::mutex> lock(mutex);
  const auto key = std::make_pair(scene_id, m);
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  const Scene& scene = scene_of(scene_id);
  if (!exact_view.count(scene_id)) {
    render(scene, options_of(1), &exact_view[scene_id]);
    ShadowOptions so;
    so.counts = false;
    exact_area[scene_id] = compute_shadows(scene, so).face(0, 0, 5).shadow_area;  // ground top
  }
  Accuracy a;
  SampleRecord rec;
  render(scene, options_of(m), &rec);
  const SampleRecord& ref = exact_view[scene_id];
  long visible = 0, differ = 0;
  for (size_t i = 0; i < rec.body.size(); ++i) {
    if (rec.body[i] < 0) continue;
    ++visible;
    differ += (rec.shadow[i * rec.lights] >= 0.5f) != (ref.shadow[i * ref.lights] >= 0.5f);
  }
  a.pixel_error = visible ? static_cast<double>(differ) / visible : 0;
  // Ground area from the top view: the shadowed fraction of the visible ground pixels times
  // the visible ground's exact area, plus the footprints the boxes cover (shadowed by the boxes
  // themselves). Taking the fraction (rather than counting pixel areas) keeps the sampling
  // error of the visible ground's outline, which a regular city aligned with the pixel grid
  // makes systematic, out of the shadow error.
  const Scene top = top_view(scene);
  SampleRecord t;
  render(top, options_of(m), &t);
  double shadowed = 0, ground = 0;
  for (size_t i = 0; i < t.body.size(); ++i)
    if (t.body[i] == 0 && t.face[i] == 5) {
      shadowed += t.shadow[i * t.lights];
      ground += 1;
    }
  const double feet = footprints(scene);
  a.ground_area = shadowed / ground * (scene.bodies()[0].body.face_area(5) - feet) + feet;
  a.exact_area = exact_area[scene_id];
  a.area_error = std::abs(a.ground_area - a.exact_area) / a.exact_area;
  cache[key] = a;
  return a;
}

void BM_Render(benchmark::State& state) {
  const int scene_id = static_cast<int>(state.range(0)), m = static_cast<int>(state.range(1));
  const Scene& scene = scene_of(scene_id);
  const RenderOptions o = options_of(m);
  RenderStats stats;
  for (auto _ : state) {
    const Image image = render(scene, o, nullptr, &stats);
    benchmark::DoNotOptimize(image.rgb.data());
  }
  state.counters["setup_ms"] = stats.setup_ms;
  state.counters["shadows_ms"] = stats.shadows_ms;
  state.counters["raster_ms"] = stats.raster_ms;
  state.counters["triangles"] = stats.triangles;
  const ShadowSettings s = method_of(m);
  state.counters["method"] = static_cast<int>(s.method);
  state.counters["resolution"] = s.map_resolution;
  state.counters["bias"] = s.map_bias;
  state.counters["probes"] = s.ray_samples;
  if (m != 0) {
    const Accuracy a = accuracy(scene_id, m);
    state.counters["pixel_error"] = a.pixel_error;
    state.counters["area_error"] = a.area_error;
    state.counters["ground_area"] = a.ground_area;
    state.counters["exact_area"] = a.exact_area;
  }
  state.SetLabel(s.to_string());
}

void render_args(benchmark::internal::Benchmark* b) {
  for (int scene_id : {kCity10, kCity40, kDemo})
    for (int m = 0; m < method_count(); ++m)
      if (!quick() || in_quick_set(m)) b->Args({scene_id, m});
}

BENCHMARK(BM_Render)->Apply(render_args)->ArgNames({"scene", "method"})->Unit(benchmark::kMillisecond)->UseRealTime();

// The target configuration on 1 and 2 threads: N = 40, 1024², Phong, exact shadows.
void BM_Target(benchmark::State& state) {
  RenderOptions o = options_of(1);
  o.threads = static_cast<int>(state.range(0));
  RenderStats stats;
  for (auto _ : state) {
    const Image image = render(scene_of(kCity40), o, nullptr, &stats);
    benchmark::DoNotOptimize(image.rgb.data());
  }
  state.counters["setup_ms"] = stats.setup_ms;
  state.counters["shadows_ms"] = stats.shadows_ms;
  state.counters["raster_ms"] = stats.raster_ms;
}

BENCHMARK(BM_Target)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
