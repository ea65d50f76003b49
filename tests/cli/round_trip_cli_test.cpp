// Round trips (issue 14, item 6): for every format hedra writes (OFF, OBJ, PLY, STL ASCII, STL
// binary float32, scene JSON), `convert` and then info, decompose, clip, hlr, shadows and render give
// the original's results within the rounding of the format. The original is a scene whose camera
// and light are those a mesh file gets (cli/info.h, load_scene), so that a mesh written from it
// is seen the same way; it holds a non-convex prism, a box rotated by a generic angle (rounded
// coordinates) and a cylinder (curved, rounded coordinates). The cylinder stands clear of the
// ground: a curved body standing on another, read from float32 STL with --tolerance, has its
// base vertices snapped off the contact plane by ulps (a junction line appears; docs/stability.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "hedra/io/png.h"
#include "testing/cli_run.h"
#include "testing/temp_files.h"

namespace {

namespace fs = std::filesystem;
using hedra::testing::run_hedra;

const char* kScene = R"({"version": 1, "bodies": [
  {"name": "ground", "box": {"min": [-3, -3, -1], "max": [8, 7, 0]}},
  {"name": "L", "prism": {"polygon": [[0,0],[4,0],[4,1],[1,1],[1,3],[0,3]], "z": [0, 2]}},
  {"name": "b", "box": {"min": [0, 0, 0], "max": [1.5, 1, 1]},
   "transform": [{"rotate": {"axis": [0.3, 0.5, 1], "deg": 31.7}}, {"translate": [4.5, 2.5, 0.3]}]},
  {"name": "c", "cylinder": {"radius": 0.6, "z": [0.05, 1.75], "tolerance": 0.02},
   "transform": [{"translate": [2.2, 4.2, 0]}]}],
 "camera": {"projection": "parallel", "direction": [-1, -2, -1.5], "up": [0, 0, 1]},
 "lights": [{"type": "directional", "direction": [-1, -1.5, -3], "intensity": 0.9}]})";

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The numbers a round trip must keep, from the commands' JSON reports and image.
struct Results {
  int bodies = 0, faces = 0, pieces = 0;
  double volume = 0, area = 0, pieces_volume = 0;
  double visible = 0, hidden = 0;           // hidden-line lengths (3D)
  double cast = 0, self = 0;                // shadow areas
  // Segments clipped against every body: parts and their total length, exact method and
  // midpoint method (the latter against the decomposition's exact pieces).
  int parts = 0, midpoint_parts = 0;
  double clipped = 0, midpoint_clipped = 0;
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
};

double length(const nlohmann::json& list) {
  double total = 0;
  for (const auto& s : list)
    total += std::hypot(s[3].get<double>() - s[0].get<double>(), s[4].get<double>() - s[1].get<double>(),
                        s[5].get<double>() - s[2].get<double>());
  return total;
}

Results results_of(const fs::path& file, const fs::path& dir, const std::string& options) {
  Results r;
  const std::string f = file.string() + " " + options;
  auto info = run_hedra("info --json " + f);
  EXPECT_EQ(info.code, 0) << file << ": " << info.err;
  if (info.code != 0) return r;
  const nlohmann::json info_json = nlohmann::json::parse(info.out);
  for (const auto& b : info_json["bodies"]) {
    ++r.bodies;
    r.faces += b["faces"].get<int>();
    r.volume += b["volume"].get<double>();
    r.area += b["area"].get<double>();
  }
  // decompose reports every body of a mesh file but only the non-convex bodies of a scene: the
  // non-convex ones (more than one piece) are compared.
  auto dec = run_hedra("decompose --json " + f);
  EXPECT_EQ(dec.code, 0) << file << ": " << dec.err;
  const nlohmann::json dj = nlohmann::json::parse(dec.out);
  const auto add_dec = [&](const nlohmann::json& j) {
    if (j["pieces"].get<int>() < 2) return;
    r.pieces += j["pieces"].get<int>();
    r.pieces_volume += j["pieces_volume"].get<double>();
  };
  if (dj.is_array()) {
    for (const auto& j : dj) add_dec(j);
  } else {
    add_dec(dj);
  }
  const fs::path hj = dir / "hlr.json", sj = dir / "shadows.json", png = dir / "r.png";
  auto hlr = run_hedra("hlr --hidden --json " + hj.string() + " " + f);
  EXPECT_EQ(hlr.code, 0) << file << ": " << hlr.err;
  const nlohmann::json h = nlohmann::json::parse(read(hj));
  r.visible = length(h["visible"]) + length(h["junction"]) + (h.contains("outline") ? length(h["outline"]) : 0);
  r.hidden = length(h["hidden"]);
  auto sh = run_hedra("shadows --json " + sj.string() + " " + f);
  EXPECT_EQ(sh.code, 0) << file << ": " << sh.err;
  const nlohmann::json parsed_face = nlohmann::json::parse(read(sj));
  for (const auto& face : parsed_face["lights"][0]["faces"])
    (face["self_shadowed"].get<bool>() ? r.self : r.cast) += face["shadow_area"].get<double>();
  // 60 seeded segments across the scene's box, through the L prism's pieces and the rotated box.
  const fs::path segments = dir / "segments.txt", parts = dir / "parts.txt";
  {
    std::ofstream out(segments);
    out.precision(17);
    unsigned state = 20261208;
    const auto next = [&](double lo, double hi) {
      state = state * 1664525u + 1013904223u;
      return lo + (hi - lo) * static_cast<double>(state >> 8) / static_cast<double>(1u << 24);
    };
    for (int k = 0; k < 60; ++k)
      out << next(-3, 8) << " " << next(-3, 7) << " " << next(-1, 2.5) << " " << next(-3, 8) << " "
          << next(-3, 7) << " " << next(-1, 2.5) << "\n";
  }
  for (const char* method : {"cyrus-beck", "midpoint"}) {
    auto cl = run_hedra("clip --method " + std::string(method) + " --body " + f + " --segments " + segments.string() +
                        " -o " + parts.string());
    EXPECT_EQ(cl.code, 0) << file << ": " << cl.err;
    std::ifstream in(parts);
    double x[7];
    const bool midpoint = std::string(method) == "midpoint";
    while (in >> x[0] >> x[1] >> x[2] >> x[3] >> x[4] >> x[5] >> x[6]) {
      ++(midpoint ? r.midpoint_parts : r.parts);
      (midpoint ? r.midpoint_clipped : r.clipped) += std::hypot(x[3] - x[0], x[4] - x[1], x[5] - x[2]);
    }
  }
  // Flat shading: a curved primitive's analytic normals are not part of any mesh format.
  auto rd = run_hedra("render --shading flat --width 240 --height 180 -o " + png.string() + " " + f);
  EXPECT_EQ(rd.code, 0) << file << ": " << rd.err;
  r.rgb = hedra::io::read_png(png.string(), &r.width, &r.height);
  return r;
}

// Fraction of pixels whose colour differs by more than 8 levels in a channel.
double pixels_differing(const Results& a, const Results& b) {
  if (a.rgb.size() != b.rgb.size() || a.rgb.empty()) return 1;
  size_t differ = 0;
  for (size_t i = 0; i < a.rgb.size(); i += 3)
    for (size_t k = 0; k < 3; ++k)
      if (std::abs(int(a.rgb[i + k]) - int(b.rgb[i + k])) > 8) {
        ++differ;
        break;
      }
  return static_cast<double>(differ) / static_cast<double>(a.rgb.size() / 3);
}

void expect_same(const Results& want, const Results& got, double rel, double pixels,
                 const std::string& what) {
  const auto near = [&](double a, double b, const char* name) {
    EXPECT_NEAR(b, a, rel * std::max(1.0, std::abs(a))) << what << ": " << name;
  };
  EXPECT_EQ(got.bodies, want.bodies) << what;
  EXPECT_EQ(got.faces, want.faces) << what;
  EXPECT_EQ(got.pieces, want.pieces) << what;
  near(want.volume, got.volume, "volume");
  near(want.area, got.area, "area");
  near(want.pieces_volume, got.pieces_volume, "pieces volume");
  near(want.visible, got.visible, "visible length");
  near(want.hidden, got.hidden, "hidden length");
  near(want.cast, got.cast, "cast shadow area");
  near(want.self, got.self, "self-shadowed area");
  EXPECT_EQ(got.parts, want.parts) << what;
  EXPECT_EQ(got.midpoint_parts, want.midpoint_parts) << what;
  near(want.clipped, got.clipped, "clipped length");
  // Midpoint subdivision ends each part within ε = 1e-9 of the body's size (about 15 here) of
  // the exact end, each decision on the pieces it was given: the scene's (a moved body's exact
  // image) and the file's (its plane solid) are one solid within rounding, so the ends agree
  // within 2ε, 60 segments' worth.
  EXPECT_NEAR(got.midpoint_clipped, want.midpoint_clipped, std::max(rel * want.midpoint_clipped, 60 * 2 * 2 * 15e-9))
      << what << ": midpoint clipped length";
  EXPECT_LE(pixels_differing(want, got), pixels) << what << ": rendered image";
}

class RoundTrip : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = hedra::testing::temp_dir("round_trip");
    scene_ = hedra::testing::write(dir_ / "scene.json", kScene);
    original_ = new Results(results_of(scene_, dir_, ""));
  }
  static void TearDownTestSuite() {
    delete original_;
    fs::remove_all(dir_);
  }
  // Converts the scene to `name` and checks every command's results against the original's.
  static void check(const std::string& name, const std::string& convert_options,
                    const std::string& read_options, double rel, double pixels) {
    const fs::path out = dir_ / name;
    const auto c = run_hedra("convert " + scene_ + " " + out.string() + " " + convert_options);
    ASSERT_EQ(c.code, 0) << c.err;
    expect_same(*original_, results_of(out, dir_, read_options), rel, pixels, name);
  }
  static inline fs::path dir_;
  static inline std::string scene_;
  static inline Results* original_ = nullptr;
};

TEST_F(RoundTrip, OriginalIsNonTrivial) {
  EXPECT_EQ(original_->bodies, 4);
  EXPECT_GT(original_->pieces, 1);  // the L prism is decomposed
  EXPECT_GT(original_->visible, 10);
  EXPECT_GT(original_->hidden, 1);
  EXPECT_GT(original_->cast, 1);
  EXPECT_GT(original_->parts, 30);
  EXPECT_EQ(original_->midpoint_parts, original_->parts);
  EXPECT_NEAR(original_->midpoint_clipped, original_->clipped, 60 * 2 * 15e-9);
}

// Exact formats that store polygons: coordinates as written by %.17g (or JSON's shortest round
// trip) read back as the same doubles, so every result is the same up to the order of summation.
TEST_F(RoundTrip, Off) { check("r.off", "", "", 1e-12, 0.001); }
TEST_F(RoundTrip, Obj) { check("r.obj", "", "", 1e-12, 0.001); }
TEST_F(RoundTrip, Ply) { check("r.ply", "", "", 1e-12, 0.001); }
TEST_F(RoundTrip, SceneJson) { check("r.json", "", "", 1e-12, 0.001); }

// ASCII STL keeps the doubles but stores triangles only: the rotated box's quads, planar only
// within the rounding of the rotation, come back as pairs of triangles that are not exactly
// coplanar (one more face each, and more convex pieces). A --tolerance far below any
// feature (1e-9) merges them back; results agree to 1e-8.
TEST_F(RoundTrip, StlAscii) { check("r.stl", "--stl-ascii", "--tolerance 1e-9", 1e-8, 0.001); }

// Binary STL stores float32: coordinates move by up to 2^-24 of their size (≤ 5e-7 here), so
// the rotated box's and cylinder's faces come back as triangles coplanar only within that; the
// reader's --tolerance (well above the rounding, far below the features) merges them back into
// the original faces. Results agree to the rounding: 1e-5 relative.
TEST_F(RoundTrip, StlBinaryFloat32) { check("r32.stl", "", "--tolerance 1e-5", 1e-5, 0.005); }

// What float32 cannot hold is not written: a plate 1e-5 thick at x = 1000 (float32's step there
// is 6.1e-5) would collapse to a flat mesh no command reads. `convert` to binary STL exits 3 with
// one line naming the file and writes nothing; to ASCII STL it writes the plate, which reads back.
TEST_F(RoundTrip, BodyFloat32CannotHoldIsNotWrittenToBinaryStl) {
  const std::string thin = hedra::testing::write(
      dir_ / "thin.json", R"({"bodies": [{"name": "thin", "box": {"min": [1000, 0, 0], "max": [1000.00001, 1, 1]}}]})");
  const fs::path out = dir_ / "thin.stl";
  const auto c = run_hedra("convert " + thin + " " + out.string());
  EXPECT_EQ(c.code, 3) << c.err;
  EXPECT_EQ(c.err.rfind("hedra: error: " + out.string() + ": rounded to float32 (binary STL), the bodies would not read back: ", 0), 0u) << c.err;
  EXPECT_EQ(std::count(c.err.begin(), c.err.end(), '\n'), 1) << c.err;
  EXPECT_FALSE(fs::exists(out));
  const auto a = run_hedra("convert " + thin + " " + out.string() + " --stl-ascii");
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_EQ(run_hedra("info " + out.string()).code, 0);
}

}  // namespace
