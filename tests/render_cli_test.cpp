// `hedra render` end to end: images written, exit codes and one-line errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "io/png.h"

namespace {

namespace fs = std::filesystem;

struct Result {
  int code;
  std::string out, err;
};

Result run(const std::string& args) {
  static int calls = 0;
  const fs::path err_file = fs::temp_directory_path() /
                            ("hedra_render_stderr_" + std::to_string(::getpid()) + "_" +
                             std::to_string(++calls) + ".txt");
  const std::string command = std::string(HEDRA_BIN) + " " + args + " 2>" + err_file.string();
  std::FILE* pipe = ::popen(command.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  std::string err;
  if (std::FILE* f = std::fopen(err_file.c_str(), "r")) {
    while (size_t n = std::fread(buf.data(), 1, buf.size(), f)) err.append(buf.data(), n);
    std::fclose(f);
  }
  fs::remove(err_file);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out, err};
}

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("hedra_render_cli_" + std::to_string(::getpid()));
  fs::create_directories(d);
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

TEST(RenderCli, LinesOverlayOrAClearMessage) {
  const fs::path dir = temp_dir();
  const fs::path out = dir / "lines.png";
  const Result r = run("render " + kExample + " -o " + out.string() + " --width 96 --height 72 --lines");
  if (r.code == 0) {
    EXPECT_TRUE(fs::exists(out));
  } else {
    EXPECT_EQ(r.code, 3);
    EXPECT_NE(r.err.find("roberts"), std::string::npos) << r.err;
  }
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
