// Faces scaling (issue 15), the in-process half: hidden lines of one scene, a ground slab
// (8 × 8 × 0.5), a sphere (r = 1.5) and a cylinder (r = 0.8, h = 2.5) at chordal tolerance
// t = 1e-2 … 1e-5 (quick: … 1e-4), parallel view along (−1, −1, −1):
//  - hedra: `hidden_lines` on the tessellated bodies (building the bodies is not timed);
//  - OCCT: `HLRBRep_PolyAlgo` on the same analytic shapes meshed by `BRepMesh_IncrementalMesh`
//    at linear deflection t (the same chordal tolerance); the meshing time is reported apart
//    (counter mesh_ms) and not timed, like hedra's tessellation; t ≤ 1e-4 only (see
//    occt_tolerances);
//  - OCCT: the exact `HLRBRep_Algo` on the analytic shapes (no meshing), whose drawn 2D length
//    (visible sharp edges and outlines) is the reference for hedra's at every t (counter
//    drawn_2d on both sides).
// The whole-process half (info, hlr, shadows, render: CPU time and peak memory per face, and a
// 1 M-triangle mesh file) is scripts/faces_scaling.py; scripts/faces_report.py writes the
// "Faces scaling" section of docs/benchmarks.md from both.
#include <benchmark/benchmark.h>

#include <malloc.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <utility>
#include <optional>
#include <vector>

#include "hedra/core/primitives.h"
#include "hedra/core/smooth_surface.h"
#include "hedra/core/transform.h"
#include "hedra/visibility/roberts.h"

#if HEDRA_HAVE_OCCT
// Shapes from surfaces and sewing: Debian's OCCT 7.6 headers for BRepPrimAPI need a header the
// packages lack (NCollection_AliasedArray.hxx).
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeShell.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepLib.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_SphericalSurface.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Builder.hxx>
#include <TopoDS_Compound.hxx>

#include "occt_hlr.h"
#endif

namespace {

using namespace hedra;

bool quick() { return std::getenv("HEDRA_BENCH_QUICK") != nullptr; }

// The scene of scripts/faces_scaling.py, kept in step with it.
const Vec3 kSlabMin(-4, -4, -0.5), kSlabMax(4, 4, 0);
const Vec3 kBallCentre(-1.5, 0, 1.5);
constexpr double kBallRadius = 1.5, kCanRadius = 0.8, kCanHeight = 2.5;
const Vec3 kCanAt(2, 1, 0);
constexpr int kMaxFaces = 2000000;

double tolerance_of(const benchmark::State& state) { return std::pow(10.0, -static_cast<double>(state.range(0))); }

std::vector<Body> hedra_scene(double t) {
  return {box(kSlabMin, kSlabMax), sphere(kBallCentre, kBallRadius, t, kMaxFaces),
          cylinder(kCanRadius, 0, kCanHeight, t, kMaxFaces).transformed(Transform::translation(kCanAt))};
}

// The analytic surfaces, as `hedra hlr` gives them for a scene's primitives (outlines from the
// true normals).
std::vector<SmoothSurface> hedra_surfaces() {
  return {SmoothSurface(), SmoothSurface::sphere(kBallCentre, kBallRadius),
          SmoothSurface::cylinder(kCanRadius, 0, kCanHeight).transformed(Transform::translation(kCanAt))};
}

const Camera kCamera = Camera::parallel({-1, -1, -1});

// Visible sharp edges and outlines, in the picture plane.
double drawn_2d(const HlrResult& r) { return r.picture_length(LineKind::Edge) + r.picture_length(LineKind::Outline); }

void BM_FacesHedraHlr(benchmark::State& state) {
  const std::vector<Body> bodies = hedra_scene(tolerance_of(state));
  const std::vector<SmoothSurface> surfaces = hedra_surfaces();
  long faces = 0;
  for (const Body& b : bodies) faces += b.face_count();
  // One untimed call first: it decides each body's convexity (kept with the body), which the
  // first timed iteration would otherwise include; at 1e-5 a repetition is a single iteration.
  HlrResult r = hidden_lines(bodies, surfaces, kCamera);
  for (auto _ : state) {
    r = hidden_lines(bodies, surfaces, kCamera);
    benchmark::DoNotOptimize(r.visible.data());
  }
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["visible_length"] = r.length(LineKind::Edge);
  state.counters["drawn_2d"] = drawn_2d(r);
}

// The first call on freshly built bodies: hidden_lines decides each body's convexity once and
// keeps the verdict with the body (Body::convexity_memo), so the repeated calls above run
// without it. The bodies are rebuilt outside the timed region.
void BM_FacesHedraHlrFirst(benchmark::State& state) {
  const double t = tolerance_of(state);
  const std::vector<SmoothSurface> surfaces = hedra_surfaces();
  long faces = 0;
  HlrResult r;
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<Body> bodies = hedra_scene(t);
    faces = 0;
    for (const Body& b : bodies) faces += b.face_count();
    state.ResumeTiming();
    r = hidden_lines(bodies, surfaces, kCamera);
    benchmark::DoNotOptimize(r.visible.data());
    state.PauseTiming();
    bodies.clear();  // freed outside the timed region
    state.ResumeTiming();
  }
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["visible_length"] = r.length(LineKind::Edge);
  state.counters["drawn_2d"] = drawn_2d(r);
}

#if HEDRA_HAVE_OCCT
TopoDS_Shape occt_sphere() {
  const Handle(Geom_SphericalSurface) s = new Geom_SphericalSurface(
      gp_Ax3(gp_Pnt(kBallCentre.x(), kBallCentre.y(), kBallCentre.z()), gp::DZ()), kBallRadius);
  return BRepBuilderAPI_MakeSolid(BRepBuilderAPI_MakeShell(s).Shell()).Solid();
}

TopoDS_Shape occt_cylinder() {
  const gp_Ax3 axis(gp_Pnt(kCanAt.x(), kCanAt.y(), kCanAt.z()), gp::DZ());
  const Handle(Geom_CylindricalSurface) s = new Geom_CylindricalSurface(axis, kCanRadius);
  BRepBuilderAPI_Sewing sew;
  sew.Add(BRepBuilderAPI_MakeFace(s, 0, 2 * M_PI, 0, kCanHeight, 1e-7).Face());
  for (double z : {0.0, kCanHeight}) {
    const gp_Ax2 at(gp_Pnt(kCanAt.x(), kCanAt.y(), kCanAt.z() + z), gp::DZ());
    const TopoDS_Wire rim = BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(gp_Circ(at, kCanRadius)).Edge()).Wire();
    sew.Add(BRepBuilderAPI_MakeFace(gp_Pln(gp_Ax3(at)), rim, Standard_True).Face());
  }
  sew.Perform();
  return BRepBuilderAPI_MakeSolid(TopoDS::Shell(sew.SewedShape())).Solid();
}

TopoDS_Compound occt_scene() {
  TopoDS_Builder builder;
  TopoDS_Compound c;
  builder.MakeCompound(c);
  builder.Add(c, bench::occt_box(kSlabMin, kSlabMax));
  builder.Add(c, occt_sphere());
  builder.Add(c, occt_cylinder());
  // The cylinder made from its surface and sewn keeps its seam (u = 0) recorded as C0, so
  // HLRBRep_Algo draws the seam as a visible sharp edge: 2.041 of a drawn length of 58.71
  // (+3.6 %), where BRepPrimAPI_MakeCylinder would record it as smooth. EncodeRegularity
  // records every edge's continuity from its two faces, as the primitives do; the seam then
  // goes to the smooth class (RgNLineVCompound), which neither side counts.
  BRepLib::EncodeRegularity(c);
  return c;
}

void BM_FacesOcctPoly(benchmark::State& state) {
  const double t = tolerance_of(state);
  double length = 0, mesh_ms = 0;
  TopoDS_Compound c;
  bench::OcctLines lines;
  // Meshed once per tolerance (OCCT's meshing takes 26 s at 1e-4 on the development machine);
  // every iteration runs the HLR on the same triangulation.
  static std::map<int, std::pair<TopoDS_Compound, double>> meshed;
  auto it = meshed.find(static_cast<int>(state.range(0)));
  if (it == meshed.end()) {
    TopoDS_Compound scene = occt_scene();
    const auto t0 = std::chrono::steady_clock::now();
    BRepMesh_IncrementalMesh mesh(scene, t);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    it = meshed.emplace(static_cast<int>(state.range(0)), std::make_pair(scene, ms)).first;
  }
  c = it->second.first;
  mesh_ms = it->second.second;
  for (auto _ : state) {
    state.PauseTiming();
    lines.clear();
    state.ResumeTiming();
    bench::occt_poly_lines(c, kCamera, lines);
    state.PauseTiming();
    length = lines.length();
    state.ResumeTiming();
  }
  state.counters["mesh_ms"] = mesh_ms;
  state.counters["visible_length_2d"] = length;
}

// The exact HLRBRep_Algo on the analytic shapes: no tolerance, no meshing.
void BM_FacesOcctExact(benchmark::State& state) {
  const TopoDS_Compound c = occt_scene();
  double length = 0;
  bench::OcctLines lines;
  for (auto _ : state) {
    state.PauseTiming();
    lines.clear();
    state.ResumeTiming();
    bench::occt_exact_lines(c, kCamera, lines);
    state.PauseTiming();
    length = lines.length();
    state.ResumeTiming();
  }
  state.counters["drawn_2d"] = length;
}
#endif

void tolerances(benchmark::internal::Benchmark* b) {
  b->ArgNames({"t_exp"});
  for (int k = 2; k <= (quick() ? 4 : 5); ++k) b->Args({k});
}

// OCCT's meshing grows about 50× per 10× finer tolerance (0.5 s at 1e-3, 26 s at 1e-4): at 1e-5
// it would take longer than the whole benchmark run, so OCCT stops at 1e-4 (quick: 1e-3).
void occt_tolerances(benchmark::internal::Benchmark* b) {
  b->ArgNames({"t_exp"});
  for (int k = 2; k <= (quick() ? 3 : 4); ++k) b->Args({k});
}

}  // namespace

BENCHMARK(BM_FacesHedraHlr)->Apply(tolerances)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FacesHedraHlrFirst)->Apply(tolerances)->UseRealTime()->Unit(benchmark::kMillisecond);
#if HEDRA_HAVE_OCCT
BENCHMARK(BM_FacesOcctPoly)->Apply(occt_tolerances)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FacesOcctExact)->UseRealTime()->Unit(benchmark::kMillisecond);
#endif

// The allocator as the hedra command sets it (cli/main.cpp, tune_allocator): blocks up to 32 MB
// from the heap, freed memory kept. glibc's default maps every block over 32 MB afresh and
// unmaps it on free, so each call pays its page faults again: at 1e-5 the occlusion volume's
// 59 MB of planes alone, 258 instead of 110 ms a call on this project's machine, where a page
// fault costs about 10 µs (1e-4: no difference). hedra and OCCT run under the same settings.
int main(int argc, char** argv) {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_TOP_PAD, 64 << 20);
#endif
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
