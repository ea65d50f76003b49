// The hedra command end to end: exit codes, one-line errors, output files.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "bad_files.h"

namespace {

namespace fs = std::filesystem;

struct Result {
  int code;
  std::string out;
  std::string err;
};

Result run(const std::string& args) {
  static int calls = 0;
  const fs::path err_file = fs::temp_directory_path() /
                            ("hedra_cli_stderr_" + std::to_string(::getpid()) + "_" +
                             std::to_string(++calls) + ".txt");
  std::string command = std::string(HEDRA_BIN) + " " + args + " 2>" + err_file.string();
  std::FILE* pipe = ::popen(command.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
  int status = ::pclose(pipe);
  std::string err;
  if (std::FILE* f = std::fopen(err_file.c_str(), "r")) {
    while (size_t n = std::fread(buf.data(), 1, buf.size(), f)) err.append(buf.data(), n);
    std::fclose(f);
  }
  fs::remove(err_file);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out, err};
}

fs::path temp_dir(const char* name) {
  fs::path d = fs::temp_directory_path() / (std::string("hedra_cli_") + name);
  fs::create_directories(d);
  return d;
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

TEST(Cli, BadInputExitsWithThreeAndOneLine) {
  const fs::path dir = temp_dir("bad");
  hedra::testing::write_bad_files(dir);
  for (const auto& bad : hedra::testing::bad_files()) {
    const fs::path path = dir / bad.name;
    Result r = run("info " + path.string());
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
  EXPECT_EQ(run("decompose --method nonsense " + (dir / "l.obj").string()).code, 3);
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

}  // namespace
