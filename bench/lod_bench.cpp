// Level-of-detail benchmarks (docs/design.md, "Model no more than a scene needs"), in one run:
//  - chordal tolerance against the measured geometric error and the cost: sphere, cylinder and
//    cone of radius 1 (height 2) at tolerances 1e-1 … 1e-5 of the radius (quick: … 1e-3). For each: the faces the
//    tessellation got, the largest distance from the polyhedron's surface to the true surface
//    (measured independently by sampling every triangle on a barycentric grid, not taken from the
//    formula the tessellation used), the time to build and validate the body, and the time of
//    Roberts hidden lines on it (what modeling finer costs downstream);
//  - pixel tolerance: a unit sphere at distances 5 … 500 from a perspective camera (fov 40°,
//    1024 × 768) at 0.5 px: faces and the resulting chordal error in pixels.
// scripts/lod_report.py turns the JSON output into the "Level of detail" section of
// docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "hedra/scene/lod.h"
#include "hedra/core/primitives.h"
#include "hedra/visibility/roberts.h"

namespace {

using namespace hedra;

constexpr double kHeight = 2;
const char* kShapes[] = {"sphere", "cylinder", "cone"};
// Down to 1e-5 (about 250 000 faces on the sphere; quick: down to 1e-3). Hidden lines on one
// convex body are near-linear in its faces (issue 15).
const double kTolerances[] = {1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5};
constexpr int kQuickDropped = 4;
constexpr int kMaxFaces = 2000000;

Body make(int shape, double tol) {
  switch (shape) {
    case 0: return sphere(Vec3::Zero(), 1, tol, kMaxFaces);
    case 1: return cylinder(1, 0, kHeight, tol, kMaxFaces);
    default: return cone(1, 0, kHeight, tol, kMaxFaces);
  }
}

// Distance of p from the true surface of the shape (radius 1).
double surface_distance(int shape, const Vec3& p) {
  const double rho = std::hypot(p.x(), p.y());
  if (shape == 0) return std::abs(p.norm() - 1);
  if (shape == 1) {
    // Lateral surface, and the two caps (a point of a cap polygon lies on the cap disc).
    const double lateral = std::abs(rho - 1) + std::max(0.0, -p.z()) + std::max(0.0, p.z() - kHeight);
    const double cap = std::min(std::abs(p.z()), std::abs(p.z() - kHeight)) + std::max(0.0, rho - 1);
    return std::min(lateral, cap);
  }
  // Cone: the segment from (ρ, z) = (1, 0) to (0, kHeight) in the meridian half-plane, or the base.
  const Vec2 a(1, 0), b(0, kHeight), q(rho, p.z());
  const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  const double lateral = (a + t * (b - a) - q).norm();
  const double base = std::abs(p.z()) + std::max(0.0, rho - 1);
  return std::min(lateral, base);
}

// Largest distance from the polyhedron's surface to the true surface: every triangle sampled
// on a barycentric grid of k × k steps (vertices, edge midpoints and interiors).
double measured_error(int shape, const Body& body) {
  constexpr int k = 16;
  double worst = 0;
  for (const Triangle& t : body.triangles()) {
    const Vec3& a = body.vertices()[static_cast<size_t>(t.v[0])];
    const Vec3& b = body.vertices()[static_cast<size_t>(t.v[1])];
    const Vec3& c = body.vertices()[static_cast<size_t>(t.v[2])];
    for (int i = 0; i <= k; ++i)
      for (int j = 0; i + j <= k; ++j) {
        const double u = double(i) / k, v = double(j) / k;
        worst = std::max(worst, surface_distance(shape, a + u * (b - a) + v * (c - a)));
      }
  }
  return worst;
}

void BM_Build(benchmark::State& state) {
  const int shape = static_cast<int>(state.range(0));
  const double tol = kTolerances[state.range(1)];
  int faces = 0;
  for (auto _ : state) {
    Body b = make(shape, tol);
    faces = b.face_count();
    benchmark::DoNotOptimize(b.matrix());
  }
  const Body body = make(shape, tol);
  state.counters["tolerance"] = tol;
  state.counters["faces"] = faces;
  state.counters["error"] = measured_error(shape, body);
  state.SetLabel(kShapes[shape]);
}

void BM_HiddenLines(benchmark::State& state) {
  const int shape = static_cast<int>(state.range(0));
  const double tol = kTolerances[state.range(1)];
  const Body body = make(shape, tol);
  const Camera camera = Camera::parallel({-1, -1, -1});
  double length = 0;
  for (auto _ : state) {
    HlrResult r = hidden_lines(std::span<const Body>(&body, 1), camera);
    length = r.length(LineKind::Edge);
    benchmark::DoNotOptimize(length);
  }
  state.counters["tolerance"] = tol;
  state.counters["faces"] = body.face_count();
  state.counters["visible_length"] = length;
  state.SetLabel(kShapes[shape]);
}

// A unit sphere at `distance` in front of a perspective camera, tessellated for 0.5 px.
void BM_PixelTolerance(benchmark::State& state) {
  const double distance = static_cast<double>(state.range(0));
  Camera camera = Camera::perspective({0, -distance, 0}, {0, 0, 0}, 40);
  camera.width = 1024;
  camera.height = 768;
  constexpr double kPixels = 0.5;
  double tol = 0;
  int faces = 0;
  for (auto _ : state) {
    tol = chordal_tolerance_for_pixels(kPixels, Vec3::Zero(), 1, camera, 0, nullptr);
    Body b = sphere(Vec3::Zero(), 1, tol);
    faces = b.face_count();
    benchmark::DoNotOptimize(b.matrix());
  }
  const Body body = sphere(Vec3::Zero(), 1, tol);
  const double pixel = camera.pixel_size_at(Vec3(0, -1, 0), 0);
  state.counters["distance"] = distance;
  state.counters["faces"] = faces;
  state.counters["tolerance"] = tol;
  state.counters["error_px"] = measured_error(0, body) / pixel;
}

bool quick() { return std::getenv("HEDRA_BENCH_QUICK") != nullptr; }

void register_all() {
  const int settings = int(std::size(kTolerances)) - (quick() ? kQuickDropped : 0);  // quick: down to 1e-3
  for (int s = 0; s < 3; ++s)
    for (int i = 0; i < settings; ++i) {
      benchmark::RegisterBenchmark("lod/build", BM_Build)->Args({s, i})->Unit(benchmark::kMillisecond)
          ->MinTime(0.02);
      benchmark::RegisterBenchmark("lod/hlr", BM_HiddenLines)->Args({s, i})->Unit(benchmark::kMillisecond)
          ->MinTime(0.02);
    }
  for (int d : {5, 10, 20, 50, 100, 200, 500})
    benchmark::RegisterBenchmark("lod/pixels", BM_PixelTolerance)->Arg(d)->Unit(benchmark::kMillisecond)
        ->MinTime(0.02);
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
