#include "hedra/io/mesh_io.h"

#include <gtest/gtest.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "testing/bad_files.h"
#include "testing/temp_files.h"
#include "hedra/core/error.h"
#include "hedra/core/primitives.h"
#include "hedra/core/transform.h"

namespace hedra {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() {
  return hedra::testing::temp_dir(std::string("mesh_io_") +
                                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
}

std::vector<Body> sample_bodies() {
  return {prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2),
          prism({{10, 0}, {14, 0}, {14, 4}, {10, 4}}, 0, 1, {{{11, 1}, {13, 1}, {13, 3}, {11, 3}}}),
          pyramid({{20, 0}, {22, 0}, {22, 2}, {20, 2}}, 0, {21, 1, 3})};
}

void expect_same(const Body& a, const Body& b, double tol) {
  EXPECT_EQ(a.vertex_count(), b.vertex_count());
  EXPECT_EQ(a.face_count(), b.face_count());
  EXPECT_EQ(a.edge_count(), b.edge_count());
  EXPECT_NEAR(a.volume(), b.volume(), tol * a.volume());
  EXPECT_NEAR(a.area(), b.area(), tol * a.area());
}

TEST(MeshIo, RoundTripEveryFormat) {
  const fs::path dir = temp_dir();
  const std::vector<Body> bodies = sample_bodies();
  for (const char* name : {"out.off", "out.obj", "out.ply", "out.stl", "ascii.stl"}) {
    const std::string path = (dir / name).string();
    io::WriteOptions options;
    options.stl_ascii = std::string(name) == "ascii.stl";
    io::write_bodies(bodies, path, options);
    std::vector<Body> back = io::read_bodies(path);
    ASSERT_EQ(back.size(), bodies.size()) << name;
    for (size_t i = 0; i < bodies.size(); ++i) {
      SCOPED_TRACE(name);
      expect_same(bodies[i], back[i], 0);
    }
  }
}

// Regression (fuzz finding, CI of stop 20): an L whose vertex (0, 1) lies on the edge
// (0, 3)–(0, 0), rotated 30° about z, has a bottom-face triangle 1e-17 of its size wide. Its
// rounded Newell normal was zero, so hedra rejected its own ASCII STL: "polygon 1 has zero area".
// `prism` now refuses an outline that touches itself (HostileIo), so the body is made as a mesh
// file gives it: its faces as they are.
TEST(MeshIo, SliverTriangleOfARotatedFaceReadsBack) {
  const fs::path dir = temp_dir();
  const Polygon2 outline = {{0, 0}, {3, 0}, {4, 1}, {0, 1}, {1, 3}, {0, 3}};
  std::vector<Vec3> corners;
  for (double z : {0.0, 2.0})
    for (const Vec2& p : outline) corners.emplace_back(p.x(), p.y(), z);
  std::vector<Face> faces = {Face{5, 4, 3, 2, 1, 0}, Face{6, 7, 8, 9, 10, 11}};
  for (int i = 0; i < 6; ++i) faces.push_back(Face{i, (i + 1) % 6, (i + 1) % 6 + 6, i + 6});
  const Body l = Body(corners, faces).transformed(Transform::rotation_z(30));
  for (const char* name : {"l.off", "l.obj", "l.ply", "ascii.stl"}) {
    const std::string path = (dir / name).string();
    io::WriteOptions options;
    options.stl_ascii = std::string(name) == "ascii.stl";
    io::write_bodies({l}, path, options);
    std::vector<Body> back = io::read_bodies(path);
    ASSERT_EQ(back.size(), 1u) << name;
    SCOPED_TRACE(name);
    expect_same(l, back[0], 0);
  }
}

TEST(MeshIo, DoublesSurviveTextFormatsExactly) {
  const fs::path dir = temp_dir();
  Body b = box({0.1, 0.2, 0.3}, {1.7, 2.9, 3.1}).rotated_z(17, {0.3, 0.3, 0});
  for (const char* name : {"r.off", "r.obj", "r.ply", "ra.stl"}) {
    const std::string path = (dir / name).string();
    io::WriteOptions options;
    options.stl_ascii = true;
    io::write_bodies({b}, path, options);
    Body back = io::read_bodies(path).at(0);
    // Same coordinates bit for bit (as a set; STL reorders vertices).
    auto sorted = [](std::vector<Vec3> v) {
      std::sort(v.begin(), v.end(), [](const Vec3& p, const Vec3& q) {
        return std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3);
      });
      return v;
    };
    EXPECT_EQ(sorted(back.vertices()), sorted(b.vertices())) << name;
    EXPECT_EQ(back.face_count(), 6) << name;
  }
}

TEST(MeshIo, OpenMeshReadsWhatHedraWrites) {
  omerr().disable();
  omlog().disable();
  const fs::path dir = temp_dir();
  Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2);
  for (const char* name : {"l.off", "l.obj", "l.ply", "l.stl"}) {
    const std::string path = (dir / name).string();
    io::write_bodies({l}, path);
    OpenMesh::PolyMesh_ArrayKernelT<> mesh;
    ASSERT_TRUE(OpenMesh::IO::read_mesh(mesh, path)) << name;
    EXPECT_EQ(mesh.n_vertices(), 12u) << name;
    const bool stl = std::string(name) == "l.stl";
    EXPECT_EQ(mesh.n_faces(), stl ? 20u : 8u) << name;  // STL: 2·(6 − 2) caps + 6·2 sides
  }
}

TEST(MeshIo, TriangulatedStlBoxBecomesSixFaces) {
  const fs::path dir = temp_dir();
  io::write_bodies({box({0, 0, 0}, {1, 2, 3})}, (dir / "box.stl").string());
  std::vector<Body> back = io::read_bodies((dir / "box.stl").string());
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].face_count(), 6);
  EXPECT_EQ(back[0].volume(), 6);
}

// hedra writes no file it would reject. STL has no vertex numbers (a reader welds equal points),
// so two bodies sharing a point, stacked boxes, would read back as one mesh with non-manifold
// edges ("inconsistent orientation or non-manifold edge"). Writing them is refused, naming the
// file, the bodies and the point, and no file is left; OFF keeps them apart and reads back as two
// bodies. Binary STL welds after rounding to float32: two points equal only in float32 count.
TEST(MeshIo, BodiesSharingAPointAreNotWrittenToStl) {
  const fs::path dir = temp_dir();
  const std::vector<Body> stack{box({0, 0, 0}, {1, 1, 1}), box({0, 0, 1}, {1, 1, 2})};
  io::WriteOptions named;
  named.names = {"lower", "upper"};
  for (bool ascii : {false, true}) {
    io::WriteOptions o = named;
    o.stl_ascii = ascii;
    const std::string path = (dir / (ascii ? "a.stl" : "b.stl")).string();
    try {
      io::write_bodies(stack, path, o);
      ADD_FAILURE() << "wrote " << path;
    } catch (const InvalidInput& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": bodies 'lower' and 'upper' share the point (", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find("write OFF, OBJ, PLY or a scene file"), std::string::npos);
    }
    EXPECT_FALSE(fs::exists(path));
  }
  io::write_bodies(stack, (dir / "stack.off").string(), named);
  EXPECT_EQ(io::read_bodies((dir / "stack.off").string()).size(), 2u);
  // Apart (a gap of 1e-3): written and read back as two bodies.
  const std::vector<Body> apart{box({0, 0, 0}, {1, 1, 1}), box({0, 0, 1.001}, {1, 1, 2})};
  io::write_bodies(apart, (dir / "apart.stl").string(), named);
  EXPECT_EQ(io::read_bodies((dir / "apart.stl").string()).size(), 2u);
  // 1 + 2^-40 and 1 differ in double, not in float32: binary STL is refused, ASCII STL is not.
  const std::vector<Body> close{box({0, 0, 0}, {1, 1, 1}), box({0, 0, 1 + std::ldexp(1.0, -40)}, {1, 1, 2})};
  EXPECT_THROW(io::write_bodies(close, (dir / "close.stl").string()), InvalidInput);
  io::WriteOptions ascii;
  ascii.stl_ascii = true;
  EXPECT_NO_THROW(io::write_bodies(close, (dir / "close_ascii.stl").string(), ascii));
}

// A body valid in double whose float32 rounding is not a body: a plate 1e-5 thick at x = 1000,
// where float32's step is 6.1e-5, so its two sides round to one plane and every side face
// collapses. Binary STL would hold a flat, invalid mesh; it is refused, nothing is written, and
// ASCII STL (doubles) and OFF read back as the plate. A plate 1e-3 thick there (16 steps) is
// written as binary STL and reads back as one body of the same volume within float32's rounding.
TEST(MeshIo, BodyThatFloat32RoundingBreaksIsNotWrittenToBinaryStl) {
  const fs::path dir = temp_dir();
  const std::vector<Body> thin{box({1000, 0, 0}, {1000.00001, 1, 1})};
  const std::string path = (dir / "thin.stl").string();
  try {
    io::write_bodies(thin, path);
    ADD_FAILURE() << "wrote " << path;
  } catch (const InvalidInput& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ": rounded to float32 (binary STL), the bodies would not read back: ", 0), 0u) << message;
    EXPECT_NE(message.find("ASCII STL (which keeps doubles), OFF, OBJ, PLY or a scene file keep it"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(path));
  io::WriteOptions ascii;
  ascii.stl_ascii = true;
  for (const std::string name : {"thin_ascii.stl", "thin.off"}) {
    io::write_bodies(thin, (dir / name).string(), ascii);
    const std::vector<Body> back = io::read_bodies((dir / name).string());
    ASSERT_EQ(back.size(), 1u) << name;
    EXPECT_EQ(back[0].volume(), thin[0].volume()) << name;
  }
  const std::vector<Body> plate{box({1000, 0, 0}, {1000.001, 1, 1})};
  io::write_bodies(plate, (dir / "plate.stl").string());
  const std::vector<Body> back = io::read_bodies((dir / "plate.stl").string());
  ASSERT_EQ(back.size(), 1u);
  EXPECT_NEAR(back[0].volume(), plate[0].volume(), 2 * 6.2e-5);  // each side within half a step
}

TEST(MeshIo, BadFilesGiveNamedErrors) {
  const fs::path dir = temp_dir();
  testing::write_bad_files(dir);
  for (const auto& bad : testing::bad_files()) {
    const std::string path = (dir / bad.name).string();
    try {
      io::read_bodies(path);
      ADD_FAILURE() << bad.name << " was accepted";
    } catch (const InvalidInput& e) {
      std::string message = e.what();
      EXPECT_EQ(message.rfind(path, 0), 0u) << message;  // starts with the file name
      EXPECT_NE(message.find(bad.expected), std::string::npos) << bad.name << ": " << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;  // one line
    }
  }
}

TEST(MeshIo, MissingFileAndUnknownFormat) {
  EXPECT_THROW(io::read_bodies("/nonexistent/x.off"), IoError);
  EXPECT_THROW(io::read_bodies("x.xyz"), InvalidInput);
}

TEST(MeshIo, FailedWriteLeavesNoFile) {
  const fs::path dir = temp_dir();
  EXPECT_THROW(io::write_bodies(sample_bodies(), (dir / "missing" / "out.off").string()), IoError);
  EXPECT_FALSE(fs::exists(dir / "missing"));
}

}  // namespace
}  // namespace hedra
