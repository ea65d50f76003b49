// The hedra command end to end: exit codes, one-line errors, output files.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "testing/cli_run.h"
#include "testing/temp_files.h"
#include "testing/bad_files.h"

namespace {

namespace fs = std::filesystem;

using Result = hedra::testing::CliResult;

Result run(const std::string& args) { return hedra::testing::run_hedra(args); }

fs::path temp_dir(const char* name) {
  return hedra::testing::temp_dir(std::string("cli_") + name);
}

TEST(Cli, DemoPrintsTheInfoTable) {
  Result r = run("demo");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("ground"), std::string::npos);
  EXPECT_NE(r.out.find("pyramid"), std::string::npos);
  EXPECT_NE(r.out.find("body matrix of L"), std::string::npos);
}

TEST(Cli, InfoJsonOnAnLPrism) {
  const fs::path dir = temp_dir("info");
  {
    std::ofstream f(dir / "l.obj");
    f << "v 0 0 0\nv 4 0 0\nv 4 1 0\nv 1 1 0\nv 1 3 0\nv 0 3 0\n"
         "v 0 0 2\nv 4 0 2\nv 4 1 2\nv 1 1 2\nv 1 3 2\nv 0 3 2\n"
         "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\n"
         "f 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\nf 4 5 11 10\nf 5 6 12 11\nf 6 1 7 12\n";
  }
  Result r = run("info --json " + (dir / "l.obj").string());
  ASSERT_EQ(r.code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  const auto& b = j["bodies"][0];
  EXPECT_EQ(b["name"], "l");
  EXPECT_EQ(b["vertices"], 12);
  EXPECT_EQ(b["edges"], 18);
  EXPECT_EQ(b["faces"], 8);
  EXPECT_EQ(b["closed"], true);
  EXPECT_EQ(b["volume"], 12.0);
  EXPECT_EQ(b["area"], 40.0);
  EXPECT_EQ(b["convex"], false);
  EXPECT_EQ(b["nonconvex_faces"], nlohmann::json({4, 5}));
  EXPECT_EQ(b["matrix"].size(), 8u);
}

// `hedra info` on a scene file: every visible body (hidden Boolean operands left out), and for
// each curved one how many faces it got and why.
TEST(Cli, InfoOnASceneFileReportsEveryBodyAndItsLevelOfDetail) {
  const std::string scene = std::string(HEDRA_SOURCE_DIR) + "/examples/city-block.json";
  Result r = run("info --json " + scene);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["bodies"].size(), 11u);
  std::map<std::string, nlohmann::json> by_name;
  for (const auto& b : j["bodies"]) by_name[b["name"].get<std::string>()] = b;
  EXPECT_EQ(by_name.count("blockA"), 0u);
  EXPECT_EQ(by_name["cut"]["volume"], 6.0 * 6 * 4 - 4 * 4 * 2);
  EXPECT_EQ(by_name["s"]["faces"], 512);
  EXPECT_NE(by_name["s"]["lod"].get<std::string>().find("512 faces"), std::string::npos) << by_name["s"];
  EXPECT_NE(by_name["tower"]["lod"].get<std::string>().find("pixel_tolerance 0.5 px"), std::string::npos);
  r = run("info " + scene);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("level of detail:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  tower: "), std::string::npos) << r.out;
}

TEST(Cli, ConvertThenInfo) {
  const fs::path dir = temp_dir("convert");
  {
    std::ofstream f(dir / "cube.off");
    f << hedra::testing::cube_off_with("1 1 -1");
  }
  Result r = run("convert " + (dir / "cube.off").string() + " " + (dir / "cube.stl").string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("info --json " + (dir / "cube.stl").string());
  ASSERT_EQ(r.code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["bodies"][0]["faces"], 6);
  EXPECT_EQ(j["bodies"][0]["volume"], 8.0);
}

// The command executes itself again with glibc's huge-page tunable (cli/main.cpp,
// use_huge_pages): the second run must see the very arguments of the first, a file name with
// spaces and quotes included, and print what a run without the re-execution prints.
TEST(Cli, HugePageReexecutionKeepsTheArgumentsAndTheOutput) {
  const fs::path dir = temp_dir("huge pages");
  const fs::path file = dir / "a 'quoted' cube.off";
  {
    std::ofstream f(file);
    f << hedra::testing::cube_off_with("1 1 -1");
  }
  const std::string args = "info --json \"" + file.string() + "\"";
  const char* saved = std::getenv("GLIBC_TUNABLES");
  const std::string before = saved != nullptr ? saved : "";
  ::unsetenv("GLIBC_TUNABLES");
  const Result reexecuted = run(args);
  ::setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=0", 1);
  const Result direct = run(args);
  if (saved != nullptr) ::setenv("GLIBC_TUNABLES", before.c_str(), 1);
  else ::unsetenv("GLIBC_TUNABLES");
  ASSERT_EQ(direct.code, 0) << direct.err;
  ASSERT_EQ(reexecuted.code, 0) << reexecuted.err;
  EXPECT_EQ(reexecuted.out, direct.out);
  EXPECT_EQ(nlohmann::json::parse(reexecuted.out)["bodies"][0]["volume"], 8.0);
  EXPECT_EQ(run("info --json").code, 2);  // a usage error is still a usage error
}

TEST(Cli, BadInputExitsWithThreeAndOneLine) {
  const fs::path dir = temp_dir("bad");
  hedra::testing::write_bad_files(dir);
  for (const auto& bad : hedra::testing::bad_files()) {
    const fs::path path = dir / bad.name;
    // An open surface is a valid input of info (and of hlr, shadows, render): a solid command.
    Result r = run((bad.name == "open.off" ? "decompose " : "info ") + path.string());
    EXPECT_EQ(r.code, 3) << bad.name << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(path.string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(bad.expected), std::string::npos) << bad.name << ": " << r.err;
    // convert must not leave an output behind
    const fs::path out = dir / (bad.name + ".out.off");
    r = run("convert " + path.string() + " " + out.string());
    EXPECT_EQ(r.code, 3);
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST(Cli, DecomposeJsonAndPieceFiles) {
  const fs::path dir = temp_dir("decompose");
  {
    std::ofstream f(dir / "l.obj");
    f << "v 0 0 0\nv 4 0 0\nv 4 1 0\nv 1 1 0\nv 1 3 0\nv 0 3 0\n"
         "v 0 0 2\nv 4 0 2\nv 4 1 2\nv 1 1 2\nv 1 3 2\nv 0 3 2\n"
         "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\n"
         "f 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\nf 4 5 11 10\nf 5 6 12 11\nf 6 1 7 12\n";
  }
  fs::remove_all(dir / "pieces");
  Result r = run("decompose --json " + (dir / "l.obj").string() + " -o " + (dir / "pieces").string());
  ASSERT_EQ(r.code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["method"], "planes");
  EXPECT_EQ(j["pieces"], 2);
  EXPECT_EQ(j["input_volume"], 12.0);
  EXPECT_EQ(j["pieces_volume"], 12.0);
  EXPECT_EQ(j["all_convex"], true);
  EXPECT_TRUE(j["ms"].is_number());
  EXPECT_TRUE(fs::exists(dir / "pieces" / "piece_000.off"));
  EXPECT_TRUE(fs::exists(dir / "pieces" / "piece_001.off"));
  r = run("info --json " + (dir / "pieces" / "piece_001.off").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["bodies"][0]["convex"], true);
  EXPECT_EQ(run("decompose --method nonsense " + (dir / "l.obj").string()).code, 2);  // usage (issue 17)
#ifdef HEDRA_HAVE_TETGEN
  // TetGen's 12 tetrahedra, merged: fewer convex pieces, same volume.
  r = run("decompose --json --method tetgen --merge " + (dir / "l.obj").string());
  ASSERT_EQ(r.code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_LE(j["pieces"].get<int>(), 6);
  EXPECT_GE(j["merged"].get<int>(), 6);
  EXPECT_EQ(j["all_convex"], true);
  EXPECT_NEAR(j["pieces_volume"].get<double>(), 12.0, 1e-12);
#endif
}

TEST(Cli, UsageErrorsExitWithTwo) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("info").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("info /nonexistent/file.off").code, 3);
}

// ---- Issue 14: float32 parts, --tolerance, open surfaces -----------------------------------

// A scene with one body: `shape` (JSON of a body without its name), under `transform`.
fs::path part_scene(const fs::path& dir, const std::string& name, const std::string& bodies) {
  const fs::path path = dir / (name + ".json");
  std::ofstream(path) << "{\"version\": 1, \"bodies\": [" << bodies << "]}\n";
  return path;
}

const char* kRotation = R"("transform": [{"rotate": {"axis": [1, 2, 3], "deg": 37}}])";

std::string l_block(bool rotated) {
  return std::string(R"({"name": "L", "prism": {"polygon": [[0,0],[4,0],[4,1],[1,1],[1,3],[0,3]], "z": [0, 2]})") +
         (rotated ? std::string(", ") + kRotation : "") + "}";
}

std::string drilled_plate(bool rotated) {
  return std::string(R"({"name": "plate", "box": {"min": [-2, -2, 0], "max": [2, 2, 1]}, "hidden": true},)"
                     R"({"name": "drill", "cylinder": {"radius": 0.5, "z": [-1, 2], "tolerance": 0.01}, "hidden": true},)"
                     R"({"name": "drilled", "subtract": ["plate", "drill"])") +
         (rotated ? std::string(", ") + kRotation : "") + "}";
}

// A Boolean whose corners are not doubles (a block less a slanted prism: its edges cross the
// block's faces at 1/6 and 5/6 of their length), then turned by the body's transform: the
// exact solid is turned exactly, its faces stay exactly planar, and the pieces are the exact
// result's. A Boolean that rounds no corner (the drilled plate) is its body exactly.
TEST(Cli, BooleanResultsDecomposeFromTheirExactSolid) {
  const fs::path dir = temp_dir("exact_solid");
  const std::string slanted =
      R"({"name": "block", "box": {"min": [0, 0, 0], "max": [4, 4, 4]}, "hidden": true},)"
      R"({"name": "prism", "polyhedron": {"vertices": [[1, 1, -1], [3, 1.25, -1], [1.75, 3, -1],)"
      R"( [1.5, 1.25, 5], [3.5, 1.5, 5], [2.25, 3.25, 5]],)"
      R"( "faces": [[0, 2, 1], [3, 4, 5], [0, 1, 4, 3], [1, 2, 5, 4], [2, 0, 3, 5]]}, "hidden": true},)"
      R"({"name": "holed", "subtract": ["block", "prism"])";
  for (bool rotated : {false, true}) {
    SCOPED_TRACE(rotated ? "rotated" : "aligned");
    const std::string body = slanted + (rotated ? std::string(", ") + kRotation : "") + "}";
    Result r = run("decompose --json " + part_scene(dir, "holed", body).string());
    ASSERT_EQ(r.code, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["name"], "holed");
    EXPECT_EQ(j["from_exact_solid"], true);
    EXPECT_EQ(j["all_convex"], true);
    EXPECT_NEAR(j["pieces_volume"].get<double>(), j["input_volume"].get<double>(), 1e-9 * j["input_volume"].get<double>());
    r = run("decompose --json " + part_scene(dir, "drilled", drilled_plate(rotated)).string());
    ASSERT_EQ(r.code, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["from_exact_solid"], false);
    EXPECT_EQ(j["all_convex"], true);
  }
}

TEST(Cli, RotatedFloat32PartsRunThroughEveryCommand) {
  const fs::path dir = temp_dir("float32");
  std::ofstream(dir / "segments.txt") << "-5 -5 -5 5 5 5\n0 0 -5 0 0 5\n-5 0.1 0.3 5 0.2 0.4\n";
  for (const auto& [name, body] : {std::pair{"l", l_block(true)}, {"drilled", drilled_plate(true)}}) {
    SCOPED_TRACE(name);
    const std::string stl = (dir / (std::string(name) + ".stl")).string();
    Result r = run("convert " + part_scene(dir, name, body).string() + " " + stl);
    ASSERT_EQ(r.code, 0) << r.err;
    r = run("decompose --json " + stl);
    ASSERT_EQ(r.code, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_NEAR(j["pieces_volume"].get<double>(), j["input_volume"].get<double>(),
                1e-9 * j["input_volume"].get<double>());
    EXPECT_EQ(j["all_convex"], true);
    r = run("hlr " + stl + " -o " + (dir / "lines.svg").string());
    EXPECT_EQ(r.code, 0) << r.err;
    r = run("shadows " + stl);
    EXPECT_EQ(r.code, 0) << r.err;
    r = run("render " + stl + " -o " + (dir / "image.png").string() + " --width 64 --height 48");
    EXPECT_EQ(r.code, 0) << r.err;
    r = run("clip --body " + stl + " --segments " + (dir / "segments.txt").string() + " -o " +
            (dir / "parts.txt").string());
    EXPECT_EQ(r.code, 0) << r.err;
  }
}

std::string plate_5x5(bool rotated) {
  std::string holes;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      const int x = 1 + 2 * i, y = 1 + 2 * j;
      holes += std::string(holes.empty() ? "" : ",") + "[[" + std::to_string(x) + "," + std::to_string(y) +
               "],[" + std::to_string(x + 1) + "," + std::to_string(y) + "],[" + std::to_string(x + 1) +
               "," + std::to_string(y + 1) + "],[" + std::to_string(x) + "," + std::to_string(y + 1) + "]]";
    }
  return std::string(R"({"name": "plate", "prism": {"polygon": [[0,0],[11,0],[11,11],[0,11]], "holes": [)") +
         holes + R"(], "z": [0, 1]})" + (rotated ? std::string(", ") + kRotation : "") + "}";
}

TEST(Cli, ToleranceGivesTheAlignedTwinsPieceCount) {
  const fs::path dir = temp_dir("tolerance");
  for (const auto& [name, make] :
       {std::pair{"l", &l_block}, {"drilled", &drilled_plate}, {"plate5", &plate_5x5}}) {
    SCOPED_TRACE(name);
    int pieces[2];
    for (bool rotated : {false, true}) {
      const std::string stl = (dir / (std::string(name) + (rotated ? "_r" : "") + ".stl")).string();
      ASSERT_EQ(run("convert " + part_scene(dir, name, make(rotated)).string() + " " + stl).code, 0);
      Result r = run("decompose --json --tolerance 1e-5 " + stl);
      ASSERT_EQ(r.code, 0) << r.err;
      pieces[rotated] = nlohmann::json::parse(r.out)["pieces"].get<int>();
    }
    EXPECT_LE(std::abs(pieces[1] - pieces[0]), 0.1 * pieces[0]) << pieces[0] << " vs " << pieces[1];
    // The snapped body is valid as it is: written and read back without a tolerance.
    const std::string stl = (dir / (std::string(name) + "_r.stl")).string();
    const std::string off = (dir / (std::string(name) + "_snapped.off")).string();
    Result r = run("convert --tolerance 1e-5 " + stl + " " + off);
    ASSERT_EQ(r.code, 0) << r.err;
    r = run("info --json " + off);
    ASSERT_EQ(r.code, 0) << r.err;
    // The old names are aliases.
    EXPECT_EQ(run("info --coplanar-tol 1e-5 " + stl).code, 0);
    EXPECT_EQ(run("hlr --planarity-tol 1e-5 " + stl + " -o " + (dir / "l.svg").string()).code, 0);
  }
}

TEST(Cli, OpenSurfacesAreReportedAndRejectedBySolidCommands) {
  const fs::path dir = temp_dir("open");
  const std::string open = (dir / "cup.off").string();
  std::ofstream(dir / "segments.txt") << "0 0 -1 0 0 2\n";
  std::ofstream(open) << "OFF\n8 5 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                         "4 0 3 2 1\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  // Not a body, but hlr, shadows and render take it: the surface's report on stdout, exit 0.
  Result r = run("info --json " + open);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const nlohmann::json b = nlohmann::json::parse(r.out)["bodies"][0];
  EXPECT_EQ(b["closed"], false);
  EXPECT_EQ(b["boundary_edges"], 4);
  EXPECT_EQ(b["faces"], 5);
  EXPECT_EQ(b["area"], 5.0);
  r = run("info " + open);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("open surface"), std::string::npos);
  // A flipped face is not an open surface: no report.
  std::ofstream(dir / "flipped.off") << "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                                        "4 0 3 2 1\n4 7 6 5 4\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  r = run("info " + (dir / "flipped.off").string());
  EXPECT_EQ(r.code, 3);
  EXPECT_EQ(r.out, "");
  for (const std::string& command :
       {"decompose " + open, "clip --body " + open + " --segments " + (dir / "segments.txt").string() +
                                  " -o " + (dir / "x").string()}) {
    r = run(command);
    EXPECT_EQ(r.code, 3) << command;
    EXPECT_NE(r.err.find("cup.off"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("boundary edge"), std::string::npos) << r.err;
  }
}

}  // namespace
