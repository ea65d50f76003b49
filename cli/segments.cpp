#include "cli/segments.h"

#include <cmath>

#include "hedra/core/tolerance.h"
#include "hedra/io/text_reader.h"

namespace hedra::cli {

std::vector<Segment> parse_segments(const std::string& path, const std::string& text) {
  io::TextReader reader(path, text);
  static constexpr const char* kNames[6] = {"x1", "y1", "z1", "x2", "y2", "z2"};
  std::vector<Segment> segments;
  while (reader.next_line()) {
    const size_t fields = reader.tokens().size();
    if (fields != 6)
      reader.fail("expected 6 numbers (x1 y1 z1 x2 y2 z2), got " + std::to_string(fields) +
                  (fields == 1 ? " field" : " fields"));
    double v[6];
    for (size_t i = 0; i < 6; ++i) {
      v[i] = reader.number(i, kNames[i]);
      if (std::abs(v[i]) > kMaxAbsCoordinate)
        reader.fail(std::string(kNames[i]) + " is beyond ±1e101");
    }
    segments.push_back({Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5]), reader.line_number()});
  }
  return segments;
}

}  // namespace hedra::cli
