// `hedra clip` end to end: output format, inside/outside, methods, pieces, errors and exit codes.
#include <gtest/gtest.h>

#include "testing/cli_run.h"
#include "testing/temp_files.h"
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace {

namespace fs = std::filesystem;

using Result = hedra::testing::CliResult;

Result run(const std::string& args) { return hedra::testing::run_hedra(args); }

fs::path temp_dir(const char* name) { return hedra::testing::temp_dir(std::string("clip_cli_") + name); }

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

// A box as OFF polygons (vertices numbered from `base`), counter-clockwise from outside.
std::string box_off_body(double x0, double y0, double z0, double x1, double y1, double z1, int base,
                         std::string& faces) {
  std::ostringstream v;
  v.precision(17);
  for (int i = 0; i < 8; ++i)
    v << (i & 1 ? x1 : x0) << " " << (i & 2 ? y1 : y0) << " " << (i & 4 ? z1 : z0) << "\n";
  const int f[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                       {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : f)
    faces += "4 " + std::to_string(base + q[0]) + " " + std::to_string(base + q[1]) + " " +
             std::to_string(base + q[2]) + " " + std::to_string(base + q[3]) + "\n";
  return v.str();
}

std::string boxes_off(const std::vector<std::array<double, 6>>& boxes) {
  std::string vertices, faces;
  int base = 0;
  for (const auto& b : boxes) {
    vertices += box_off_body(b[0], b[1], b[2], b[3], b[4], b[5], base, faces);
    base += 8;
  }
  return "OFF\n" + std::to_string(base) + " " + std::to_string(6 * boxes.size()) + " 0\n" +
         vertices + faces;
}

std::vector<std::vector<double>> read_rows(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::vector<double> row;
    double v;
    while (s >> v) row.push_back(v);
    rows.push_back(row);
  }
  return rows;
}

TEST(ClipCli, ConvexBodyInsideAndOutside) {
  const fs::path dir = temp_dir("convex");
  write(dir / "cube.off", boxes_off({{0, 0, 0, 2, 2, 2}}));
  write(dir / "segs.txt",
        "# x1 y1 z1 x2 y2 z2\n"
        "-1 1 1 3 1 1\n"  // line 2: across the cube
        "\n"
        "5 5 5 6 6 6\n"                  // line 4: outside
        "0.5 0.5 0.5 1 1 1  # inside\n"  // line 5
        "-1 1 0 1 -1 0\n");              // line 6: touches the corner (0, 0, 0) only
  Result r = run("clip --body " + (dir / "cube.off").string() + " --segments " +
                 (dir / "segs.txt").string() + " -o " + (dir / "in.txt").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("3 parts of 4 segments"), std::string::npos) << r.out;
  auto rows = read_rows(dir / "in.txt");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0], (std::vector<double>{0, 1, 1, 2, 1, 1, 2}));
  EXPECT_EQ(rows[1], (std::vector<double>{0.5, 0.5, 0.5, 1, 1, 1, 5}));
  EXPECT_EQ(rows[2], (std::vector<double>{0, 0, 0, 0, 0, 0, 6}));  // a single point

  r = run("clip --outside --body " + (dir / "cube.off").string() + " --segments " +
          (dir / "segs.txt").string() + " -o " + (dir / "out.txt").string());
  ASSERT_EQ(r.code, 0) << r.err;
  rows = read_rows(dir / "out.txt");
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0], (std::vector<double>{-1, 1, 1, 0, 1, 1, 2}));
  EXPECT_EQ(rows[1], (std::vector<double>{2, 1, 1, 3, 1, 1, 2}));
  EXPECT_EQ(rows[2], (std::vector<double>{5, 5, 5, 6, 6, 6, 4}));
  EXPECT_EQ(rows[3], (std::vector<double>{-1, 1, 0, 1, -1, 0, 6}));  // touching: all outside
}

TEST(ClipCli, MidpointMethodWithinEps) {
  const fs::path dir = temp_dir("midpoint");
  write(dir / "cube.off", boxes_off({{0, 0, 0, 2, 2, 2}}));
  write(dir / "segs.txt", "-1 0.3 1.7 3 1.1 0.2\n");
  Result r =
      run("clip --method midpoint --eps 1e-6 --body " + (dir / "cube.off").string() +
          " --segments " + (dir / "segs.txt").string() + " -o " + (dir / "mid.txt").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("midpoint, eps 1e-06"), std::string::npos) << r.out;
  const auto rows = read_rows(dir / "mid.txt");
  ASSERT_EQ(rows.size(), 1u);
  // Exact: x from −1 to 3 enters at x = 0 (t = 1/4) and leaves at x = 2 (t = 3/4).
  EXPECT_NEAR(rows[0][0], 0, 1e-6);
  EXPECT_NEAR(rows[0][3], 2, 1e-6);
  EXPECT_GE(rows[0][0], 0);  // the ends found are visible points
  EXPECT_LE(rows[0][3], 2);
}

TEST(ClipCli, SeveralConvexBodiesAreThePiecesOfOneClipper) {
  const fs::path dir = temp_dir("pieces");
  // The L prism as two boxes sharing the face x = 1, 0 ≤ y ≤ 1.
  write(dir / "l.off", boxes_off({{0, 0, 0, 1, 3, 2}, {1, 0, 0, 4, 1, 2}}));
  write(dir / "segs.txt",
        "-1 0.5 1 5 0.5 1\n"       // across the shared face: one part
        "0.5 2.5 1 3.5 0.5 1\n");  // across the notch: two parts
  Result r = run("clip --body " + (dir / "l.off").string() + " --segments " +
                 (dir / "segs.txt").string() + " -o " + (dir / "in.txt").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("2 convex pieces"), std::string::npos) << r.out;
  auto rows = read_rows(dir / "in.txt");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_NEAR(rows[0][0], 0, 1e-15);
  EXPECT_NEAR(rows[0][3], 4, 1e-15);
  EXPECT_EQ(rows[0][6], 1);
  EXPECT_EQ(rows[1][6], 2);
  EXPECT_EQ(rows[2][6], 2);
  EXPECT_EQ(rows[1][0], 0.5);
  EXPECT_EQ(rows[2][3], 3.5);
  r = run("clip --outside --body " + (dir / "l.off").string() + " --segments " +
          (dir / "segs.txt").string() + " -o " + (dir / "out.txt").string());
  ASSERT_EQ(r.code, 0) << r.err;
  rows = read_rows(dir / "out.txt");
  ASSERT_EQ(rows.size(), 3u);  // two ends of line 1, the notch of line 2
  EXPECT_EQ(rows[2][6], 2);
}

TEST(ClipCli, NonConvexBodyThroughItsDecomposition) {
  // The L prism {0 ≤ x ≤ 4, 0 ≤ y ≤ 1} ∪ {0 ≤ x ≤ 1, 0 ≤ y ≤ 3}, 0 ≤ z ≤ 2, decomposed into
  // two pieces by the clipper: parts crossing the shared cut face come out whole.
  const fs::path dir = temp_dir("nonconvex");
  write(dir / "l.obj",
        "v 0 0 0\nv 4 0 0\nv 4 1 0\nv 1 1 0\nv 1 3 0\nv 0 3 0\n"
        "v 0 0 2\nv 4 0 2\nv 4 1 2\nv 1 1 2\nv 1 3 2\nv 0 3 2\n"
        "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\n"
        "f 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\nf 4 5 11 10\nf 5 6 12 11\nf 6 1 7 12\n");
  write(dir / "segs.txt",
        "-1 0.5 1 5 0.5 1\n"      // along x through both pieces: x in [0, 4]
        "0.5 -1 1 0.5 4 1\n"      // along y through both pieces: y in [0, 3]
        "2 2 1 2 2 1.5\n"         // in the notch: nothing
        "3 0.5 1 0.5 3 1\n");     // across the notch: t in [0, 0.2] and [0.8, 1]
  const fs::path out = dir / "out.txt";
  Result r = run("clip --body " + (dir / "l.obj").string() + " --segments " +
                 (dir / "segs.txt").string() + " -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::vector<std::vector<double>> rows = read_rows(out);
  const std::vector<std::vector<double>> want = {{0, 0.5, 1, 4, 0.5, 1, 1},
                                                 {0.5, 0, 1, 0.5, 3, 1, 2},
                                                 {3, 0.5, 1, 2.5, 1, 1, 4},
                                                 {1, 2.5, 1, 0.5, 3, 1, 4}};
  ASSERT_EQ(rows.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i)
    for (size_t j = 0; j < 7; ++j) EXPECT_NEAR(rows[i][j], want[i][j], 1e-12) << i << "," << j;
  r = run("clip --outside --body " + (dir / "l.obj").string() + " --segments " +
          (dir / "segs.txt").string() + " -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  rows = read_rows(out);
  // Line 1: two outer ends; line 2: two; line 3: whole; line 4: the notch part.
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[5][6], 4);
  EXPECT_NEAR(rows[5][0], 2.5, 1e-12);
  EXPECT_NEAR(rows[5][4], 2.5, 1e-12);
}

TEST(ClipCli, MalformedLinesNameTheLineAndExitWithThree) {
  const fs::path dir = temp_dir("malformed");
  write(dir / "cube.off", boxes_off({{0, 0, 0, 1, 1, 1}}));
  const fs::path out = dir / "out.txt";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"0 0 0 1 1 1\n# fine\n1 2 3 4 5\n",
       ":3: expected 6 numbers (x1 y1 z1 x2 y2 z2), got 5 fields"},
      {"0 0 0 1 1 abc\n", ":1: expected a number for z2, got 'abc'"},
      {"0 0 0 1 1 1\n\n0 0 0 1 1 1 7\n", ":3: expected 6 numbers"},
      {"0 0 0 1 1 1e300\n", ":1: z2 is beyond ±1e101"},
      {"0 0 nan 1 1 1\n", ":1: "},
  };
  for (const auto& [text, message] : cases) {
    write(dir / "segs.txt", text);
    Result r = run("clip --body " + (dir / "cube.off").string() + " --segments " +
                   (dir / "segs.txt").string() + " -o " + out.string());
    EXPECT_EQ(r.code, 3) << text;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find((dir / "segs.txt").string() + message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
  // A missing file is an I/O error: exit code 3 as well.
  Result r = run("clip --body " + (dir / "cube.off").string() + " --segments " +
                 (dir / "none.txt").string() + " -o " + out.string());
  EXPECT_EQ(r.code, 3);
}

TEST(ClipCli, UsageErrorsExitWithTwo) {
  const fs::path dir = temp_dir("usage");
  write(dir / "cube.off", boxes_off({{0, 0, 0, 1, 1, 1}}));
  write(dir / "segs.txt", "0 0 0 1 1 1\n");
  const std::string common = " --body " + (dir / "cube.off").string() + " --segments " +
                             (dir / "segs.txt").string() + " -o " + (dir / "o.txt").string();
  EXPECT_EQ(run("clip").code, 2);
  EXPECT_EQ(run("clip --segments x.txt -o y.txt").code, 2);
  EXPECT_EQ(run("clip --method fastest" + common).code, 2);
  EXPECT_EQ(run("clip --method midpoint --eps -1" + common).code, 2);
  EXPECT_EQ(run("clip" + common).code, 0);
}

// An 80 000-triangle sphere written as binary STL (float32): the rounding makes thousands of
// its face diagonals slightly reflex, so the body is exactly non-convex. `clip --body` clips it
// directly against its triangles (no decomposition, which took minutes), in about half a
// second of CPU for 1 000 segments (docs/clipping.md). Reference: the same sphere in double
// precision (OFF, exactly convex, Cyrus–Beck): the same parts per segment, ends within the
// float32 rounding, away from near-tangent segments.
TEST(ClipCli, Float32StlSphereIsClippedDirectly) {
  const fs::path dir = temp_dir("float32_sphere");
  write(dir / "s.json",
        "{\"version\": 1, \"bodies\": [{\"name\": \"s\", \"sphere\": {\"center\": [0, 0, 0], "
        "\"radius\": 1.5, \"tolerance\": 1.85e-4}}]}");
  const std::string stl = (dir / "s.stl").string(), off = (dir / "s.off").string();
  ASSERT_EQ(run("convert " + (dir / "s.json").string() + " " + stl).code, 0);
  ASSERT_EQ(run("convert " + (dir / "s.json").string() + " " + off).code, 0);
  EXPECT_EQ(fs::file_size(stl), 84u + 50u * 80088u);  // binary STL: 80 088 triangles
  // 1 000 segments from a fixed linear congruential sequence in [-2.5, 2.5]^3.
  std::ostringstream segs;
  segs.precision(17);
  std::uint64_t state = 12345;
  const auto next = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return -2.5 + 5.0 * static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  std::vector<std::array<double, 6>> segments(1000);
  for (auto& s : segments) {
    for (double& x : s) x = next();
    segs << s[0] << " " << s[1] << " " << s[2] << " " << s[3] << " " << s[4] << " " << s[5] << "\n";
  }
  write(dir / "segs.txt", segs.str());
  const std::string common = " --segments " + (dir / "segs.txt").string();
  Result r = run("clip --body " + stl + common + " -o " + (dir / "stl.txt").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("1 non-convex body (80088 triangles, not decomposed)"), std::string::npos)
      << r.out;
  r = run("clip --body " + off + common + " -o " + (dir / "off.txt").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("1 convex piece"), std::string::npos) << r.out;
  const auto direct = read_rows(dir / "stl.txt"), convex = read_rows(dir / "off.txt");
  // Parts per input line; segments passing within 1e-4 of the sphere's surface are skipped
  // (float32 rounding may decide a graze differently).
  std::vector<std::vector<std::vector<double>>> by_line_direct(1001), by_line_convex(1001);
  for (const auto& row : direct) by_line_direct[static_cast<size_t>(row[6])].push_back(row);
  for (const auto& row : convex) by_line_convex[static_cast<size_t>(row[6])].push_back(row);
  int compared = 0, crossing = 0;
  for (size_t line = 1; line <= 1000; ++line) {
    const auto& s = segments[line - 1];
    const Eigen::Vector3d a(s[0], s[1], s[2]), b(s[3], s[4], s[5]);
    const double t = std::clamp(-a.dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    const double distance = (a + t * (b - a)).norm();
    if (std::abs(distance - 1.5) < 1e-4 || std::abs(a.norm() - 1.5) < 1e-4 ||
        std::abs(b.norm() - 1.5) < 1e-4)
      continue;
    ++compared;
    ASSERT_EQ(by_line_direct[line].size(), by_line_convex[line].size()) << "line " << line;
    for (size_t k = 0; k < by_line_direct[line].size(); ++k) {
      ++crossing;
      for (int j = 0; j < 6; ++j)
        EXPECT_NEAR(by_line_direct[line][k][static_cast<size_t>(j)],
                    by_line_convex[line][k][static_cast<size_t>(j)], 1e-5)
            << "line " << line;
    }
  }
  EXPECT_GT(compared, 990);
  EXPECT_GT(crossing, 300);
  // Outside: the complement, also without decomposition.
  r = run("clip --outside --body " + stl + common + " -o " + (dir / "out.txt").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("not decomposed"), std::string::npos) << r.out;
  fs::remove_all(dir);
}

}  // namespace
