// Every example of issue 17's list in one place: none may end in exit 1 ("internal error",
// reserved for bugs) or a crash; each gets the exit code the docs give it (0 for valid input,
// 2 usage, 3 bad input) and, when it fails, one line on stderr. The classes have their detailed
// tests in hostile_cli_test.cpp and io/hostile_input_test.cpp (docs/stability.md, "Hostile
// input"); this table is the issue's list itself, so that no example is left without a test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "testing/cli_run.h"
#include "testing/temp_files.h"

namespace {

namespace fs = std::filesystem;
using hedra::testing::write;

struct Example {
  std::string args;  // after `hedra`
  int code;          // expected exit code
};

TEST(HostileExamples, NoExampleOfTheIssueEndsInAnInternalError) {
  const fs::path dir = hedra::testing::temp_dir("issue17_examples");
  const auto at = [&](const std::string& name) { return (dir / name).string(); };
  const std::string box = write(dir / "box.json", R"({"version": 1,
    "bodies": [{"name": "ground", "box": {"min": [-3, -3, -1], "max": [3, 3, 0]}},
               {"name": "b", "box": {"min": [0, 0, 0], "max": [1, 1, 1]}}],
    "lights": [{"type": "directional", "direction": [-1, -1, -2]}]})");
  const std::string sun = write(dir / "sun.json", R"({"version": 1,
    "bodies": [{"name": "ground", "box": {"min": [-3, -3, -1], "max": [3, 3, 0]}}],
    "lights": [{"type": "sun", "latitude": 52.52, "longitude": 13.40, "time": "2026-06-21T10:00:00Z"}]})");
  const std::string l = write(dir / "l.obj",
                              "v 0 0 0\nv 4 0 0\nv 4 1 0\nv 1 1 0\nv 1 3 0\nv 0 3 0\n"
                              "v 0 0 2\nv 4 0 2\nv 4 1 2\nv 1 1 2\nv 1 3 2\nv 0 3 2\n"
                              "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\n"
                              "f 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\nf 4 5 11 10\nf 5 6 12 11\nf 6 1 7 12\n");
  const auto shape = [&](const std::string& name, const std::string& json) {
    return write(dir / name, R"({"version": 1, "bodies": [{"name": "s", )" + json + "}]}");
  };
  std::string ply = "ply\nformat ascii 1.0\n";
  for (int i = 0; i < 60; ++i) ply += "element e" + std::to_string(i) + " 100000000\n";
  ply += "end_header\n";
  fs::create_symlink("/dev/zero", dir / "zero.off");
  fs::create_symlink("/dev/zero", dir / "zero.txt");
  fs::create_directory(dir / "adir");
  write(dir / "regular", "x");
  write(dir / "unit.off",
        "OFF\n8 6 0\n-1 -1 -1\n1 -1 -1\n-1 1 -1\n1 1 -1\n-1 -1 1\n1 -1 1\n-1 1 1\n1 1 1\n"
        "4 0 4 6 2\n4 1 3 7 5\n4 0 1 5 4\n4 2 6 7 3\n4 0 2 3 1\n4 4 5 7 6\n");
  write(dir / "tiny.off",
        "OFF\n8 6 0\n-1e-100 -1e-100 -1e-100\n1e-100 -1e-100 -1e-100\n-1e-100 1e-100 -1e-100\n"
        "1e-100 1e-100 -1e-100\n-1e-100 -1e-100 1e-100\n1e-100 -1e-100 1e-100\n"
        "-1e-100 1e-100 1e-100\n1e-100 1e-100 1e-100\n"
        "4 0 4 6 2\n4 1 3 7 5\n4 0 1 5 4\n4 2 6 7 3\n4 0 2 3 1\n4 4 5 7 6\n");
  write(dir / "long.txt", "-1e70 0 0 1e70 0 0\n");
  const std::string png = at("x.png");

  const std::vector<Example> examples = {
      // Crash: thread counts (segfault in TBB's arena set-up), -1 accepted silently.
      {"render " + box + " -o " + png + " --threads 10000000", 2},
      {"decompose " + l + " --threads 2000000000", 2},
      {"shadows " + box + " --threads -1", 2},
      // Unbounded memory or time from a tiny input.
      {"info " + shape("cyl.json", R"("cylinder": {"radius": 1, "z": [0, 1], "tolerance": 1e-12})"), 3},
      {"info " + shape("sph.json", R"("sphere": {"center": [0, 0, 0], "radius": 1, "tolerance": 2e-7})"), 3},
      {"info " + shape("pix.json", R"("sphere": {"center": [0, 0, 0], "radius": 1, "pixel_tolerance": 1e-12})"), 3},
      {"info " + shape("prism.json", R"("regular_prism": {"sides": 1000000000, "radius": 1, "z": [0, 1]})"), 3},
      {"info " + write(dir / "empty.ply", ply), 3},
      {"info " + write(dir / "huge.off", "OFF\n100000000 1 0\n0 0 0\n"), 3},
      {"info " + at("zero.off"), 3},
      {"info " + write(dir / "zero.json", R"({"version": 1, "bodies": [{"name": "z", "mesh": "zero.off"}]})"), 3},
      {"clip --body " + l + " --segments " + at("zero.txt") + " -o " + at("o.txt"), 3},
      {"render " + box + " -o " + png + " --width 65536 --height 65536", 2},
      // Silent wrong model.
      {"info " + shape("cyl300.json", R"("cylinder": {"radius": 1, "z": [0, 1], "tolerance": 1e-300})"), 3},
      {"info " + shape("cone.json", R"("cone": {"radius": 1, "z": [0, 1], "tolerance": 1e-20})"), 3},
      // Internal errors for bad input.
      {"decompose " + l + " -o " + at("regular"), 3},
      {"info --json " + write(dir / "utf8.json", "{\"version\": 1, \"bodies\": [{\"name\": \"b\xff\xfe\", "
                                                 "\"box\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1]}}]}"), 0},
      {"info --json " + write(dir / "bad\xff\xfe.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n"), 0},
      // Partial output after a failure.
      {"hlr " + box + " -o " + at("ok.svg") + " --json " + at("missing-dir/x.json"), 3},
      {"shadows " + box + " --json " + at("ok.json") + " --svg " + at("missing-dir/x.svg"), 3},
      {"convert " + shape("hidden.json", R"("box": {"min": [0, 0, 0], "max": [1, 1, 1]}, "hidden": true)") + " " + at("out.off"), 3},
      // Messages.
      {"info " + write(dir / "nl.json", R"({"version": 1, "bodies": [
         {"name": "two\nlines", "box": {"min": [1, 0, 0], "max": [0, 1, 1]}}]})"), 3},
      {"info " + write(dir / "token.off", std::string(2'000'000, 'x') + "\n"), 3},
      {"render " + box + " -o " + png + " --ambient nan", 2},
      {"decompose " + l + " --method foo", 2},
      {"frobnicate", 2},
      {"clip --body " + l + " --segments " + at("adir") + " -o " + at("o.txt"), 3},
      {"clip --body " + l + " --segments " + at("long.txt") + " -o " + at("o.txt") + " --method midpoint --eps nan", 2},
      {"info " + l + " --coplanar-tol -1", 2},
      {"shadows " + sun + " --sun-hours 04:00 20:00 60 --grid ground 5 1e-300", 2},
      // Accuracy at extremes: valid input, exit 0.
      {"clip --body " + at("unit.off") + " --segments " + at("long.txt") + " -o " + at("o.txt"), 0},
      {"info " + at("tiny.off"), 0},
  };
  ::setenv("HEDRA_MAX_INPUT_BYTES", "4000000", 1);  // /dev/zero stops at 4 MB, not 1 GiB
  for (const Example& e : examples) {
    const hedra::testing::CliResult r = hedra::testing::run_hedra(e.args);
    const std::string shown = e.args.substr(0, 160);
    EXPECT_EQ(r.code, e.code) << shown << "\n" << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << shown << "\n" << r.err;
    if (e.code != 0) {
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << shown << "\n" << r.err;
    }
  }
  ::unsetenv("HEDRA_MAX_INPUT_BYTES");
  EXPECT_FALSE(fs::exists(png));
  EXPECT_FALSE(fs::exists(dir / "ok.svg"));
  EXPECT_FALSE(fs::exists(dir / "ok.json"));
  EXPECT_FALSE(fs::exists(dir / "out.off"));
}

}  // namespace
