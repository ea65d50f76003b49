// Issue 14, "Done when": a float32 STL of a non-axis-aligned part with curved faces (the demo's
// L block and a drilled plate, box minus cylinder, on a ground slab, under a generic rotation R,
// written by hedra's own STL writer) runs through every command, and its drawing and shadows
// equal those of the aligned twin seen by the correspondingly rotated camera and light: drawn
// 2D length within 1e-3, shadow areas within 1e-4 relative.
//
// A mesh file is seen along d0 = (−1, −2, −1.5) under a light along l0 = (−1, −1.5, −3)
// (cli/info.h, load_scene); the aligned twin is a scene seen along R⁻¹d0 under R⁻¹l0, which is
// the same picture up to a rotation in the picture plane (lengths and areas do not change).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "testing/cli_run.h"
#include "testing/temp_files.h"

namespace {

namespace fs = std::filesystem;
using hedra::testing::run_hedra;

// Hidden lines draw only the edges between faces that turn by more than the crease angle (the
// `outline` work), so the diagonals between nearly coplanar triangles of a float32 face are not
// drawn and the exact reading is compared. Before that landed, the rotated part was read with
// --tolerance 1e-5, which merges them back into its planar faces; both are checked.
const std::string kReadOptions = "";
const std::string kToleranceOptions = "--tolerance 1e-5";

const Eigen::Vector3d kAxis = Eigen::Vector3d(0.3, -0.7, 0.65).normalized();
constexpr double kDegrees = 37.3;

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
std::string vec(const Eigen::Vector3d& v) { return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]"; }

// The bodies, each followed by `transform` (empty: aligned); the L block and the plate stand on
// the ground, or float `lift` above it.
std::string bodies(const std::string& transform, double lift) {
  const std::string t = transform.empty() ? "" : ", \"transform\": [" + transform + "]";
  const std::string z0 = num(lift), z1 = num(lift + 1), z2 = num(lift + 2);
  return R"({"name": "ground", "box": {"min": [-4, -4, -1], "max": [11, 10, 0]})" + t + R"(},
  {"name": "L", "prism": {"polygon": [[0,0],[4,0],[4,1],[1,1],[1,3],[0,3]], "z": [)" + z0 + ", " + z2 + "]}" + t + R"(},
  {"name": "slab", "box": {"min": [4.5, 3.5, )" + z0 + R"(], "max": [8.5, 7.5, )" + z1 + R"(]}, "hidden": true},
  {"name": "drill", "cylinder": {"radius": 0.5, "z": [-1, 3], "tolerance": 0.01},
   "transform": [{"translate": [6.5, 5.5, 0]}], "hidden": true},
  {"name": "plate", "subtract": ["slab", "drill"])" + t + "}";
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct Measures {
  double drawn = 0;  // visible edges and junctions, length in the picture plane
  double cast = 0, self = 0;
};

Measures measure(const std::string& file, const Eigen::Vector3d& view, const fs::path& dir,
                 const std::string& options) {
  Measures m;
  const Eigen::Vector3d u = view.normalized();
  const auto r = run_hedra("hlr --json " + (dir / "h.json").string() + " " + file + " " + options);
  EXPECT_EQ(r.code, 0) << file << ": " << r.err;
  if (r.code != 0) return m;
  const nlohmann::json h = nlohmann::json::parse(read(dir / "h.json"));
  for (const char* list : {"visible", "junction", "outline"})
    for (const auto& s : h[list]) {
      const Eigen::Vector3d d(s[3].get<double>() - s[0].get<double>(), s[4].get<double>() - s[1].get<double>(),
                              s[5].get<double>() - s[2].get<double>());
      m.drawn += (d - d.dot(u) * u).norm();
    }
  const auto s = run_hedra("shadows --json " + (dir / "s.json").string() + " " + file + " " + options);
  EXPECT_EQ(s.code, 0) << file << ": " << s.err;
  if (s.code != 0) return m;
  const nlohmann::json parsed_face = nlohmann::json::parse(read(dir / "s.json"));
  for (const auto& face : parsed_face["lights"][0]["faces"])
    (face["self_shadowed"].get<bool>() ? m.self : m.cast) += face["shadow_area"].get<double>();
  return m;
}

// Writes the aligned twin and the rotated float32 STL of the scene into `dir`; returns the
// aligned scene's path and the STL's.
std::pair<std::string, std::string> write_twins(const fs::path& dir, double lift, const Eigen::Vector3d& view,
                                                const Eigen::Vector3d& light) {
  const std::string aligned = hedra::testing::write(
      dir / "aligned.json", "{\"version\": 1, \"bodies\": [" + bodies("", lift) +
                                "],\n \"camera\": {\"projection\": \"parallel\", \"direction\": " +
                                vec(view) + ", \"up\": [0, 0, 1]},\n \"lights\": [{\"type\": "
                                "\"directional\", \"direction\": " + vec(light) + "}]}");
  const std::string rotate = "{\"rotate\": {\"axis\": " + vec(kAxis) + ", \"deg\": " + num(kDegrees) + "}}";
  const std::string rotated = hedra::testing::write(
      dir / "rotated.json", "{\"version\": 1, \"bodies\": [" + bodies(rotate, lift) + "]}");
  const std::string stl = (dir / "part.stl").string();
  const auto c = run_hedra("convert " + rotated + " " + stl);
  EXPECT_EQ(c.code, 0) << c.err;
  EXPECT_NE(read(stl).substr(0, 5), "solid");  // binary
  return {aligned, stl};
}

const Eigen::Matrix3d kRotation = Eigen::AngleAxisd(kDegrees * M_PI / 180, kAxis).toRotationMatrix();
const Eigen::Vector3d kD0(-1, -2, -1.5), kL0(-1, -1.5, -3);

// Standing on the ground: every command runs; the drawing and the shadows equal the aligned
// twin's. The bodies' bottoms and the ground's top are coplanar only within float32 rounding, so
// where a bottom edge dips 1e-7 into the ground the exact hidden lines hide it and draw the
// junction line of the side face with the ground's top instead, 1e-7 away: the same drawing, with
// part of the contact drawn as junction instead of visible edge (docs/stability.md).
TEST(Float32Part, StandingPartRunsThroughEveryCommandAndDrawsAndShadowsLikeTheAlignedTwin) {
  const fs::path dir = hedra::testing::temp_dir("float32_part_standing");
  const Eigen::Vector3d view = kRotation.transpose() * kD0, light = kRotation.transpose() * kL0;
  const auto [aligned, stl] = write_twins(dir, 0, view, light);
  for (const std::string& options : {kReadOptions, kToleranceOptions}) {
    for (const std::string& cmd :
         {"info " + stl, "decompose " + stl, "hlr " + stl + " -o " + (dir / "p.svg").string(),
          "shadows " + stl, "render --width 200 --height 150 " + stl + " -o " + (dir / "p.png").string(),
          "convert " + stl + " " + (dir / "back.off").string()}) {
      const auto r = run_hedra(cmd + " " + options);
      EXPECT_EQ(r.code, 0) << cmd << " " << options << ": " << r.err;
    }
  }
  hedra::testing::write(dir / "seg.txt", "-5 -5 0.5 12 10 0.5\n0 0 -3 3 2 4\n");
  const auto cl = run_hedra("clip --body " + stl + " --segments " + (dir / "seg.txt").string() + " -o " +
                            (dir / "clipped.txt").string());
  EXPECT_EQ(cl.code, 0) << cl.err;
  const Measures want = measure(aligned, view, dir, "");
  EXPECT_GT(want.drawn, 20);
  EXPECT_GT(want.cast, 1);
  for (const std::string& options : {kReadOptions, kToleranceOptions}) {
    const Measures got = measure(stl, kD0, dir, options);
    EXPECT_NEAR(got.drawn, want.drawn, 1e-3 * want.drawn) << options;
    EXPECT_NEAR(got.cast, want.cast, 1e-4 * want.cast) << options;
    EXPECT_NEAR(got.self, want.self, 1e-4 * want.self) << options;
  }
  fs::remove_all(dir);
}

// Clear of the ground (by 0.05): drawing and shadows equal the aligned twin's.
TEST(Float32Part, RotatedStlDrawsAndShadowsLikeTheAlignedTwin) {
  const fs::path dir = hedra::testing::temp_dir("float32_part_lifted");
  const Eigen::Vector3d view = kRotation.transpose() * kD0, light = kRotation.transpose() * kL0;
  const auto [aligned, stl] = write_twins(dir, 0.05, view, light);
  const Measures want = measure(aligned, view, dir, "");
  EXPECT_GT(want.drawn, 20);
  EXPECT_GT(want.cast, 1);
  for (const std::string& options : {kReadOptions, kToleranceOptions}) {
    const Measures got = measure(stl, kD0, dir, options);
    EXPECT_NEAR(got.drawn, want.drawn, 1e-3 * want.drawn) << options;
    EXPECT_NEAR(got.cast, want.cast, 1e-4 * want.cast) << options;
    EXPECT_NEAR(got.self, want.self, 1e-4 * want.self) << options;
  }
  fs::remove_all(dir);
}

// Regression (issue 14): a generically rotated cylinder standing on the ground, as float32 STL
// read with --tolerance 1e-5. Its side faces are planar only within rounding after the merge, and
// where its base sinks 1e-8 into the ground the contact is drawn as junction lines on the side
// faces. Hidden lines used to test those junctions against the cylinder's own volume, which hid
// them by a rounding of the face plane: 0.16 of the contact line went missing (0.44 % of the
// drawing). A convex body cannot hide its own front faces, so its volume is no candidate now.
TEST(Float32Part, RotatedCylinderStandingOnTheGroundKeepsItsContactLine) {
  const fs::path dir = hedra::testing::temp_dir("float32_cylinder_standing");
  const Eigen::Vector3d view = kRotation.transpose() * kD0, light = kRotation.transpose() * kL0;
  auto scene = [&](const std::string& t) {
    const std::string tr = t.empty() ? "" : ", \"transform\": [" + t + "]";
    return R"({"name": "ground", "box": {"min": [-3, -3, -1], "max": [3, 3, 0]})" + tr +
           R"(}, {"name": "cyl", "cylinder": {"radius": 1, "z": [0, 2], "tolerance": 0.01})" + tr + "}";
  };
  const std::string aligned = hedra::testing::write(
      dir / "aligned.json", "{\"version\": 1, \"bodies\": [" + scene("") +
                                "],\n \"camera\": {\"projection\": \"parallel\", \"direction\": " + vec(view) +
                                ", \"up\": [0, 0, 1]},\n \"lights\": [{\"type\": \"directional\", \"direction\": " +
                                vec(light) + "}]}");
  const std::string rotate = "{\"rotate\": {\"axis\": " + vec(kAxis) + ", \"deg\": " + num(kDegrees) + "}}";
  const std::string rotated =
      hedra::testing::write(dir / "rotated.json", "{\"version\": 1, \"bodies\": [" + scene(rotate) + "]}");
  const std::string stl = (dir / "cyl.stl").string();
  ASSERT_EQ(run_hedra("convert " + rotated + " " + stl).code, 0);
  const Measures want = measure(aligned, view, dir, "");
  EXPECT_GT(want.drawn, 30);
  for (const std::string& options : {kReadOptions, kToleranceOptions}) {
    const Measures got = measure(stl, kD0, dir, options);
    EXPECT_NEAR(got.drawn, want.drawn, 1e-3 * want.drawn) << options;
    EXPECT_NEAR(got.cast, want.cast, 1e-4 * want.cast) << options;
  }
  fs::remove_all(dir);
}

}  // namespace
