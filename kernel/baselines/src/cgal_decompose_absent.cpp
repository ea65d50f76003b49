// The sanitizer build's decompose_cgal (make test-asan, CI): CGAL's Nef polyhedra take about
// 85 s of one core to compile under ASan + UBSan, a comparison method is not hedra's code, and
// the Release build runs its test (DecomposeCgal). `hedra decompose --method cgal` says so,
// as a build without TetGen does for --method tetgen.
#include "hedra/baselines/decompose_baselines.h"
#include "hedra/core/error.h"

namespace hedra {

Decomposition decompose_cgal(const Body&) {
  throw InvalidInput(
      "this hedra was built without CGAL's convex_decomposition_3 (sanitizer build)");
}

}  // namespace hedra
