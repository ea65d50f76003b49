// `hedra hlr` end to end: the JSON format, the SVG, errors and exit codes, no half-written files.
#include <gtest/gtest.h>

#include "testing/cli_run.h"
#include "testing/temp_files.h"
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "hedra/core/transform.h"

namespace {

namespace fs = std::filesystem;

using Result = hedra::testing::CliResult;

Result run(const std::string& args) { return hedra::testing::run_hedra(args); }

fs::path temp_dir(const char* name) { return hedra::testing::temp_dir(std::string("hlr_cli_") + name); }

using hedra::testing::write;

std::string read(const fs::path& path) { return hedra::testing::read_text(path); }

// A cube pierced by a bar, seen from −x, −y, +z.
const char* kBarScene = R"({
  "version": 1,
  "bodies": [
    {"name": "cube", "box": {"min": [0, 0, 0], "max": [4, 4, 4]}},
    {"name": "bar", "box": {"min": [-1, 1, 1], "max": [5, 3, 3]}}
  ],
  "camera": {"projection": "parallel", "direction": [1, 0.5, -0.7], "up": [0, 0, 1]},
  "image": {"width": 400, "height": 300}
})";

bool has(const nlohmann::json& list, std::array<double, 6> s) {
  for (const auto& e : list) {
    const std::array<double, 6> v{e[0], e[1], e[2], e[3], e[4], e[5]};
    if (v == s) return true;
    if (std::array<double, 6>{v[3], v[4], v[5], v[0], v[1], v[2]} == s) return true;
  }
  return false;
}

const char* kCubeOff = "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                       "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

// A mesh file is a scene of its bodies, seen parallel along (−1, −2, −1.5): a unit cube shows
// three faces, so 9 visible edges of length 1 and 3 hidden ones.
TEST(HlrCli, AcceptsAMeshFile) {
  const fs::path dir = temp_dir("mesh");
  write(dir / "cube.off", kCubeOff);
  const Result r = run("hlr " + (dir / "cube.off").string() + " --hidden --json " + (dir / "c.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(read(dir / "c.json"));
  auto length = [](const nlohmann::json& list) {
    double total = 0;
    for (const auto& s : list)
      total += std::hypot(s[3].get<double>() - s[0].get<double>(), s[4].get<double>() - s[1].get<double>(),
                          s[5].get<double>() - s[2].get<double>());
    return total;
  };
  EXPECT_NEAR(length(j["visible"]), 9.0, 1e-12);
  EXPECT_NEAR(length(j["hidden"]), 3.0, 1e-12);
  EXPECT_TRUE(j["junction"].empty());
  fs::remove_all(dir);
}

TEST(HlrCli, WritesJsonAndSvg) {
  const fs::path d = temp_dir("json");
  write(d / "bar.json", kBarScene);
  const Result r = run("hlr " + (d / "bar.json").string() + " -o " + (d / "bar.svg").string() + " --json " +
                       (d / "out.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("2 junction segments"), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(read(d / "out.json"));
  ASSERT_TRUE(j.contains("visible") && j.contains("hidden") && j.contains("junction") && j.contains("ms"));
  EXPECT_TRUE(j["ms"].is_number());
  EXPECT_GE(j["ms"].get<double>(), 0);
  EXPECT_TRUE(j["hidden"].empty());  // only with --hidden
  // Junction segments only under "junction", exactly the two seen (world coordinates).
  ASSERT_EQ(j["junction"].size(), 2u);
  EXPECT_TRUE(has(j["junction"], {0, 1, 1, 0, 1, 3}));
  EXPECT_TRUE(has(j["junction"], {0, 1, 3, 0, 3, 3}));
  EXPECT_FALSE(has(j["visible"], {0, 1, 1, 0, 1, 3}));
  // The bar's edges up to where it enters the cube.
  EXPECT_TRUE(has(j["visible"], {-1, 1, 3, 0, 1, 3}));
  for (const auto& e : j["visible"]) EXPECT_EQ(e.size(), 6u);
  const std::string svg = read(d / "bar.svg");
  EXPECT_NE(svg.find("width=\"400\" height=\"300\""), std::string::npos);
  EXPECT_NE(svg.find("class=\"junction\""), std::string::npos);
  EXPECT_EQ(svg.find("class=\"hidden\""), std::string::npos);
  fs::remove_all(d);
}

TEST(HlrCli, HiddenLinesOnRequest) {
  const fs::path d = temp_dir("hidden");
  write(d / "bar.json", kBarScene);
  const Result r = run("hlr " + (d / "bar.json").string() + " --hidden -o " + (d / "bar.svg").string() +
                       " --json " + (d / "out.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(read(d / "out.json"));
  EXPECT_FALSE(j["hidden"].empty());
  // The cube's edge (4, 4, 0)–(4, 4, 4) is behind the cube: hidden whole.
  EXPECT_TRUE(has(j["hidden"], {4, 4, 0, 4, 4, 4}));
  EXPECT_NE(read(d / "bar.svg").find("class=\"hidden\""), std::string::npos);
  fs::remove_all(d);
}

TEST(HlrCli, ErrorsNameTheFileAndPlaceAndWriteNothing) {
  const fs::path d = temp_dir("errors");
  write(d / "bad.json", "{\n  \"version\": 1,\n  \"bodies\": [\n    {\"name\": \"a\", \"box\": {\"min\": [0, 0], \"max\": [1, 1, 1]}}\n  ]\n}\n");
  Result r = run("hlr " + (d / "bad.json").string() + " -o " + (d / "out.svg").string() + " --json " +
                 (d / "out.json").string());
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("bad.json:4:"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(d / "out.svg"));
  EXPECT_FALSE(fs::exists(d / "out.json"));
  // The eye inside a body: the file and the body are named.
  write(d / "inside.json", R"({"version": 1, "bodies": [{"name": "tower", "box": {"min": [0, 0, 0], "max": [4, 4, 4]}}],
    "camera": {"projection": "perspective", "eye": [1, 1, 1], "target": [3, 3, 0], "up": [0, 0, 1], "fov_deg": 40}})");
  r = run("hlr " + (d / "inside.json").string() + " -o " + (d / "out.svg").string());
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("inside.json: body 'tower'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "out.svg"));
  // Missing file: exit 3; no scene argument: usage, exit 2.
  EXPECT_EQ(run("hlr " + (d / "missing.json").string()).code, 3);
  EXPECT_EQ(run("hlr").code, 2);
  // An unwritable output: exit 3 and nothing left behind.
  write(d / "bar.json", kBarScene);
  r = run("hlr " + (d / "bar.json").string() + " -o " + (d / "no-such-dir" / "x.svg").string());
  EXPECT_EQ(r.code, 3);
  fs::remove_all(d);
}

// Length of the world segments projected along the unit direction d (a parallel view).
double picture_length(const nlohmann::json& list, const hedra::Vec3& view) {
  const hedra::Vec3 d = view.normalized();
  double total = 0;
  for (const auto& s : list) {
    hedra::Vec3 v(s[3].get<double>() - s[0].get<double>(), s[4].get<double>() - s[1].get<double>(),
                  s[5].get<double>() - s[2].get<double>());
    total += (v - v.dot(d) * d).norm();
  }
  return total;
}

TEST(HlrCli, CreaseAngleIsValidated) {
  const fs::path d = temp_dir("crease");
  write(d / "bar.json", kBarScene);
  for (const char* bad : {"-1", "180.5", "nan", "inf", "abc"}) {
    const Result r = run("hlr " + (d / "bar.json").string() + " --crease-angle " + bad);
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_NE(r.err.find("crease-angle"), std::string::npos) << r.err;
  }
  for (const char* good : {"0", "180", "45"})
    EXPECT_EQ(run("hlr " + (d / "bar.json").string() + " --crease-angle " + good).code, 0) << good;
  fs::remove_all(d);
}

// A sphere of radius 1.5 above a box, seen from above at a slant: the box's picture and the
// sphere's do not meet.
const char* kSphereScene = R"({
  "bodies": [
    {"name": "base", "box": {"min": [-6, -2, -1], "max": [-3, 2, 0]}},
    {"name": "ball", "sphere": {"center": [2, 0, 1], "radius": 1.5, "tolerance": 0.001}}
  ],
  "camera": {"projection": "parallel", "direction": [0.3, 0.4, -1], "up": [0, 0, 1]}
})";

TEST(HlrCli, CurvedBodiesDrawTheirOutlineNotTheirFacets) {
  const fs::path d = temp_dir("outline");
  write(d / "s.json", kSphereScene);
  write(d / "bar.json", kBarScene);
  Result r = run("hlr " + (d / "s.json").string() + " -o " + (d / "s.svg").string() + " --json " +
                 (d / "s.hlr.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("outline segments"), std::string::npos) << r.out;
  nlohmann::json j = nlohmann::json::parse(read(d / "s.hlr.json"));
  ASSERT_TRUE(j.contains("outline"));
  EXPECT_FALSE(j.contains("smooth"));
  // The outline of a sphere of radius 1.5 in a parallel view: a circle, 3π; the box's
  // visible edges are all that "visible" holds (its 9 edges: 3·(3 + 4 + 1) before projection).
  const hedra::Vec3 view(0.3, 0.4, -1);
  EXPECT_NEAR(picture_length(j["outline"], view), 3 * M_PI, 5e-3 * 3 * M_PI);
  for (const auto& e : j["visible"]) EXPECT_LT(e[0].get<double>(), -2.9);
  EXPECT_NE(read(d / "s.svg").find("class=\"outline\""), std::string::npos);
  EXPECT_EQ(read(d / "s.svg").find("class=\"smooth\""), std::string::npos);
  // --smooth adds the facet edges as their own class.
  r = run("hlr " + (d / "s.json").string() + " --smooth -o " + (d / "s.svg").string() + " --json " +
          (d / "s.hlr.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  j = nlohmann::json::parse(read(d / "s.hlr.json"));
  ASSERT_TRUE(j.contains("smooth"));
  EXPECT_GT(j["smooth"].size(), 100u);
  EXPECT_NE(read(d / "s.svg").find("class=\"smooth\""), std::string::npos);
  // A scene of boxes has no smooth parts: its report has no new key, its drawing no new class.
  r = run("hlr " + (d / "bar.json").string() + " -o " + (d / "b.svg").string() + " --json " +
          (d / "b.hlr.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  j = nlohmann::json::parse(read(d / "b.hlr.json"));
  EXPECT_FALSE(j.contains("outline"));
  EXPECT_EQ(j.size(), 4u);  // visible, hidden, junction, ms
  EXPECT_EQ(read(d / "b.svg").find(".outline"), std::string::npos);
  EXPECT_EQ(r.out.find("outline segments"), std::string::npos);
  fs::remove_all(d);
}

// An L block under a generic rotation, converted to binary (float32) STL: its rectangles come
// back as triangle pairs coplanar only within float rounding. Drawn from that file without
// --tolerance, seen by the correspondingly rotated camera, it has the aligned block's drawing:
// no diagonals (picture length within 1e-3).
TEST(HlrCli, RotatedFloat32StlDrawsLikeItsAlignedTwin) {
  const fs::path d = temp_dir("stl");
  const char* l = R"("prism": {"polygon": [[0,0],[4,0],[4,1],[1,1],[1,3],[0,3]], "z": [0, 2]})";
  write(d / "rotated.json", std::string(R"({"bodies": [{"name": "l", )") + l +
                                R"(, "transform": [{"rotate": {"axis": [1, 2, 3], "deg": 37}}]}]})");
  ASSERT_EQ(run("convert " + (d / "rotated.json").string() + " " + (d / "l.stl").string()).code, 0);
  const hedra::Transform rotation = hedra::Transform::rotation({1, 2, 3}, 37);
  const hedra::Vec3 view(-1, -1, -1), up(0, 0, 1);
  const hedra::Vec3 rview = rotation.apply_vector(view), rup = rotation.apply_vector(up);
  char camera[256];
  std::snprintf(camera, sizeof camera,
                R"("camera": {"projection": "parallel", "direction": [%.17g, %.17g, %.17g], "up": [%.17g, %.17g, %.17g]})",
                rview.x(), rview.y(), rview.z(), rup.x(), rup.y(), rup.z());
  write(d / "stl.json", std::string(R"({"bodies": [{"name": "l", "mesh": "l.stl"}], )") + camera + "}");
  write(d / "aligned.json", std::string(R"({"bodies": [{"name": "l", )") + l + R"(}],
    "camera": {"projection": "parallel", "direction": [-1, -1, -1], "up": [0, 0, 1]}})");
  ASSERT_EQ(run("hlr " + (d / "stl.json").string() + " --json " + (d / "r.json").string()).code, 0);
  ASSERT_EQ(run("hlr " + (d / "aligned.json").string() + " --json " + (d / "a.json").string()).code, 0);
  const nlohmann::json r = nlohmann::json::parse(read(d / "r.json"));
  const nlohmann::json a = nlohmann::json::parse(read(d / "a.json"));
  const double expected = picture_length(a["visible"], view);
  EXPECT_NEAR(picture_length(r["visible"], rview) + picture_length(r["outline"], rview), expected,
              1e-3 * expected);
  EXPECT_TRUE(r["outline"].empty());
  // With crease angle 0 every edge is drawn: the diagonals come back.
  ASSERT_EQ(run("hlr " + (d / "stl.json").string() + " --crease-angle 0 --json " + (d / "r0.json").string()).code, 0);
  EXPECT_GT(picture_length(nlohmann::json::parse(read(d / "r0.json"))["visible"], rview), 1.1 * expected);
  fs::remove_all(d);
}

}  // namespace
