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
  // Drawing: the scan's boundary and its creases, hidden parts behind it.
  auto r = run_hedra("hlr " + scan + " --hidden -o " + (dir / "scan.svg").string() + " --json " +
                     (dir / "h.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json h = nlohmann::json::parse(read(dir / "h.json"));
  EXPECT_GT(h["visible"].size(), 100u);
  EXPECT_GT(h["hidden"].size(), 10u);  // the far side of the scan and the ground's back edges
  // Shadows: the scan shades the ground's top (the file's face 1, body scan.f1).
  r = run_hedra("shadows " + scan + " --json " + (dir / "s.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  double ground_top = 0, scan_self = 0, scan_cast = 0;
  const nlohmann::json parsed1 = nlohmann::json::parse(read(dir / "s.json"));
  for (const auto& face : parsed1["lights"][0]["faces"]) {
    const std::string body = face["body"];
    // The whole file is a surface: the ground's faces are two-sided too; its top's upper side
    // (face 0, the file's orientation) receives the scan's shadow, the lower side is dark.
    if (body == "scan.f1" && face["face"] == 0) ground_top += face["shadow_area"].get<double>();
    else if (body.rfind("scan.f", 0) == 0 && std::stoi(body.substr(6)) >= 6)
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

}  // namespace
