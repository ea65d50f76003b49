// The bad-input files of the test suite, written into a temporary directory, each paired
// with a fragment its one-line error message must contain.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace hedra::testing {

struct BadFile {
  std::string name;      // file name (format from the extension)
  std::string bytes;     // contents
  std::string expected;  // fragment of the error message
};

inline std::string cube_off_with(const std::string& vertex3, const std::string& face2 = "4 0 1 5 4") {
  return "OFF\n8 6 0\n-1 -1 -1\n1 -1 -1\n-1 1 -1\n" + vertex3 +
         "\n-1 -1 1\n1 -1 1\n-1 1 1\n1 1 1\n4 0 4 6 2\n4 1 3 7 5\n" + face2 +
         "\n4 2 6 7 3\n4 0 2 3 1\n4 4 5 7 6\n";
}

inline std::string binary_stl(std::uint32_t header_count, std::uint32_t records) {
  std::string s(84 + 50 * records, '\0');
  std::memcpy(s.data() + 80, &header_count, 4);
  for (std::uint32_t t = 0; t < records; ++t) {
    float v[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::memcpy(s.data() + 84 + 50 * t, v, 48);
  }
  return s;
}

inline std::vector<BadFile> bad_files() {
  std::string truncated = binary_stl(12, 12);
  truncated.resize(truncated.size() - 30);
  std::string open_box = cube_off_with("1 1 -1");  // the cube without its top face
  open_box.replace(open_box.find("8 6 0"), 5, "8 5 0");
  open_box.erase(open_box.rfind("4 4 5 7 6"));
  return {
      {"empty.off", "", "empty file"},
      {"empty.stl", "", "empty file"},
      {"truncated.stl", truncated, "but the file has 654: truncated file"},
      {"wrong_count.stl", binary_stl(13, 12), "header says 13 triangles, which need 734 bytes, but the file has 684; the file holds 12 whole triangles: wrong triangle count"},
      {"two_vertices.off", cube_off_with("1 1 -1", "2 0 1"), ":13: face 2 has 2 vertices"},
      {"out_of_range.off", cube_off_with("1 1 -1", "4 0 1 5 40"), "refers to vertex 40, out of range"},
      {"nan.off", cube_off_with("nan 1 -1"), ":6: x is not finite"},
      {"inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 inf\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
       ":4: z is not finite"},
      {"open.off", open_box, "not closed: 4 boundary edges"},
      {"flipped.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 3 2\n",
       "face 3 is flipped"},
      {"nonplanar.off", cube_off_with("1 1 -0.5"), "face 4 is not planar: vertex"},
      {"huge.off", cube_off_with("1e300 1 -1"), "coordinate beyond"},
      {"garbage.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1\n",
       "vertex element lacks x, y or z"},
      {"text.obj", "this is not a mesh\n", "no faces"},
      {"bad_number.off", cube_off_with("1 one -1"), ":6: expected a number for y, got 'one'"},
  };
}

/// Writes every bad file into `dir` (created if needed).
inline void write_bad_files(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  for (const BadFile& f : bad_files()) {
    std::ofstream out(dir / f.name, std::ios::binary);
    out.write(f.bytes.data(), static_cast<std::streamsize>(f.bytes.size()));
  }
}

}  // namespace hedra::testing
