// `hedra render` end to end: images written, exit codes and one-line errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "testing/cli_run.h"
#include "testing/temp_files.h"
#include "hedra/io/png.h"

namespace {

namespace fs = std::filesystem;

using Result = hedra::testing::CliResult;

Result run(const std::string& args) { return hedra::testing::run_hedra(args); }

fs::path temp_dir() {
  static const fs::path d = hedra::testing::temp_dir("render_cli");
  return d;
}

const std::string kExample = std::string(HEDRA_SOURCE_DIR) + "/examples/city-block.json";

TEST(RenderCli, WritesAPngOfTheExampleWithEveryMethod) {
  const fs::path dir = temp_dir();
  for (const char* method : {"exact", "map:512:2", "rays:2", "none"}) {
    const fs::path out = dir / (std::string("city-") + std::to_string(method[0]) + ".png");
    const Result r = run("render " + kExample + " -o " + out.string() + " --width 96 --height 72 --shadows " +
                         method + " --shading gouraud --aa 4");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("wrote"), std::string::npos);
    int w = 0, h = 0;
    const std::vector<uint8_t> rgb = hedra::io::read_png(out.string(), &w, &h);
    EXPECT_EQ(w, 96);
    EXPECT_EQ(h, 72);
  }
  fs::remove_all(dir);
}

TEST(RenderCli, BadOptionsAreUsageErrors) {
  const fs::path dir = temp_dir();
  const std::string out = (dir / "x.png").string();
  for (const std::string bad : {"--shadows map:5", "--shadows fuzzy", "--shading toon", "--aa 3",
                                "--attenuation linear:-1", "--width 0"}) {
    const Result r = run("render " + kExample + " -o " + out + " " + bad);
    EXPECT_EQ(r.code, 2) << bad << ": " << r.err;
  }
  EXPECT_EQ(run("render " + kExample + " -o " + (dir / "x.jpg").string()).code, 2);
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(dir);
}

TEST(RenderCli, BadSceneNamesFileAndPlace) {
  const fs::path dir = temp_dir();
  const fs::path scene = dir / "bad.json";
  std::ofstream(scene) << "{\"bodies\": [\n  {\"name\": \"a\", \"box\": {\"min\": [0,0,0], \"max\": [1,1]}}]}\n";
  const Result r = run("render " + scene.string() + " -o " + (dir / "y.png").string());
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("bad.json:2:"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "y.png"));
  fs::remove_all(dir);
}

// --lines draws the Roberts visible lines on top: the picture gains dark line pixels and
// changes nowhere else by more than the lines' width.
TEST(RenderCli, LinesOverlayDrawsTheVisibleEdges) {
  const fs::path dir = temp_dir();
  const fs::path plain = dir / "plain.png", lines = dir / "lines.png";
  const std::string common = " --width 160 --height 120 --shadows none --aa 1";
  ASSERT_EQ(run("render " + kExample + " -o " + plain.string() + common).code, 0);
  const Result r = run("render " + kExample + " -o " + lines.string() + common + " --lines");
  ASSERT_EQ(r.code, 0) << r.err;
  int w0 = 0, h0 = 0, w1 = 0, h1 = 0;
  const std::vector<uint8_t> a = hedra::io::read_png(plain.string(), &w0, &h0);
  const std::vector<uint8_t> b = hedra::io::read_png(lines.string(), &w1, &h1);
  ASSERT_EQ(w0, w1);
  ASSERT_EQ(h0, h1);
  auto dark = [](const std::vector<uint8_t>& img) {
    size_t n = 0;
    for (size_t i = 0; i + 2 < img.size(); i += 3) n += img[i] < 40 && img[i + 1] < 40 && img[i + 2] < 40;
    return n;
  };
  size_t changed = 0;
  for (size_t i = 0; i + 2 < a.size(); i += 3) changed += a[i] != b[i] || a[i + 1] != b[i + 1] || a[i + 2] != b[i + 2];
  EXPECT_GT(dark(b), dark(a) + 200) << "the overlay adds dark line pixels";
  EXPECT_GT(changed, 200u);
  EXPECT_LT(changed, a.size() / 3 / 3) << "only the lines change, not the shading";
  fs::remove_all(dir);
}

TEST(RenderCli, DemoWritesDemoRender) {
  const fs::path dir = temp_dir();
  const std::string command = "cd " + dir.string() + " && " + HEDRA_BIN + " demo > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0);
  int w = 0, h = 0;
  hedra::io::read_png((dir / "demo-render.png").string(), &w, &h);
  EXPECT_EQ(w, 1024);
  EXPECT_EQ(h, 768);
  fs::remove_all(dir);
}

}  // namespace
