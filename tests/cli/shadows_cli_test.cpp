// `hedra shadows` and the demo's shadows end to end: JSON fields, SVG, sun studies, errors and
// exit codes.
#include <gtest/gtest.h>

#include "testing/cli_run.h"
#include "testing/temp_files.h"
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using Result = hedra::testing::CliResult;

fs::path temp(const std::string& name) {
  static const fs::path dir = hedra::testing::temp_dir("shadows_cli");
  return dir / name;
}

Result run(const std::string& args, const fs::path& cwd = fs::path()) { return hedra::testing::run_hedra(args, cwd); }

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = temp(name);
  std::ofstream(p) << text;
  return p.string();
}

json read_json(const std::string& path) {
  std::ifstream f(path);
  return json::parse(f);
}

const char* kBoxScene = R"({
  "version": 1,
  "bodies": [
    {"name": "ground", "box": {"min": [-10, -10, -1], "max": [10, 10, 0]}},
    {"name": "box", "box": {"min": [0, 0, 0], "max": [1, 1, 1]}}
  ],
  "camera": {"projection": "perspective", "eye": [-6, -9, 7], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 40},
  "lights": [{"type": "directional", "direction": [-1, -2, -4]},
             {"type": "sun", "latitude": 52.52, "longitude": 13.40, "time": "2026-06-21T10:00:00Z"}]
})";

TEST(ShadowsCli, ReportsFacesPolygonsAndCounts) {
  const std::string scene = write("box.json", kBoxScene);
  const std::string out = temp("box-report.json").string();
  const Result r = run("shadows " + scene + " --json " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("light 1, directional"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("umbra"), std::string::npos) << r.out;
  const json j = read_json(out);
  ASSERT_TRUE(j["ms"].is_number());
  EXPECT_GE(j["ms"].get<double>(), 0);
  ASSERT_EQ(j["lights"].size(), 2u);
  EXPECT_EQ(j["lights"][0]["light"]["type"], "directional");
  EXPECT_EQ(j["lights"][1]["light"]["type"], "sun");
  EXPECT_GT(j["lights"][1]["light"]["elevation_deg"].get<double>(), 0);
  const json& faces = j["lights"][0]["faces"];
  ASSERT_EQ(faces.size(), 12u);  // two boxes
  int self = 0;
  for (const json& f : faces) {
    for (const char* key :
         {"body", "face", "area", "self_shadowed", "visible", "shadow_area", "polygons"})
      EXPECT_TRUE(f.contains(key)) << key;
    if (f["self_shadowed"].get<bool>()) {
      ++self;
      EXPECT_EQ(f["shadow_area"].get<double>(), f["area"].get<double>());
      EXPECT_EQ(f["polygons"].size(), 1u);
    }
    for (const json& ring : f["polygons"])
      for (const json& p : ring) ASSERT_EQ(p.size(), 3u);
  }
  EXPECT_EQ(self, 6);  // three faces of each box turn their backs to (−1, −2, −4)
  // The ground's top (face 5): the known hexagon of area 1.75.
  const json& top = faces[5];
  EXPECT_EQ(top["body"], "ground");
  EXPECT_NEAR(top["shadow_area"].get<double>(), 1.75, 1e-14);
  ASSERT_EQ(top["polygons"].size(), 1u);
  EXPECT_EQ(top["polygons"][0].size(), 6u);
  // Two lights: regions with counts, the footprint among the umbra.
  ASSERT_TRUE(j["counts"].is_array());
  double umbra = 0;
  for (const json& c : j["counts"])
    if (c["body"] == "ground" && c["face"] == 5 && c["count"] == 2) umbra = c["area"].get<double>();
  EXPECT_GT(umbra, 1 - 1e-12);
}

const char* kCubeOff = "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                       "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

// A mesh file gets a directional light travelling along (−1, −1.5, −3): a lone unit cube has
// its −x, −y and −z faces in self-shadow and casts nothing on itself.
TEST(ShadowsCli, AcceptsAMeshFile) {
  const std::string off = write("cube.off", kCubeOff);
  const std::string out = temp("cube.json").string();
  const Result r = run("shadows " + off + " --json " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = read_json(out);
  ASSERT_EQ(j["lights"].size(), 1u);
  int self = 0;
  double shadow = 0;
  for (const json& f : j["lights"][0]["faces"]) {
    self += f["self_shadowed"].get<bool>();
    shadow += f["shadow_area"].get<double>();
  }
  EXPECT_EQ(self, 3);
  EXPECT_DOUBLE_EQ(shadow, 3.0);
}

// A plate with a square hole above the ground, light straight down: the ground's shadow is one
// polygon with one hole, and the JSON says which ring is the hole.
TEST(ShadowsCli, PolygonsWithHolesNameTheirHoleRings) {
  const std::string scene = write("holed.json", R"({
    "bodies": [
      {"name": "ground", "box": {"min": [-5, -5, -1], "max": [5, 5, 0]}},
      {"name": "plate", "prism": {"polygon": [[-2,-2],[2,-2],[2,2],[-2,2]],
                                  "holes": [[[-1,-1],[1,-1],[1,1],[-1,1]]], "z": [1, 1.5]}}
    ],
    "lights": [{"type": "directional", "direction": [0, 0, -1]}]
  })");
  const std::string out = temp("holed_out.json").string();
  const Result r = run("shadows " + scene + " --json " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = read_json(out);
  bool found = false;
  for (const json& f : j["lights"][0]["faces"]) {
    if (f["body"] != "ground" || f["self_shadowed"].get<bool>() || f["grazing"].get<bool>()) continue;
    if (f["shadow_area"].get<double>() == 0) continue;
    found = true;
    EXPECT_NEAR(f["shadow_area"].get<double>(), 12.0, 1e-12);
    ASSERT_EQ(f["polygons"].size(), 2u);
    EXPECT_EQ(f["holes"], json::array({1}));
    EXPECT_EQ(f["polygons"][1].size(), 4u);
  }
  EXPECT_TRUE(found);
}

TEST(ShadowsCli, WritesTheSvgOverlay) {
  const std::string scene = write("box2.json", kBoxScene);
  const std::string svg = temp("box.svg").string();
  const Result r = run("shadows " + scene + " --svg " + svg);
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream f(svg);
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("id=\"shadows\""), std::string::npos);
  EXPECT_NE(text.find("fill-opacity"), std::string::npos);
  EXPECT_LT(text.find("id=\"shadows\""), text.find("<g", text.find("id=\"shadows\"") + 1));
}

TEST(ShadowsCli, SunStudy) {
  const std::string scene = write("box3.json", kBoxScene);
  const std::string out = temp("study.json").string();
  const Result r =
      run("shadows " + scene + " --sun-hours 02:00 20:00 60 --grid ground 5 2 --json " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("sun study: 19 steps"), std::string::npos) << r.out;
  const json j = read_json(out);
  const json& st = j["sun_study"];
  ASSERT_EQ(st["steps"].size(), 19u);
  EXPECT_EQ(st["steps"][0]["time"].get<std::string>().substr(0, 16), "2026-06-21T02:00");
  EXPECT_EQ(st["faces"].size(), 12u);
  EXPECT_EQ(st["grid"]["points"].size(), 100u);
  // The box's roof sees the sun whenever it is up.
  double roof = -1;
  for (const json& f : st["faces"])
    if (f["body"] == "box" && f["face"] == 5) roof = f["sun_hours"].get<double>();
  EXPECT_GT(roof, 15);
  EXPECT_LT(roof, 18);
}

TEST(ShadowsCli, ErrorsAndExitCodes) {
  EXPECT_EQ(run("shadows").code, 2);
  const std::string scene = write("box4.json", kBoxScene);
  EXPECT_EQ(run("shadows " + scene + " --sun-hours 02:00 20:00 often").code, 2);
  EXPECT_EQ(run("shadows " + scene + " --sun-hours 02:00 20:00").code, 2);
  EXPECT_EQ(run("shadows " + scene + " --threads -1").code, 2);
  Result r = run("shadows " + temp("missing.json").string());
  EXPECT_EQ(r.code, 3);
  r = run("shadows " + write("dark.json", R"({"version": 1,
    "bodies": [{"name": "b", "box": {"min": [0, 0, 0], "max": [1, 1, 1]}}]})"));
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("no lights"), std::string::npos) << r.err;
  r = run("shadows " + write("night.json", R"({"version": 1,
    "bodies": [{"name": "b", "box": {"min": [0, 0, 0], "max": [1, 1, 1]}}],
    "lights": [{"type": "sun", "latitude": 52.52, "longitude": 13.40, "time": "2026-06-21T22:00:00Z"}]})"));
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("below the horizon"), std::string::npos) << r.err;
  r = run("shadows " + write("nosun.json", R"({"version": 1,
    "bodies": [{"name": "b", "box": {"min": [0, 0, 0], "max": [1, 1, 1]}}],
    "lights": [{"type": "point", "position": [0, 0, 5]}]})") +
          " --sun-hours 04:00 05:00 30");
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("needs a sun light"), std::string::npos) << r.err;
  r = run("shadows " + scene + " --sun-hours 04:00 05:00 30 --grid nobody 0 1");
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("nobody"), std::string::npos) << r.err;
  // A failed run leaves no output file.
  const std::string out = temp("never.json").string();
  EXPECT_EQ(run("shadows " + scene + " --sun-hours 20:00 04:00 30 --json " + out).code, 3);
  EXPECT_FALSE(fs::exists(out));
}

TEST(ShadowsCli, CityBlockExample) {
  const std::string out = temp("city.json").string();
  const Result r =
      run("shadows " + std::string(HEDRA_SOURCE_DIR) + "/examples/city-block.json --json " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = read_json(out);
  EXPECT_EQ(j["lights"].size(), 4u);
  double ground = 0;
  for (const json& f : j["lights"][0]["faces"])
    if (f["body"] == "ground" && f["face"] == 5) ground = f["shadow_area"].get<double>();
  EXPECT_GT(ground, 1);
}

TEST(ShadowsCli, DemoWritesShadows) {
  const fs::path dir = temp("demo");
  fs::create_directories(dir);
  const Result r = run("demo", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("shadowed area of the ground"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir / "demo-shadows.svg"));
}

}  // namespace
