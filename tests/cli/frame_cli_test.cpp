// `hlr -o` and `shadows --svg` framed as `render` frames the scene (--fit: fitted), a camera
// standing inside the scene (near-plane clipping instead of an error), and Ctrl-C: exit 130
// and no output file.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Geometry>

#include "testing/cli_run.h"
#include "testing/temp_files.h"

namespace {

namespace fs = std::filesystem;
using Result = hedra::testing::CliResult;
using Vec3 = Eigen::Vector3d;

Result run(const std::string& args) { return hedra::testing::run_hedra(args); }

fs::path temp_dir(const char* name) { return hedra::testing::temp_dir(std::string("frame_cli_") + name); }

using hedra::testing::write;

std::string read(const fs::path& path) { return hedra::testing::read_text(path); }

// The points of the path data of the visible lines: pairs of numbers after M or L.
std::vector<Eigen::Vector2d> visible_points(const std::string& svg) {
  std::vector<Eigen::Vector2d> out;
  const std::regex group("<path class=\"visible\" d=\"([^\"]*)\"");
  std::smatch m;
  if (!std::regex_search(svg, m, group)) return out;
  const std::string d = m[1];
  const std::regex point("[ML](-?[0-9.]+) (-?[0-9.]+)");
  for (auto it = std::sregex_iterator(d.begin(), d.end(), point); it != std::sregex_iterator(); ++it)
    out.emplace_back(std::stod((*it)[1]), std::stod((*it)[2]));
  return out;
}

// A cube seen in perspective from (9, −7, 6) towards (1, 1, 1), 50° vertical field of view, on a
// 320 × 200 image.
const char* kCubeScene = R"({"version": 1,
  "bodies": [{"name": "cube", "box": {"min": [0, 0, 0], "max": [2, 2, 2]}}],
  "camera": {"projection": "perspective", "eye": [9, -7, 6], "target": [1, 1, 1], "up": [0, 0, 1], "fov_deg": 50},
  "image": {"width": 320, "height": 200}})";

// The pinhole camera written out: raster point of p for that camera (y down, centre of the image
// at the optical axis, 0.5·height / tan(fov/2) pixels per unit at depth 1).
Eigen::Vector2d pinhole(const Vec3& p) {
  const Vec3 eye(9, -7, 6), f = (Vec3(1, 1, 1) - eye).normalized();
  const Vec3 right = f.cross(Vec3(0, 0, 1)).normalized(), up = right.cross(f);
  const double s = 0.5 * 200 / std::tan(25 * std::numbers::pi / 180);
  const Vec3 q = p - eye;
  return {160 + s * q.dot(right) / q.dot(f), 100 - s * q.dot(up) / q.dot(f)};
}

TEST(FrameCli, HlrDrawsWhereRenderDraws) {
  const fs::path d = temp_dir("frame");
  write(d / "cube.json", kCubeScene);
  const Result r = run("hlr " + (d / "cube.json").string() + " -o " + (d / "cube.svg").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // no progress bar when stderr is not a terminal
  const std::vector<Eigen::Vector2d> points = visible_points(read(d / "cube.svg"));
  ASSERT_FALSE(points.empty());
  // The seven corners the camera sees (all but (0, 2, 0), behind the cube) are drawn at the
  // pinhole camera's pixels, to the SVG's 0.01 px.
  int found = 0;
  for (const Vec3 corner : {Vec3(2, 0, 2), Vec3(2, 0, 0), Vec3(2, 2, 2), Vec3(0, 0, 2), Vec3(0, 2, 2), Vec3(2, 2, 0), Vec3(0, 0, 0)}) {
    const Eigen::Vector2d expected = pinhole(corner);
    bool hit = false;
    for (const Eigen::Vector2d& p : points) hit = hit || (p - expected).cwiseAbs().maxCoeff() <= 0.0051;
    EXPECT_TRUE(hit) << corner.transpose() << " expected at " << expected.transpose();
    found += hit;
  }
  EXPECT_EQ(found, 7);
  // --fit keeps the fitted framing: the drawing touches the 5 % margin of the image.
  ASSERT_EQ(run("hlr " + (d / "cube.json").string() + " --fit -o " + (d / "fit.svg").string()).code, 0);
  double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
  for (const Eigen::Vector2d& p : visible_points(read(d / "fit.svg"))) {
    xmin = std::min(xmin, p.x()), xmax = std::max(xmax, p.x());
    ymin = std::min(ymin, p.y()), ymax = std::max(ymax, p.y());
  }
  EXPECT_GE(xmin, 16 - 0.01);
  EXPECT_LE(xmax, 304 + 0.01);
  EXPECT_GE(ymin, 10 - 0.01);
  EXPECT_LE(ymax, 190 + 0.01);
  EXPECT_TRUE(std::abs(xmin - 16) < 0.02 || std::abs(ymin - 10) < 0.02);
  fs::remove_all(d);
}

// The camera stands among the bodies: beams pass beside the eye and reach behind it.
const char* kInsideScene = R"({"version": 1,
  "bodies": [
    {"name": "wall", "box": {"min": [-3, -3, -1], "max": [3, 3, 0]}},
    {"name": "beam", "box": {"min": [1.5, -0.5, -0.5], "max": [2.5, 0.5, 8]}},
    {"name": "other", "box": {"min": [-2.5, 0.2, 0.5], "max": [-1.2, 1.1, 7]}}
  ],
  "lights": [{"type": "point", "position": [0.5, 2, 6]}],
  "camera": {"projection": "perspective", "eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 90},
  "image": {"width": 200, "height": 150}})";

TEST(FrameCli, ACameraInsideTheSceneIsClippedByTheNearPlane) {
  const fs::path d = temp_dir("inside");
  write(d / "inside.json", kInsideScene);
  const std::string scene = (d / "inside.json").string();
  Result r = run("hlr " + scene + " -o " + (d / "a.svg").string() + " --json " + (d / "a.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_FALSE(visible_points(read(d / "a.svg")).empty());
  // Every drawn point lies in the image's neighbourhood: nothing from behind the eye.
  for (const Eigen::Vector2d& p : visible_points(read(d / "a.svg"))) {
    EXPECT_TRUE(std::isfinite(p.x()) && std::isfinite(p.y()));
  }
  r = run("shadows " + scene + " --svg " + (d / "s.svg").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "s.svg"));
  r = run("render " + scene + " -o " + (d / "r.png").string() + " --lines --shadows none");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "r.png"));
  fs::remove_all(d);
}

// n × n × 2 boxes, each overlapping its neighbours (junction lines everywhere), under a light.
std::string big_scene(int n) {
  std::string s = R"({"version": 1, "bodies": [)";
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < 2; ++k) {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      R"(%s{"name": "b%d_%d_%d", "box": {"min": [%g, %g, %g], "max": [%g, %g, %g]}})",
                      (i || j || k) ? ", " : "", i, j, k, 1.5 * i + 0.3 * k, 1.5 * j + 0.2 * k, 0.4 * k,
                      1.5 * i + 2.1 + 0.3 * k, 1.5 * j + 2.3 + 0.2 * k, 1.3 + 0.4 * k + 0.01 * (i + j));
        s += buf;
      }
  s += R"(], "lights": [{"type": "directional", "direction": [-1, -0.7, -2]}],
  "camera": {"projection": "parallel", "direction": [-1, -0.8, -0.9], "up": [0, 0, 1]},
  "image": {"width": 800, "height": 600}})";
  return s;
}

// Starts `hedra args` (stdout and stderr to files), sends SIGINT after `delay`, waits.
struct Stopped {
  bool exited = false;
  int code = -1;
  std::string err;
};
Stopped interrupt_after(const std::vector<std::string>& args, std::chrono::milliseconds delay,
                        const fs::path& dir) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string out = (dir / "stdout.txt").string(), err = (dir / "stderr.txt").string();
    if (!std::freopen(out.c_str(), "w", stdout) || !std::freopen(err.c_str(), "w", stderr)) ::_exit(99);
    std::vector<char*> argv{const_cast<char*>(HEDRA_BIN)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(HEDRA_BIN, argv.data());
    ::_exit(98);
  }
  std::this_thread::sleep_for(delay);
  ::kill(pid, SIGINT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  Stopped s;
  s.exited = WIFEXITED(status);
  s.code = s.exited ? WEXITSTATUS(status) : -1;
  s.err = read(dir / "stderr.txt");
  return s;
}

// Ctrl-C during the work: exit 130, one line on stderr, no output file. A run that finished
// before the signal is repeated on a larger scene; one stopped by the signal before `hedra`
// installed its handler (a very slow start) is repeated with a longer delay.
void expect_clean_interrupt(const std::string& command, const std::string& output_flag,
                            const std::string& output_name) {
  const fs::path d = temp_dir(command.c_str());
  int n = 8;
  std::chrono::milliseconds delay(300);
  for (int attempt = 0; attempt < 8; ++attempt) {
    const fs::path scene = d / "big.json", output = d / output_name;
    write(scene, big_scene(n));
    fs::remove(output);
    std::vector<std::string> args{command, scene.string(), output_flag, output.string()};
    if (command == "render") args.insert(args.end(), {"--shadows", "exact", "--aa", "16"});
    const Stopped s = interrupt_after(args, delay, d);
    if (s.exited && s.code == 0) {  // finished first: a larger scene
      n *= 2;
      continue;
    }
    if (!s.exited) {  // killed before the handler was in place
      delay *= 2;
      continue;
    }
    EXPECT_EQ(s.code, 130) << s.err;
    EXPECT_FALSE(fs::exists(output)) << output;
    EXPECT_EQ(std::count(s.err.begin(), s.err.end(), '\n'), 1) << s.err;
    EXPECT_NE(s.err.find("interrupted"), std::string::npos) << s.err;
    // Nothing else left in the directory: no temporary file either.
    for (const auto& e : fs::directory_iterator(d)) {
      const std::string name = e.path().filename().string();
      EXPECT_TRUE(name == "big.json" || name == "stdout.txt" || name == "stderr.txt") << name;
    }
    fs::remove_all(d);
    return;
  }
  fs::remove_all(d);
  FAIL() << "hedra " << command << " was never interrupted during its work";
}

TEST(FrameCli, CtrlCStopsHlrCleanly) { expect_clean_interrupt("hlr", "-o", "lines.svg"); }

TEST(FrameCli, CtrlCStopsRenderCleanly) { expect_clean_interrupt("render", "-o", "image.png"); }

}  // namespace
