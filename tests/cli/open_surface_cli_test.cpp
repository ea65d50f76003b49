// Open surfaces through the command (docs/io.md, "Open surfaces"): a scan-like open mesh (a
// sphere with its lower cap removed, its boundary ragged) over a ground slab, in one OFF file,
// renders, draws and casts shadows; decompose refuses it naming the file and a boundary edge.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "hedra/io/png.h"
#include "testing/cli_run.h"
#include "testing/temp_files.h"

namespace {

namespace fs = std::filesystem;
using hedra::testing::run_hedra;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The ground box [-3, 3]² × [-1, 0] and the scan: a unit sphere centred at (0, 0, 1.6) with the
// rings below its equator removed, every other triangle of the last row left out.
std::string scan_off() {
  std::vector<std::array<double, 3>> v = {{-3, -3, -1}, {3, -3, -1}, {3, 3, -1}, {-3, 3, -1},
                                          {-3, -3, 0},  {3, -3, 0},  {3, 3, 0},  {-3, 3, 0}};
  std::vector<std::vector<int>> f = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                     {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  const int rings = 8, around = 16;
  const int top = static_cast<int>(v.size());
  v.push_back({0, 0, 2.6});
  for (int k = 1; k <= rings; ++k)
    for (int m = 0; m < around; ++m) {
      const double th = M_PI * k / 14, ph = 2 * M_PI * m / around;
      v.push_back({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), 1.6 + std::cos(th)});
    }
  const auto at = [&](int k, int m) { return top + 1 + (k - 1) * around + (m % around); };
  for (int m = 0; m < around; ++m) f.push_back({top, at(1, m), at(1, m + 1)});
  for (int k = 1; k < rings; ++k)
    for (int m = 0; m < around; ++m) {
      f.push_back({at(k, m), at(k + 1, m), at(k + 1, m + 1)});
      if (k + 1 < rings || m % 2 == 0) f.push_back({at(k, m), at(k + 1, m + 1), at(k, m + 1)});
    }
  std::ostringstream out;
  out.precision(17);
  out << "OFF\n" << v.size() << " " << f.size() << " 0\n";
  for (const auto& p : v) out << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (const auto& face : f) {
    out << face.size();
    for (int i : face) out << " " << i;
    out << "\n";
  }
  return out.str();
}

TEST(OpenSurfaceCli, ScanRendersDrawsAndCastsShadows) {
  const fs::path dir = hedra::testing::temp_dir("open_surface_cli");
  const std::string scan = hedra::testing::write(dir / "scan.off", scan_off());
  // Drawing: the scan's boundary (its ragged last row), the ground's edges and the cap's
  // outline, hidden parts behind them; the edges between the cap's faces (they turn by 13° and
  // 22.5°) are smooth. With crease angle 0, every facet edge and no outline.
  auto r = run_hedra("hlr " + scan + " --hidden -o " + (dir / "scan.svg").string() + " --json " +
                     (dir / "h.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json h = nlohmann::json::parse(read(dir / "h.json"));
  EXPECT_GT(h["visible"].size(), 20u);
  EXPECT_LT(h["visible"].size(), 60u);
  EXPECT_GT(h["outline"].size(), 10u);
  EXPECT_GT(h["hidden"].size(), 10u);  // the far side of the scan and the ground's back edges
  r = run_hedra("hlr " + scan + " --crease-angle 0 --json " + (dir / "h.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json all = nlohmann::json::parse(read(dir / "h.json"));
  EXPECT_GT(all["visible"].size(), 200u);
  EXPECT_FALSE(all.contains("outline"));
  // Shadows: the scan shades the ground's top (the file's face 1: face 1 of the one two-sided
  // body "scan", whose faces F … 2F − 1 are the other sides of faces 0 … F − 1).
  r = run_hedra("shadows " + scan + " --json " + (dir / "s.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  double ground_top = 0, scan_self = 0, scan_cast = 0;
  const nlohmann::json parsed1 = nlohmann::json::parse(read(dir / "s.json"));
  int sides = 0;
  for (const auto& face : parsed1["lights"][0]["faces"]) {
    EXPECT_EQ(face["body"], "scan");
    ++sides;
  }
  sides /= 2;
  ASSERT_GT(sides, 6);
  for (const auto& face : parsed1["lights"][0]["faces"]) {
    const int f = face["face"];
    // The whole file is a surface: the ground's faces are two-sided too; its top's upper side
    // (face 1, the file's orientation) receives the scan's shadow, the lower side is dark.
    if (f == 1) ground_top += face["shadow_area"].get<double>();
    else if (f % sides >= 6)
      (face["self_shadowed"].get<bool>() ? scan_self : scan_cast) += face["shadow_area"].get<double>();
  }
  // The light (−1, −1.5, −3) throws the ring of radius ≤ 1 onto the ground: its shadow is
  // larger than the cap's own disk (π · sin²(8π/14)) and smaller than a disk of radius 2.
  EXPECT_GT(ground_top, M_PI * std::pow(std::sin(8 * M_PI / 14), 2));
  EXPECT_LT(ground_top, 4 * M_PI);
  EXPECT_GT(scan_self, 1);   // faces turned from the light
  EXPECT_GT(scan_cast, 0);   // inside of the cup, shaded by its far wall
  // Rendering: the scan covers the middle of the picture.
  r = run_hedra("render --width 160 --height 120 " + scan + " -o " + (dir / "scan.png").string());
  ASSERT_EQ(r.code, 0) << r.err;
  int w = 0, hgt = 0;
  const std::vector<uint8_t> rgb = hedra::io::read_png((dir / "scan.png").string(), &w, &hgt);
  int background = 0;
  for (size_t i = 0; i < rgb.size(); i += 3) background += rgb[i] == 255 && rgb[i + 1] == 255 && rgb[i + 2] == 255;
  EXPECT_LT(background, w * hgt);
  // Solids only: decompose refuses it, naming the file and a boundary edge.
  r = run_hedra("decompose " + scan);
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("scan.off"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("boundary edge"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

// A height-field terrain over [-3, 3]², 12 × 12 cells of two triangles, at z = 10 + h: flat
// (h = 0) where |x|, |y| ≤ 1.5, gentle hills elsewhere (h ≤ 0.05, slopes ≤ 0.1: no terrain face
// shades another under a light steeper than that).
std::string terrain_off() {
  const int n = 12;
  std::ostringstream out;
  out.precision(17);
  out << "OFF\n" << (n + 1) * (n + 1) << " " << 2 * n * n << " 0\n";
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -3 + 0.5 * i, y = -3 + 0.5 * j;
      const bool flat = std::abs(x) <= 1.5 && std::abs(y) <= 1.5;
      out << x << " " << y << " " << 10 + (flat ? 0 : 0.05 * ((i * 7 + j * 3) % 5) / 4) << "\n";
    }
  const auto at = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      out << "3 " << at(i, j) << " " << at(i + 1, j) << " " << at(i + 1, j + 1) << "\n";
      out << "3 " << at(i, j) << " " << at(i + 1, j + 1) << " " << at(i, j + 1) << "\n";
    }
  return out.str();
}

// A scene combining an open terrain (a "mesh" moved down by 10), an open inline polyhedron (a
// square panel at z = 3 whose shadow falls off the terrain), a box and a light.
std::string terrain_scene(const std::string& camera) {
  return R"({"version": 1, "bodies": [
 {"name": "terrain", "mesh": "terrain.off", "transform": [{"translate": [0, 0, -10]}],
  "material": {"color": [0.3, 0.7, 0.3]}},
 {"name": "panel", "polyhedron": {"vertices": [[2.5, 2.5, 3], [2.9, 2.5, 3], [2.9, 2.9, 3], [2.5, 2.9, 3]],
  "faces": [[0, 1, 2, 3]]}},
 {"name": "box", "box": {"min": [-0.5, -0.5, 0.5], "max": [0.5, 0.5, 1.5]}, "material": {"color": [0.8, 0.2, 0.2]}}],
 "camera": )" + camera + R"(,
 "lights": [{"type": "directional", "direction": [0.3, 0.2, -1]}],
 "image": {"width": 200, "height": 150}}
)";
}

double length(const nlohmann::json& s) {
  return std::hypot(s[3].get<double>() - s[0].get<double>(), s[4].get<double>() - s[1].get<double>(),
                    s[5].get<double>() - s[2].get<double>());
}

TEST(OpenSurfaceCli, SceneFileCombinesAnOpenTerrainWithASolidAndALight) {
  const fs::path dir = hedra::testing::temp_dir("open_scene_cli");
  hedra::testing::write(dir / "terrain.off", terrain_off());
  const std::string scene = hedra::testing::write(
      dir / "scene.json", terrain_scene(R"({"projection": "parallel", "direction": [0, 0, -1], "up": [0, 1, 0]})"));
  // info: the box is a solid; the terrain and the panel are open surfaces (boundary edge counts:
  // the grid's 4 × 12 edges, the panel's 4).
  auto r = run_hedra("info --json " + scene);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json info = nlohmann::json::parse(r.out)["bodies"];
  ASSERT_EQ(info.size(), 3u) << r.out;
  EXPECT_EQ(info[0]["name"], "box");
  EXPECT_EQ(info[0]["closed"], true);
  EXPECT_EQ(info[1]["name"], "terrain");
  EXPECT_EQ(info[1]["closed"], false);
  EXPECT_EQ(info[1]["faces"], 288);
  EXPECT_EQ(info[1]["boundary_edges"], 48);
  EXPECT_EQ(info[2]["name"], "panel");
  EXPECT_EQ(info[2]["boundary_edges"], 4);
  EXPECT_NEAR(info[2]["area"].get<double>(), 0.16, 1e-12);
  r = run_hedra("info " + scene);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("open surface"), std::string::npos) << r.out;
  // Solid commands refuse it: the scene file, the body and the first boundary edge.
  const std::string segments = hedra::testing::write(dir / "segments.txt", "0 0 -5 0 0 5\n");
  for (const std::string& command :
       {"decompose " + scene, "clip --body " + scene + " --segments " + segments + " -o " + (dir / "p.txt").string(),
        "convert " + scene + " " + (dir / "out.off").string()}) {
    r = run_hedra(command);
    EXPECT_EQ(r.code, 3) << command;
    EXPECT_NE(r.err.find(scene + ":2:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("body 'terrain'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("boundary edges, first between vertices 0 (-3, -3, 10) and 1 (-2.5, -3, 10)"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir / "p.txt") || fs::exists(dir / "out.off"));
  }
  // Hidden lines seen from straight above: the terrain's border (24 long) and the box's top
  // (4) are seen whole; no terrain edge under the box is seen.
  r = run_hedra("hlr " + scene + " -o " + (dir / "h.svg").string() + " --json " + (dir / "h.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json h = nlohmann::json::parse(read(dir / "h.json"));
  double border = 0, top = 0;
  for (const auto& s : h["visible"]) {
    const double mx = (s[0].get<double>() + s[3].get<double>()) / 2, my = (s[1].get<double>() + s[4].get<double>()) / 2;
    const double mz = (s[2].get<double>() + s[5].get<double>()) / 2;
    if (std::max(std::abs(mx), std::abs(my)) == 3)  // its drawn (x, y) length
      border += std::hypot(s[3].get<double>() - s[0].get<double>(), s[4].get<double>() - s[1].get<double>());
    if (mz == 1.5) top += length(s);
    if (mz < 1) {
      EXPECT_FALSE(std::abs(mx) < 0.5 && std::abs(my) < 0.5) << s;
    }
  }
  EXPECT_NEAR(border, 24, 1e-12);
  EXPECT_NEAR(top, 4, 1e-12);
  // Shadows: the box's shadow on the terrain's upper side (its faces 0 … F − 1) along the light
  // (0.3, 0.2, −1) on the flat part: the unit square swept by the shift of the box's height
  // 1, area 1 + 0.3 + 0.2 (the panel's shadow falls beyond the terrain).
  r = run_hedra("shadows " + scene + " --json " + (dir / "s.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  double on_terrain = 0;
  const nlohmann::json shadows = nlohmann::json::parse(read(dir / "s.json"));
  int sides = 0;
  for (const auto& face : shadows["lights"][0]["faces"]) sides += face["body"] == "terrain";
  sides /= 2;
  EXPECT_GT(sides, 100);
  for (const auto& face : shadows["lights"][0]["faces"]) {
    if (face["body"] == "terrain" && face["face"].get<int>() < sides) {
      EXPECT_FALSE(face["self_shadowed"].get<bool>()) << face["face"];
      on_terrain += face["shadow_area"].get<double>();
    }
  }
  EXPECT_NEAR(on_terrain, 1.5, 1e-9);
  // Rendering: the terrain's green and the box's red are both on the picture.
  r = run_hedra("render " + scene + " -o " + (dir / "r.png").string());
  ASSERT_EQ(r.code, 0) << r.err;
  int w = 0, hgt = 0;
  const std::vector<uint8_t> rgb = hedra::io::read_png((dir / "r.png").string(), &w, &hgt);
  EXPECT_EQ(w, 200);
  EXPECT_EQ(hgt, 150);
  int green = 0, red = 0;
  for (size_t i = 0; i + 2 < rgb.size(); i += 3) {
    green += rgb[i + 1] > rgb[i] + 40 && rgb[i + 1] > rgb[i + 2] + 40;
    red += rgb[i] > rgb[i + 1] + 40 && rgb[i] > rgb[i + 2] + 40;
  }
  EXPECT_GT(green, w * hgt / 4);
  EXPECT_GT(red, 100);
  fs::remove_all(dir);
}

// Bug: a camera standing on the terrain (a perspective eye over it, the terrain reaching behind
// it) failed in hlr, render --lines and shadows --svg with "a body needs at least 4 vertices".
// Now each command draws; no drawn point lies behind the eye (its depth along the view is
// positive), and the box in front of the eye is drawn.
TEST(OpenSurfaceCli, CameraStandingOnTheTerrainDrawsEveryCommand) {
  const fs::path dir = hedra::testing::temp_dir("open_surface_eye_cli");
  hedra::testing::write(dir / "terrain.off", terrain_off());
  const std::string scene = hedra::testing::write(
      dir / "scene.json",
      terrain_scene(R"({"projection": "perspective", "eye": [0, -2.5, 0.4], "target": [0, 3, 0.3], "fov_deg": 70})"));
  auto r = run_hedra("hlr " + scene + " -o " + (dir / "h.svg").string() + " --json " + (dir / "h.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json h = nlohmann::json::parse(read(dir / "h.json"));
  const double eye[3] = {0, -2.5, 0.4}, view[3] = {0, 5.5, -0.1};
  int box = 0;
  for (const auto& s : h["visible"]) {
    for (int k = 0; k < 2; ++k) {
      double depth = 0;
      for (int c = 0; c < 3; ++c) depth += (s[3 * k + c].get<double>() - eye[c]) * view[c];
      EXPECT_GT(depth, 0) << s;
    }
    box += s[2].get<double>() >= 0.5 && s[5].get<double>() >= 0.5;
  }
  EXPECT_GT(box, 4);
  r = run_hedra("shadows " + scene + " --svg " + (dir / "s.svg").string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_hedra("render " + scene + " --lines -o " + (dir / "r.png").string());
  ASSERT_EQ(r.code, 0) << r.err;
  fs::remove_all(dir);
}

// `--tolerance D` on an open surface: a grid of 10 × 10 cells of two triangles over [0, 5]² on
// the plane z = 0.3x + 0.2y, its vertices moved by up to 1e-9 along z.
std::string noisy_grid_off() {
  const int n = 10;
  std::ostringstream out;
  out.precision(17);
  out << "OFF\n" << (n + 1) * (n + 1) << " " << 2 * n * n << " 0\n";
  unsigned state = 7;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      state = state * 1103515245u + 12345u;
      const double r = static_cast<double>((state >> 8) % 2001) / 1000 - 1;
      const double x = 0.5 * i, y = 0.5 * j;
      out << x << " " << y << " " << 0.3 * x + 0.2 * y + 1e-9 * r << "\n";
    }
  const auto at = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      out << "3 " << at(i, j) << " " << at(i + 1, j) << " " << at(i + 1, j + 1) << "\n";
      out << "3 " << at(i, j) << " " << at(i + 1, j + 1) << " " << at(i, j + 1) << "\n";
    }
  return out.str();
}

TEST(OpenSurfaceCli, ToleranceMergesNearlyCoplanarFacesOfAnOpenSurface) {
  const fs::path dir = hedra::testing::temp_dir("open_tolerance_cli");
  const std::string grid = hedra::testing::write(dir / "grid.off", noisy_grid_off());
  const std::string json = (dir / "h.json").string();
  // Drawn from above: exact, the noisy triangles stay apart and the edges between them are
  // smooth (they turn by far less than 30°): the border alone is drawn, in 40 segments, of
  // length 2 · 5 · (√1.09 + √1.04); with crease angle 0 every edge between them is drawn.
  // Within D = 1e-6, one face whose 4 edges are the border.
  auto r = run_hedra("hlr " + grid + " --json " + json);
  ASSERT_EQ(r.code, 0) << r.err;
  {
    const nlohmann::json h = nlohmann::json::parse(read(json));
    EXPECT_EQ(h["visible"].size(), 40u);
    double drawn = 0;
    for (const auto& s : h["visible"]) drawn += length(s);
    EXPECT_NEAR(drawn, 10 * (std::sqrt(1.09) + std::sqrt(1.04)), 1e-5);
  }
  r = run_hedra("hlr " + grid + " --crease-angle 0 --json " + json);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(nlohmann::json::parse(read(json))["visible"].size(), 200u);
  r = run_hedra("hlr " + grid + " --tolerance 1e-6 --json " + json);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json h = nlohmann::json::parse(read(json));
  EXPECT_EQ(h["visible"].size(), 4u);
  double drawn = 0;
  for (const auto& s : h["visible"]) drawn += length(s);
  EXPECT_NEAR(drawn, 10 * (std::sqrt(1.09) + std::sqrt(1.04)), 1e-5);
  // The same through a scene file: its "tolerance", and the command's.
  const std::string light = R"(, "lights": [{"type": "directional", "direction": [0, 0, -1]}]})";
  const std::string scene = hedra::testing::write(
      dir / "s.json", R"({"version": 1, "tolerance": 1e-6, "bodies": [{"name": "g", "mesh": "grid.off"}])" + light);
  const std::string exact = hedra::testing::write(
      dir / "e.json", R"({"version": 1, "bodies": [{"name": "g", "mesh": "grid.off"}])" + light);
  for (const std::string& command : {"shadows " + scene, "shadows --tolerance 1e-6 " + exact, "shadows " + exact}) {
    r = run_hedra(command + " --json " + json);
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json shadows = nlohmann::json::parse(read(json));
    const size_t faces = shadows["lights"][0]["faces"].size();  // two sides per face
    if (command == "shadows " + exact) {
      EXPECT_GT(faces, 300u) << command;
    } else {
      EXPECT_EQ(faces, 2u) << command;
    }
  }
  fs::remove_all(dir);
}

}  // namespace

namespace {

// An inline open polyhedron whose one face has a hole (a 4 × 4 panel at z = 2 with a 2 × 2
// window), and an L-shaped panel beside it: both are open surfaces, cut into convex two-sided
// faces. Bug: the face with a hole was refused ("a body needs at least 4 faces"), and the
// L panel was drawn with the diagonal between its two convex parts.
TEST(OpenSurfaceCli, FaceWithAHoleAndNonConvexFaceDrawWithoutInnerEdges) {
  const fs::path dir = hedra::testing::temp_dir("open_hole_cli");
  const std::string scene = hedra::testing::write(dir / "scene.json", R"({"version": 1, "bodies": [
    {"name": "ground", "box": {"min": [-5, -5, -1], "max": [10, 5, 0]}},
    {"name": "window", "polyhedron": {"vertices": [[-2,-2,2],[2,-2,2],[2,2,2],[-2,2,2],[-1,-1,2],[-1,1,2],[1,1,2],[1,-1,2]],
      "faces": [[[0,1,2,3],[4,5,6,7]]]}},
    {"name": "ell", "polyhedron": {"vertices": [[4,0,1],[8,0,1],[8,1,1],[5,1,1],[5,3,1],[4,3,1]], "faces": [[0,1,2,3,4,5]]}}],
    "camera": {"projection": "parallel", "direction": [0, 0, -1], "up": [0, 1, 0]},
    "lights": [{"type": "point", "position": [0, 0, 8]}]})");
  // Seen from above: the window's two squares (16 + 8) and the L's outline (14); nothing of
  // the cuts between their convex parts.
  auto r = run_hedra("hlr " + scene + " --json " + (dir / "h.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json h = nlohmann::json::parse(read(dir / "h.json"));
  double window = 0, ell = 0;
  for (const auto& s : h["visible"]) {
    const double mz = (s[2].get<double>() + s[5].get<double>()) / 2;
    if (mz == 2) window += length(s);
    if (mz == 1) ell += length(s);
  }
  EXPECT_NEAR(window, 24, 1e-12);
  EXPECT_NEAR(ell, 14, 1e-12);
  // The window's shadow on the ground from the light 6 above it: the frame's area 12 scaled
  // by (8 / 6)²; the L's, 1 below the light's 8, by (8 / 7)² (area 4 + 2 = 6).
  r = run_hedra("shadows " + scene + " --json " + (dir / "s.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json shadows = nlohmann::json::parse(read(dir / "s.json"));
  double on_ground = 0;
  for (const auto& face : shadows["lights"][0]["faces"])
    if (face["body"] == "ground" && !face["self_shadowed"].get<bool>()) on_ground += face["shadow_area"].get<double>();
  EXPECT_NEAR(on_ground, 12 * 16.0 / 9 + 6 * 64.0 / 49, 1e-9);
}

}  // namespace
