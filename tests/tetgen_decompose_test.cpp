// hedra::tetgen (AGPL-3.0 TetGen) as a decomposition method.
#include "kernel/tetgen_decompose.h"

#include <gtest/gtest.h>

#include "decomposition_suite.h"
#include "kernel/convexity.h"

namespace hedra {
namespace {

TEST(TetgenDecompose, TetrahedraFillTheSuiteShapes) {
  for (const suite::Shape& shape : suite::shapes(false)) {
    Decomposition d = tetgen::decompose(shape.body);
    double volume = 0;
    for (const Body& t : d.pieces) {
      EXPECT_EQ(t.face_count(), 4);
      volume += t.volume();
    }
    EXPECT_NEAR(volume, shape.body.volume(), 1e-9 * shape.body.volume()) << shape.name;
    EXPECT_GE(d.pieces.size(), decompose(shape.body).pieces.size()) << shape.name;
  }
}

}  // namespace
}  // namespace hedra
