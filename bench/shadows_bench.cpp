// Shadow benchmarks (issue 7), side by side in one run, on the city of docs/design.md ("Targets"):
// a ground slab [0, 100]² (top at z = 0) and an N × N grid of boxes (cell p = 100/N, footprint 0.2p
// … 0.8p, heights p/4 … 9p/8 from a fixed seed), the sun travelling along (−1, −2, −3); N = 10 and
// 40.
//  - hedra: exact shadow polygons on every face (ground, facades, roofs), 2 threads and 1;
//  - CGAL: the exact 2D union (Epeck Polygon_set_2) of the ground shadows, each box's being the
//    hull of its base and its top projected along the light, clipped to the ground: the exact
//    reference of the ground's shadowed fraction;
//  - rays: the ground's shadowed fraction sampled by rays towards the sun from one jittered
//    point in each cell of an R × R grid (R = 256 … 4096), an own ray caster over a uniform grid of
//    the boxes, 2 threads.
// scripts/shadows_report.py turns the JSON output into the "Shadows" section of
// docs/benchmarks.md.
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <random>

#include "hedra/visibility/polygon_union.h"
#include "hedra/core/primitives.h"
#include "hedra/visibility/shadows.h"

namespace {

using namespace hedra;

const Vec3 kSun(-1, -2, -3);

struct City {
  int n = 0;
  double p = 0;
  Scene scene;
  std::vector<Eigen::AlignedBox3d> boxes;
  double exact_fraction = 0;  // from CGAL's exact union, computed once
};

City make_city(int n) {
  City c;
  c.n = n;
  c.p = 100.0 / n;
  c.scene.add("ground", box({0, 0, -1}, {100, 100, 0}));
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double h = c.p / 4 + (9 * c.p / 8 - c.p / 4) * u(rng);
      const Vec3 lo(i * c.p + 0.2 * c.p, j * c.p + 0.2 * c.p, 0);
      const Vec3 hi(i * c.p + 0.8 * c.p, j * c.p + 0.8 * c.p, h);
      c.scene.add("b" + std::to_string(i) + "_" + std::to_string(j), box(lo, hi));
      c.boxes.emplace_back(lo, hi);
    }
  c.scene.lights.push_back(Light::directional(kSun));
  return c;
}

// The 2D hull of a box's base and its top projected along the sun onto z = 0.
Ring2 ground_hexagon(const Eigen::AlignedBox3d& b) {
  std::vector<Vec2> pts;
  const double t = b.max().z() / -kSun.z();
  for (double x : {b.min().x(), b.max().x()})
    for (double y : {b.min().y(), b.max().y()}) {
      pts.emplace_back(x, y);
      pts.emplace_back(x + t * kSun.x(), y + t * kSun.y());
    }
  std::sort(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& c) {
    return a.x() < c.x() || (a.x() == c.x() && a.y() < c.y());
  });
  Ring2 h(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && orient2d(h[k - 2], h[k - 1], pts[i]) != Sign::Positive) --k;
    h[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, s = k + 1; i-- > 0;) {
    while (k >= s && orient2d(h[k - 2], h[k - 1], pts[i]) != Sign::Positive) --k;
    h[k++] = pts[i];
  }
  h.resize(k - 1);
  return h;
}

double cgal_ground_fraction(const City& c) {
  std::vector<Ring2> hexagons;
  for (const auto& b : c.boxes) hexagons.push_back(ground_hexagon(b));
  const double big = 1e4;
  const std::vector<Ring2> outside = {{{-big, -big}, {big, -big}, {big, 0}, {-big, 0}},
                                      {{-big, 100}, {big, 100}, {big, big}, {-big, big}},
                                      {{-big, 0}, {0, 0}, {0, 100}, {-big, 100}},
                                      {{100, 0}, {big, 0}, {big, 100}, {100, 100}}};
  return cgal_difference(hexagons, outside).area / 1e4;
}

City& city(int n) {
  static std::map<int, City> cities;
  auto it = cities.find(n);
  if (it == cities.end()) {
    it = cities.emplace(n, make_city(n)).first;
    it->second.exact_fraction = cgal_ground_fraction(it->second);
  }
  return it->second;
}

// Ground faces: face 5 (z = max) of body 0.
void BM_HedraExact(benchmark::State& state) {
  City& c = city(static_cast<int>(state.range(0)));
  ShadowOptions options;
  options.threads = static_cast<int>(state.range(1));
  options.counts = false;
  double fraction = 0, facades = 0, roofs = 0;
  for (auto _ : state) {
    const ShadowResult r = compute_shadows(c.scene, options);
    fraction = r.face(0, 0, 5).shadow_area / r.face(0, 0, 5).area;
    benchmark::DoNotOptimize(fraction);
    state.PauseTiming();
    facades = roofs = 0;
    for (const FaceShadow& f : r.lights[0].faces) {
      if (f.body == 0) continue;
      (f.face == 5 ? roofs : facades) += f.to_light == Facing::Front ? f.shadow_area : 0;
    }
    state.ResumeTiming();
  }
  state.counters["n"] = c.n;
  state.counters["boxes"] = c.n * c.n;
  state.counters["ground_fraction"] = fraction;
  state.counters["cgal_fraction"] = c.exact_fraction;
  state.counters["fraction_error"] = std::abs(fraction - c.exact_fraction);
  state.counters["relative_error"] = std::abs(fraction - c.exact_fraction) / c.exact_fraction;
  state.counters["lit_facade_shadow_area"] = facades;
  state.counters["roof_shadow_area"] = roofs;
  state.counters["threads"] = static_cast<double>(state.range(1));
}

void BM_CgalUnion(benchmark::State& state) {
  City& c = city(static_cast<int>(state.range(0)));
  double fraction = 0;
  for (auto _ : state) {
    fraction = cgal_ground_fraction(c);
    benchmark::DoNotOptimize(fraction);
  }
  state.counters["n"] = c.n;
  state.counters["ground_fraction"] = fraction;
  state.counters["fraction_error"] = std::abs(fraction - c.exact_fraction);
}

// A ray caster for the city: a uniform grid of the boxes' footprints, walked along the ray's
// projection until the ray rises above the tallest box.
class RayCaster {
 public:
  explicit RayCaster(const City& c) : c_(c) {
    for (const auto& b : c.boxes) top_ = std::max(top_, b.max().z());
    cells_.resize(static_cast<size_t>(c.n * c.n));
    for (size_t k = 0; k < c.boxes.size(); ++k) {
      const auto& b = c.boxes[k];
      for (int i = cell(b.min().x()); i <= cell(b.max().x()); ++i)
        for (int j = cell(b.min().y()); j <= cell(b.max().y()); ++j)
          cells_[static_cast<size_t>(i * c.n + j)].push_back(static_cast<int>(k));
    }
    dir_ = -kSun.normalized();
  }

  bool shadowed(double x, double y) const {
    // Walk the cells the ray's projection crosses (DDA) while it is below the tallest box.
    const Vec3 o(x, y, 0);
    const double rise = dir_.z();
    double t_end = top_ / rise;
    int i = cell(x), j = cell(y);
    const int si = dir_.x() > 0 ? 1 : -1, sj = dir_.y() > 0 ? 1 : -1;
    const double p = c_.p;
    double tx = dir_.x() != 0 ? ((i + (si > 0)) * p - x) / dir_.x() : 1e300;
    double ty = dir_.y() != 0 ? ((j + (sj > 0)) * p - y) / dir_.y() : 1e300;
    const double dtx = dir_.x() != 0 ? p / std::abs(dir_.x()) : 1e300;
    const double dty = dir_.y() != 0 ? p / std::abs(dir_.y()) : 1e300;
    for (;;) {
      if (i < 0 || j < 0 || i >= c_.n || j >= c_.n) return false;
      for (int k : cells_[static_cast<size_t>(i * c_.n + j)])
        if (hits(c_.boxes[static_cast<size_t>(k)], o)) return true;
      const double t = std::min(tx, ty);
      if (t > t_end) return false;
      if (tx < ty) {
        i += si;
        tx += dtx;
      } else {
        j += sj;
        ty += dty;
      }
    }
  }

 private:
  int cell(double v) const { return std::clamp(static_cast<int>(v / c_.p), 0, c_.n - 1); }
  bool hits(const Eigen::AlignedBox3d& b, const Vec3& o) const {
    double t0 = 0, t1 = 1e300;
    for (int a = 0; a < 3; ++a) {
      if (dir_[a] == 0) {
        if (o[a] <= b.min()[a] || o[a] >= b.max()[a]) return false;
        continue;
      }
      double u = (b.min()[a] - o[a]) / dir_[a], v = (b.max()[a] - o[a]) / dir_[a];
      if (u > v) std::swap(u, v);
      t0 = std::max(t0, u);
      t1 = std::min(t1, v);
    }
    return t0 < t1;
  }
  const City& c_;
  double top_ = 0;
  Vec3 dir_;
  std::vector<std::vector<int>> cells_;
};

// One sample per cell at a fixed pseudo-random place in it (stratified, jittered): regular
// cell centres alias with the city's grid and their error stops falling.
Vec2 jitter(int row, int col) {
  uint64_t h =
      (static_cast<uint64_t>(row) << 32) ^ static_cast<uint64_t>(col) ^ 0x9E3779B97F4A7C15ull;
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  return {static_cast<double>(h & 0xffffffff) / 4294967296.0,
          static_cast<double>(h >> 32) / 4294967296.0};
}

void BM_RaySampling(benchmark::State& state) {
  City& c = city(static_cast<int>(state.range(0)));
  const int res = static_cast<int>(state.range(1));
  const RayCaster caster(c);
  tbb::task_arena arena(2);
  double fraction = 0;
  for (auto _ : state) {
    long long hits = 0;
    arena.execute([&] {
      hits = tbb::parallel_reduce(
          tbb::blocked_range<int>(0, res), 0LL,
          [&](const tbb::blocked_range<int>& r, long long acc) {
            for (int row = r.begin(); row != r.end(); ++row)
              for (int col = 0; col < res; ++col) {
                const Vec2 j = jitter(row, col);
                acc += caster.shadowed((col + j.x()) * 100.0 / res, (row + j.y()) * 100.0 / res);
              }
            return acc;
          },
          [](long long a, long long b) { return a + b; });
    });
    fraction = static_cast<double>(hits) / (static_cast<double>(res) * res);
    benchmark::DoNotOptimize(fraction);
  }
  state.counters["n"] = c.n;
  state.counters["resolution"] = res;
  state.counters["ground_fraction"] = fraction;
  state.counters["fraction_error"] = std::abs(fraction - c.exact_fraction);
}

bool quick() { return std::getenv("HEDRA_BENCH_QUICK") != nullptr; }

void register_all() {
  for (int n : {10, 40}) {
    for (int threads : {2, 1})
      benchmark::RegisterBenchmark("BM_HedraExact", BM_HedraExact)
          ->Args({n, threads})
          ->ArgNames({"n", "threads"})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    benchmark::RegisterBenchmark("BM_CgalUnion", BM_CgalUnion)
        ->Args({n})
        ->ArgNames({"n"})
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    for (int res : {256, 512, 1024, 2048, 4096}) {
      if (quick() && res > 2048) continue;
      benchmark::RegisterBenchmark("BM_RaySampling", BM_RaySampling)
          ->Args({n, res})
          ->ArgNames({"n", "resolution"})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
